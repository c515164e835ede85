//! `EllipsoidRenderer`: the pipelines, the instance buffer and the recorded draw, embeddable in
//! a host's frame. It records into command buffers it is given; it never submits, never waits,
//! and never destroys what the host owns.
//!
//! # Barriers and layouts
//!
//! Everything is recorded for one queue (the `HostDevice::queue_family_index`), in the order
//! the host records the calls:
//! - [`EllipsoidRenderer::upload`] and [`EllipsoidRenderer::update`] (outside a pass): a barrier
//!   from earlier vertex/compute reads of the instance buffer to the transfer write, the copy
//!   from a staging buffer, and a barrier from the transfer write to vertex and compute shader
//!   reads.
//! - [`EllipsoidRenderer::record_prepass`] (outside a pass): a barrier from the previous draw's
//!   indirect, vertex, fragment and compute reads to its transfer and compute writes, its
//!   dispatches with compute-to-compute barriers between them, and a barrier from its compute
//!   writes to indirect-command, vertex and fragment shader reads.
//! - [`EllipsoidRenderer::record`] (inside the host's pass): binds its pipeline, descriptor set
//!   and push constants, sets viewport and scissor to the camera's image, and draws. It
//!   records no barrier and leaves the host's dynamic state other than viewport and scissor
//!   as it was; the host rebinds its own pipeline afterwards.
//!
//! The renderer never touches the host's images: their layouts and the barriers around the
//! pass (attachment writes before sampling, resolve, present) are the host's, as for any draw.
//! It reads depth with the camera's compare op and writes depth and the colour attachments of
//! its [`Target`] with no blending.

use ash::vk;
use glam::DVec3;
use gpu_allocator::vulkan::Allocator;
use gpu_allocator::MemoryLocation;

use crate::barriers;
use crate::camera::{Camera, Projection};
pub use crate::culling::Culling;
use crate::culling::{self, CullStep, Prepass, PrepassBuffers};
use crate::draw::{DrawConfig, Footprint, Geometry, Intersection, Shading};
use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result, VkCall};
use crate::frame_slots::{FrameSlots, Retired};
use crate::gpu::GpuBuffer;
use crate::icosphere::icosphere;
pub use crate::instances::InstanceFormat;
use crate::instances::{pack_relative, pack_scene};
use crate::pipeline::{create_cull_pipeline, create_pipeline, PipelineKey};
use crate::scene::Scene;
use crate::target::DeviceCaps;
pub use crate::target::{HostDevice, Pass, RendererOptions, Target, ID_FORMAT, NORMAL_FORMAT};

/// Bytes of camera push constants (`CameraPush` in the shader): the most every device allows.
const PUSH_BYTES: usize = 128;
/// Graphics stages that read the camera push constants. The culling pre-pass has a layout of
/// its own with a compute-only range: lavapipe 22.3.6 crashes dispatching with a range shared
/// between graphics and compute stages.
const PUSH_STAGES: vk::ShaderStageFlags = vk::ShaderStageFlags::from_raw(
    vk::ShaderStageFlags::VERTEX.as_raw() | vk::ShaderStageFlags::FRAGMENT.as_raw(),
);
/// Bytes of one chunk's indirect command: a `VkDrawIndirectCommand` and the total.
const INDIRECT_BYTES: u64 = 20;
/// Alignment of each chunk's slice of a buffer: a multiple of every device's
/// `minStorageBufferOffsetAlignment` (at most 256 by the specification).
const SLICE_ALIGN: u64 = 256;

/// How far the screen quad reaches beyond the exact silhouette bounds, in pixels.
const QUAD_MARGIN_PX: f32 = 0.01;

/// Blinn-Phong material after Gumhold 2003: ambient, diffuse, specular, shininess, specular
/// colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Ambient weight.
    pub ambient: f32,
    /// Diffuse weight.
    pub diffuse: f32,
    /// Specular weight.
    pub specular: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Colour of highlights.
    pub specular_color: [f32; 3],
}

impl Default for Material {
    fn default() -> Self {
        Self {
            ambient: 0.15,
            diffuse: 0.75,
            specular: 0.4,
            shininess: 40.0,
            specular_color: [1.0, 1.0, 1.0],
        }
    }
}

/// Pipeline, descriptor and instance data for drawing one scene into a host's frame.
///
/// One frame, recorded into the host's command buffer (`examples/embed` is a whole program):
///
/// ```no_run
/// use ash::vk;
/// use ellipsoid_splat::renderer::EllipsoidRenderer;
/// use ellipsoid_splat::{Camera, Scene};
/// use glam::DMat4;
///
/// /// # Safety
/// /// `cmd` is recording outside a pass; `slot`'s previous work has completed.
/// unsafe fn frame(
///     renderer: &mut EllipsoidRenderer,
///     device: &ash::Device,
///     allocator: &mut gpu_allocator::vulkan::Allocator,
///     cmd: vk::CommandBuffer,
///     slot: u32,
///     scene: Option<&Scene>,
///     (view, projection): (DMat4, DMat4),
/// ) -> ellipsoid_splat::Result<()> {
///     // The host's matrices (Vulkan clip space) and image size give the camera.
///     let camera = Camera::from_view_projection(view, projection, 1920, 1080)?;
///     unsafe {
///         renderer.begin_frame(device, allocator, slot)?;
///         if let Some(scene) = scene {
///             renderer.upload(device, allocator, cmd, scene)?; // outside the pass
///         }
///         renderer.record_prepass(device, allocator, cmd, &camera)?; // outside the pass
///         // ... the host begins its render pass (or dynamic rendering) and draws its meshes ...
///         renderer.record(device, allocator, cmd, &camera)?; // inside the pass
///         // ... the host ends its pass, submits, and waits for this slot before reusing it.
///     }
///     Ok(())
/// }
/// ```
pub struct EllipsoidRenderer {
    set_layout: vk::DescriptorSetLayout,
    pipeline_layout: vk::PipelineLayout,
    cull_layout: vk::PipelineLayout,
    /// The pool holding `descriptor_sets` alone (one per chunk): a set is never rewritten once
    /// recorded, so replacing a buffer makes a new pool and sets and retires the old pool.
    descriptor_pool: vk::DescriptorPool,
    descriptor_sets: Vec<vk::DescriptorSet>,
    /// A buffer was replaced since `descriptor_set` was written.
    descriptors_stale: bool,
    /// Every target drawn into so far; `target` indexes the current one.
    targets: Vec<Target>,
    target: usize,
    caps: DeviceCaps,
    /// The host's pipeline cache (borrowed; may be null).
    pipeline_cache: vk::PipelineCache,
    slots: FrameSlots<Retired>,
    pipelines: Vec<(PipelineKey, vk::Pipeline)>,
    instances: Option<GpuBuffer>,
    /// Icosphere vertex and index buffers by level, made on first use.
    meshes: Vec<(u32, MeshBuffers)>,
    count: u32,
    origin: DVec3,
    /// Shading parameters, applied at the next `record`.
    pub material: Material,
    /// How the next `record` draws (the shipped renderer by default).
    pub config: DrawConfig,
    /// Count shaded pixels with an atomic (needs `fragmentStoresAndAtomics`; for `bench`).
    pub count_fragments: bool,
    counter: Option<GpuBuffer>,
    /// Up to `SIZE_SAMPLE` instances (centre, largest semi-axis, pi r1 r2 of the two largest)
    /// from which `Footprint::Auto` and the pre-pass set-up estimate the mean projected area
    /// of the glyphs on screen.
    size_sample: Vec<(DVec3, f64, f64)>,
    /// Culling done by the pre-pass from the next `record_prepass` on (impostors only).
    pub culling: Culling,
    visible: Option<GpuBuffer>,
    indirect: Option<GpuBuffer>,
    cull_groups: Option<GpuBuffer>,
    occlusion_tiles: Option<GpuBuffer>,
    cull_pipelines: Vec<(CullKey, vk::Pipeline)>,
    /// Compute each impostor's set-up once in the pre-pass instead of in each of its vertices
    /// (it then runs even with no culling). Applies to the exact shading with an n-gon or
    /// axis-rectangle footprint and up to `MAX_PRESET_INSTANCES`.
    pub setup_in_prepass: bool,
    shading_records: Option<GpuBuffer>,
    footprint_records: Option<GpuBuffer>,
    /// Take the sphere path when every instance uploaded is a sphere (on by default).
    pub sphere_path: bool,
    /// Leave out the near-plane cap code when no ellipsoid reaches in front of the near plane
    /// (on by default).
    pub cap_free_path: bool,
    all_spheres: bool,
    extent: Option<(DVec3, DVec3)>,
    /// `record_prepass` recorded the pre-pass that the next `record` draws from.
    prepass_recorded: bool,
    /// How the next `upload` stores instances (full float32 by default; `Compact` saves a
    /// third of the memory at a measured accuracy cost, see `bench`).
    pub instance_format: InstanceFormat,
    uploaded_format: InstanceFormat,
    /// The unit of compact instances' semi-axes.
    radius_scale: f32,
    /// The most instances drawn with one descriptor set. The device's `maxStorageBufferRange`
    /// caps it anyway (2,796,032 instances for lavapipe's 128 MiB); larger scenes are drawn in
    /// chunks, each with its own pre-pass and draw. Rounded down to a multiple of 256.
    pub max_chunk_instances: u32,
    /// Let `Footprint::Auto` draw glyphs below `Footprint::TRIANGLE_AREA` as one triangle
    /// instead of the oriented rectangle. Off by default: faster on lavapipe (fewer vertices
    /// and primitives), but it shades 1.65 fragments per covered pixel, beyond the 1.35 that
    /// issue 4 holds the default to.
    pub small_glyph_triangles: bool,
}

/// What one culling pipeline is specialised for: projection, culling, step, the draw whose
/// set-up it computes (if it does), whether every instance is a sphere, and whether the
/// instances are compact.
type CullKey = (bool, Culling, CullStep, Option<DrawConfig>, bool, bool);

/// The largest mean projected glyph area (square pixels) for which the pre-pass sets up the
/// impostors. On lavapipe the fragment stage's record loads cost more than the flat varyings
/// they replace once glyphs cover more than a few pixels (README, `bench --skip`).
const PRESET_MAX_AREA_PX: f64 = 12.0;

/// Bytes per instance of the pre-pass's set-up records (`glsl/include/setup_records.glsl`).
const SHADING_RECORD_BYTES: u64 = 128;
const FOOTPRINT_RECORD_BYTES: u64 = 32;
/// The most instances whose set-up records fit the 128 MiB storage-buffer range that every
/// Vulkan device supports; larger scenes set up in the vertex stage.
pub const MAX_PRESET_INSTANCES: u32 = (1 << 27) / SHADING_RECORD_BYTES as u32;

/// How many instances `Footprint::Auto` looks at.
const SIZE_SAMPLE: usize = 4096;

/// Where a storage buffer of the descriptor set lives in the renderer.
type BufferSlot = fn(&mut EllipsoidRenderer) -> &mut Option<GpuBuffer>;

/// One icosphere level on the GPU.
struct MeshBuffers {
    vertices: GpuBuffer,
    indices: GpuBuffer,
    index_count: u32,
}

impl EllipsoidRenderer {
    /// A renderer for the host's device, drawing into `options.target`. Creates the
    /// descriptor-set and pipeline layouts and a few small buffers through `allocator`;
    /// pipelines are built on first use of each variant, so a scene pays only for what it
    /// draws. Errors name what the host's device or target lacks.
    ///
    /// # Safety
    /// `host`'s handles are valid and belong together (the device was created from
    /// `physical_device`, which comes from `instance`), the device has the features of
    /// [`crate::features::required_device_features`] enabled, `allocator` allocates from
    /// that device, and `options.target`'s render pass (if any) and `options.pipeline_cache`
    /// outlive the renderer.
    pub unsafe fn new(
        host: &HostDevice,
        allocator: &mut Allocator,
        options: RendererOptions,
    ) -> Result<Self> {
        let caps = host.caps()?;
        options.target.validate(&caps)?;
        let device = host.device;
        let mut renderer = Self {
            set_layout: vk::DescriptorSetLayout::null(),
            pipeline_layout: vk::PipelineLayout::null(),
            cull_layout: vk::PipelineLayout::null(),
            descriptor_pool: vk::DescriptorPool::null(),
            descriptor_sets: Vec::new(),
            max_chunk_instances: u32::MAX,
            instance_format: InstanceFormat::Full,
            uploaded_format: InstanceFormat::Full,
            radius_scale: 1.0,
            descriptors_stale: true,
            targets: vec![options.target],
            target: 0,
            caps,
            pipeline_cache: options.pipeline_cache,
            slots: FrameSlots::new(options.frames_in_flight)?,
            pipelines: Vec::new(),
            instances: None,
            count: 0,
            origin: DVec3::ZERO,
            material: Material::default(),
            meshes: Vec::new(),
            config: DrawConfig::default(),
            count_fragments: false,
            counter: None,
            size_sample: Vec::new(),
            culling: Culling::default(),
            visible: None,
            indirect: None,
            cull_groups: None,
            occlusion_tiles: None,
            cull_pipelines: Vec::new(),
            setup_in_prepass: true,
            shading_records: None,
            footprint_records: None,
            sphere_path: true,
            cap_free_path: true,
            all_spheres: false,
            extent: None,
            small_glyph_triangles: false,
            prepass_recorded: false,
        };
        // On failure, `destroy` releases whatever was created (null handles are skipped).
        match renderer
            .create_objects(device)
            .and_then(|_| renderer.create_counter(device, allocator))
            .and_then(|_| renderer.resize_cull_buffers(device, allocator, 1))
            .and_then(|_| renderer.resize_occlusion_tiles(device, allocator, 1, 1))
        {
            Ok(()) => Ok(renderer),
            Err(e) => {
                // SAFETY: nothing was recorded with the renderer's objects yet.
                unsafe { renderer.destroy(device, allocator) };
                Err(e)
            }
        }
    }

    fn create_objects(&mut self, device: &ash::Device) -> Result<()> {
        // Binding 0: instances; 1: the fragment counter of `count_fragments`; 2: instance
        // indices kept by the culling pre-pass; 3: its indirect draw command; 4: its keep
        // bits and group slots; 5: its occlusion tiles; 6 and 7: the set-up it computed for
        // the fragment and vertex stages.
        let storage = |binding: u32, stages: vk::ShaderStageFlags| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(stages)
        };
        let vertex_and_compute = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::COMPUTE;
        let bindings = [
            storage(0, vertex_and_compute),
            storage(1, vk::ShaderStageFlags::FRAGMENT),
            storage(2, vertex_and_compute),
            storage(3, vk::ShaderStageFlags::COMPUTE),
            storage(4, vk::ShaderStageFlags::COMPUTE),
            storage(5, vk::ShaderStageFlags::COMPUTE),
            storage(
                6,
                vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::FRAGMENT,
            ),
            storage(7, vertex_and_compute),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; owned by `self`, destroyed in `destroy`.
        self.set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .call("vkCreateDescriptorSetLayout")?;

        let layouts = [self.set_layout];
        let pipeline_layout = |stages: vk::ShaderStageFlags| {
            let ranges = [vk::PushConstantRange::default()
                .stage_flags(stages)
                .size(PUSH_BYTES as u32)];
            let info = vk::PipelineLayoutCreateInfo::default()
                .set_layouts(&layouts)
                .push_constant_ranges(&ranges);
            // SAFETY: as above.
            unsafe { device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")
        };
        self.pipeline_layout = pipeline_layout(PUSH_STAGES)?;
        self.cull_layout = pipeline_layout(vk::ShaderStageFlags::COMPUTE)?;
        Ok(())
    }

    /// Instances per chunk: as many as one storage-buffer binding holds (and
    /// `max_chunk_instances` allows), a multiple of 256 so every slice stays aligned.
    fn chunk_capacity(&self) -> u32 {
        let stride = self.uploaded_format.bytes() as u64;
        let by_device = self.caps.limits.max_storage_buffer_range as u64 / stride;
        let capacity = by_device.min(self.max_chunk_instances as u64) / 256 * 256;
        capacity.max(256) as u32
    }

    /// The chunks of `count` instances: (first index, count).
    fn chunks_of(&self, count: u32) -> Vec<(u32, u32)> {
        let capacity = self.chunk_capacity();
        (0..count.div_ceil(capacity))
            .map(|k| {
                let first = k * capacity;
                (first, capacity.min(count - first))
            })
            .collect()
    }

    /// Bytes of one chunk's slice of the culling-groups buffer.
    fn groups_slice(&self, count: u32) -> u64 {
        let chunk = self.chunk_capacity().min(count.max(1));
        culling::groups_bytes(chunk).next_multiple_of(SLICE_ALIGN)
    }

    /// The descriptor sets, one per chunk, pointing at the chunk's slices of the current
    /// buffers: new ones (in a pool of their own) when a buffer was replaced or the scene
    /// changed since the last were written; the old pool is retired, since command buffers
    /// recorded earlier may still use it.
    fn current_descriptor_sets(&mut self, device: &ash::Device) -> Result<Vec<vk::DescriptorSet>> {
        if !self.descriptors_stale {
            return Ok(self.descriptor_sets.clone());
        }
        let handle = |buffer: &Option<GpuBuffer>, binding: u32| {
            buffer.as_ref().map(|b| b.handle()).ok_or_else(|| {
                Error::invalid(
                    "descriptor set",
                    format!("binding {binding} has no buffer (nothing uploaded yet?)"),
                )
            })
        };
        let buffers = [
            handle(&self.instances, 0)?,
            handle(&self.counter, 1)?,
            handle(&self.visible, 2)?,
            handle(&self.indirect, 3)?,
            handle(&self.cull_groups, 4)?,
            handle(&self.occlusion_tiles, 5)?,
            handle(&self.shading_records, 6)?,
            handle(&self.footprint_records, 7)?,
        ];
        let chunks = self.chunks_of(self.count);
        let sets = chunks.len().max(1) as u32;
        let sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(buffers.len() as u32 * sets)];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(sets)
            .pool_sizes(&sizes);
        // SAFETY: valid create info; the pool is owned by `self` (destroyed through the frame
        // slots or in `destroy`).
        let pool =
            unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
        let layouts = vec![self.set_layout; sets as usize];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for exactly these sets; freed with the pool.
        let allocated = match unsafe { device.allocate_descriptor_sets(&info) } {
            Ok(sets) => sets,
            Err(result) => {
                // SAFETY: just created, unused.
                unsafe { device.destroy_descriptor_pool(pool, None) };
                return Err(Error::vulkan("vkAllocateDescriptorSets", result));
            }
        };
        let records = self.count <= MAX_PRESET_INSTANCES;
        let groups = self.groups_slice(self.count);
        for (k, &set) in allocated.iter().enumerate() {
            let (first, count) = chunks.get(k).copied().unwrap_or((0, 1));
            let (first, count) = (first as u64, count.max(1) as u64);
            let slice = |bytes_each: u64| (first * bytes_each, count * bytes_each);
            let whole = (0, vk::WHOLE_SIZE);
            let record = |bytes_each: u64| if records { slice(bytes_each) } else { whole };
            let ranges = [
                slice(self.uploaded_format.bytes() as u64),
                whole,
                slice(4),
                (k as u64 * SLICE_ALIGN, INDIRECT_BYTES),
                (k as u64 * groups, culling::groups_bytes(count as u32)),
                whole,
                record(SHADING_RECORD_BYTES),
                record(FOOTPRINT_RECORD_BYTES),
            ];
            let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
                .iter()
                .zip(ranges)
                .map(|(&buffer, (offset, range))| {
                    [vk::DescriptorBufferInfo::default()
                        .buffer(buffer)
                        .offset(offset)
                        .range(range)]
                })
                .collect();
            let writes: Vec<vk::WriteDescriptorSet> = infos
                .iter()
                .enumerate()
                .map(|(binding, info)| {
                    vk::WriteDescriptorSet::default()
                        .dst_set(set)
                        .dst_binding(binding as u32)
                        .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                        .buffer_info(info)
                })
                .collect();
            // SAFETY: the set is new (no command buffer uses it); every buffer is live and
            // each range lies inside its buffer (sized for the whole scene in `upload`).
            unsafe { device.update_descriptor_sets(&writes, &[]) };
        }
        if self.descriptor_pool != vk::DescriptorPool::null() {
            self.slots
                .retire(Retired::DescriptorPool(self.descriptor_pool));
        }
        self.descriptor_pool = pool;
        self.descriptor_sets = allocated;
        self.descriptors_stale = false;
        Ok(self.descriptor_sets.clone())
    }

    /// The fragment counter buffer, bound at binding 1.
    fn create_counter(&mut self, device: &ash::Device, allocator: &mut Allocator) -> Result<()> {
        let buffer = GpuBuffer::new(
            device,
            allocator,
            "fragment counter",
            4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuToCpu,
        )?;
        self.counter = Some(buffer);
        self.descriptors_stale = true;
        Ok(())
    }

    /// Makes the culling buffers hold `count` instances (bindings 2, 3 and 4); they always
    /// exist, so every binding the shaders declare is valid.
    fn resize_cull_buffers(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        count: usize,
    ) -> Result<()> {
        // Set-up records only for scenes that can use them.
        let records = if count as u64 <= MAX_PRESET_INSTANCES as u64 {
            count.max(1) as u64
        } else {
            1
        };
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let indirect = storage | vk::BufferUsageFlags::INDIRECT_BUFFER;
        let chunks = self.chunks_of(count as u32).len().max(1) as u64;
        let groups = chunks * self.groups_slice(count as u32);
        let buffers: [(BufferSlot, &'static str, u64, vk::BufferUsageFlags); 5] = [
            (
                |r| &mut r.visible,
                "visible instances",
                4 * count.max(1) as u64,
                storage,
            ),
            (
                |r| &mut r.indirect,
                "culled draw",
                chunks * SLICE_ALIGN,
                indirect | vk::BufferUsageFlags::TRANSFER_DST,
            ),
            (|r| &mut r.cull_groups, "culling groups", groups, storage),
            (
                |r| &mut r.shading_records,
                "shading set-up",
                records * SHADING_RECORD_BYTES,
                storage,
            ),
            (
                |r| &mut r.footprint_records,
                "footprint set-up",
                records * FOOTPRINT_RECORD_BYTES,
                storage,
            ),
        ];
        for (slot, name, bytes, usage) in buffers {
            self.storage_at_least(device, allocator, slot, name, bytes, usage)?;
        }
        Ok(())
    }

    /// Makes the occlusion tiles (binding 5) cover a `width` x `height` image.
    fn resize_occlusion_tiles(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        width: u32,
        height: u32,
    ) -> Result<()> {
        self.storage_at_least(
            device,
            allocator,
            |r| &mut r.occlusion_tiles,
            "occlusion tiles",
            culling::tiles_bytes(width, height),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        )
    }

    /// Makes the GPU-only buffer in `slot` hold at least `bytes`: a smaller one is replaced
    /// and retired until no recorded frame can use it.
    fn storage_at_least(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        slot: BufferSlot,
        name: &'static str,
        bytes: u64,
        usage: vk::BufferUsageFlags,
    ) -> Result<()> {
        if let Some(buffer) = slot(self).take() {
            if buffer.size() >= bytes {
                *slot(self) = Some(buffer);
                return Ok(());
            }
            self.slots.retire(Retired::Buffer(buffer));
        }
        let buffer = GpuBuffer::new(
            device,
            allocator,
            name,
            bytes,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        *slot(self) = Some(buffer);
        self.descriptors_stale = true;
        Ok(())
    }

    /// Whether the pre-pass computes the set-up of a draw with `config` and `camera` (see
    /// `setup_in_prepass`): only for glyphs of a few pixels, where vertex work dominates.
    fn presets(&self, config: &DrawConfig, camera: &Camera) -> bool {
        self.setup_in_prepass
            && self
                .mean_projected_area(camera)
                .is_some_and(|area| area <= PRESET_MAX_AREA_PX)
            && config.geometry == Geometry::Impostor
            && matches!(config.shading, Shading::Exact | Shading::FastNormal)
            && config.intersection == Intersection::Stable
            && config.footprint != Footprint::WorldQuad
            && self.count > 0
            && self.count <= MAX_PRESET_INSTANCES
    }

    /// Whether the shaders take the sphere path.
    fn spheres(&self) -> bool {
        self.sphere_path && self.all_spheres
    }

    /// Whether the fragment stage can leave out the cap code with `camera`: the box holding
    /// every ellipsoid lies wholly beyond the near plane (view depth is linear, so its
    /// nearest point is a corner).
    fn cap_free(&self, camera: &Camera) -> bool {
        let Some((lo, hi)) = self.extent.filter(|_| self.cap_free_path) else {
            return false;
        };
        let corners: Vec<DVec3> = (0..8)
            .map(|k| {
                DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                )
            })
            .collect();
        // The shaders decide "reaches the near plane" in float32 from positions relative to
        // the scene origin: keep clear of the plane by many times that rounding.
        let reach = corners
            .iter()
            .map(|c| (*c - camera.eye).length())
            .fold(0.0, f64::max);
        let margin = 1e-5 * (reach + (camera.eye - self.origin).length() + camera.near);
        corners
            .iter()
            .all(|&c| camera.view_depth(c) > camera.near + margin)
    }

    /// The scene-chosen shader variants a draw with `camera` uses: (sphere path, cap-free).
    pub fn shader_variants(&self, camera: &Camera) -> (bool, bool) {
        (self.spheres(), self.cap_free(camera))
    }

    /// Whether a draw with `camera` takes its impostors' set-up from the pre-pass.
    pub fn sets_up_in_prepass(&self, camera: &Camera) -> bool {
        self.presets(&self.effective_config(camera), camera)
    }

    /// The current target.
    fn target(&self) -> &Target {
        &self.targets[self.target]
    }

    /// The culling the pre-pass does: `culling`, without occlusion unless depth is float32
    /// (its 1e-4 depth gap must survive the depth buffer's rounding). Pixel-centre and
    /// occlusion culling reason about pixel centres, so multisampled targets (whose samples
    /// lie elsewhere) keep frustum culling only.
    fn active_culling(&self) -> Culling {
        let single = !self.target().multisampled();
        Culling {
            occlusion: self.culling.occlusion
                && single
                && self.target().depth_format() == vk::Format::D32_SFLOAT,
            pixel_centres: self.culling.pixel_centres && single,
            ..self.culling
        }
    }

    /// Whether a draw with `config` and `camera` goes through the pre-pass: to cull, or to
    /// set up. Only the exact impostor: the textbook baseline's coverage and depth errors and
    /// `flat-fill`'s whole polygons are not what the culling proofs assume.
    fn runs_prepass(&self, config: &DrawConfig, camera: &Camera) -> bool {
        config.geometry == Geometry::Impostor
            && config.intersection == Intersection::Stable
            && config.shading != Shading::FlatFill
            && self.count > 0
            && (self.active_culling().any() || self.presets(config, camera))
    }

    /// One step's culling compute pipeline, built on first use.
    fn cull_pipeline(
        &mut self,
        device: &ash::Device,
        orthographic: bool,
        step: CullStep,
        setup: Option<DrawConfig>,
    ) -> Result<vk::Pipeline> {
        let spheres = self.spheres();
        let active = self.active_culling();
        let compact = self.uploaded_format == InstanceFormat::Compact;
        let key = (orthographic, active, step, setup, spheres, compact);
        if let Some((_, p)) = self.cull_pipelines.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let pipeline = create_cull_pipeline(
            device,
            self.pipeline_cache,
            self.cull_layout,
            orthographic,
            active,
            step,
            setup,
            spheres,
            compact,
        )?;
        self.cull_pipelines.push((key, pipeline));
        Ok(pipeline)
    }

    /// Records the culling pre-pass (when `culling` is on and the geometry is an impostor)
    /// into `cmd`, outside any rendering pass, with the barriers that order it after the
    /// previous frame's draw and before this draw's indirect and vertex reads. Call it before
    /// the pass that `record` draws into.
    ///
    /// It writes the indirect command with `vkCmdUpdateBuffer`, clears the occlusion tiles
    /// with `vkCmdFillBuffer`, then runs the steps of `glsl/cull.comp`, each after a
    /// compute-to-compute barrier. When the image grew since the last frame the tiles buffer
    /// is replaced (the old one retired).
    ///
    /// # Safety
    /// `device` is the renderer's device, `cmd` a command buffer of it in the recording state
    /// outside any pass, for the queue family the renderer was made for, and submitted before
    /// the slot that is current (`begin_frame`) begins again.
    pub unsafe fn record_prepass(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        camera.validate()?;
        let config = self.effective_config(camera);
        if !self.runs_prepass(&config, camera) {
            return Ok(());
        }
        self.prepare(device, allocator, camera)?;
        let active = self.active_culling();
        if active.occlusion {
            self.resize_occlusion_tiles(device, allocator, camera.width, camera.height)?;
        }
        let orthographic = matches!(camera.projection, Projection::Orthographic { .. });
        let setup = self.presets(&config, camera).then_some(config);
        let steps = culling::steps(active)
            .into_iter()
            .map(|step| Ok((step, self.cull_pipeline(device, orthographic, step, setup)?)))
            .collect::<Result<Vec<_>>>()?;
        let vertices = config.footprint.vertices();
        let buffers = match (self.indirect.as_ref(), self.occlusion_tiles.as_ref()) {
            (Some(i), Some(t)) => PrepassBuffers {
                indirect: i.handle(),
                tiles: t.handle(),
            },
            _ => return Err(Error::invalid("culling", "buffers missing")),
        };
        let sets = self.current_descriptor_sets(device)?;
        // Each chunk culls its own instances into its own indirect command; the occlusion
        // tiles are cleared once and shared, so later chunks also see earlier occluders.
        for (k, ((first, count), set)) in
            self.chunks_of(self.count).into_iter().zip(sets).enumerate()
        {
            let command: Vec<u8> = [vertices, 0, 0, 0, count]
                .iter()
                .flat_map(|v| v.to_ne_bytes())
                .collect();
            let prepass = Prepass {
                layout: self.cull_layout,
                descriptor_set: set,
                push: self.push_constants(camera, first),
                command,
                indirect_offset: k as u64 * SLICE_ALIGN,
                steps: steps.clone(),
                groups: culling::dispatch_grid(culling::group_count(count)),
                clear_tiles: active.occlusion && k == 0,
                buffers: PrepassBuffers { ..buffers },
            };
            // SAFETY: `cmd` is recording outside a pass (caller contract); every handle is
            // owned by `self` and lives until the submission completes.
            unsafe { prepass.record(device, cmd) };
        }
        self.prepass_recorded = true;
        Ok(())
    }

    /// Zeroes the fragment counter; call before submitting a counting frame.
    pub fn reset_fragment_counter(&mut self) -> Result<()> {
        match self.counter.as_mut() {
            Some(c) => c.write(&0u32.to_ne_bytes()),
            None => Ok(()),
        }
    }

    /// Pixels shaded by the last counting frame (after its fence, and after the barrier of
    /// [`EllipsoidRenderer::record_counter_barrier`]).
    pub fn fragment_count(&self) -> Option<u32> {
        let bytes = self.counter.as_ref()?.mapped()?;
        Some(u32::from_ne_bytes(bytes.get(..4)?.try_into().ok()?))
    }

    /// Makes the counter's atomic writes visible to the host; record after the pass.
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` recording outside a pass.
    pub unsafe fn record_counter_barrier(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        if self.counter.is_some() {
            // SAFETY: caller contract.
            unsafe { barriers::COUNTER_TO_HOST.record(device, cmd) };
        }
    }

    /// The pipeline for `key`, built now if this is its first use.
    fn pipeline(&mut self, device: &ash::Device, key: PipelineKey) -> Result<vk::Pipeline> {
        if let Some((_, p)) = self.pipelines.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let pipeline = create_pipeline(
            device,
            self.pipeline_cache,
            self.pipeline_layout,
            &self.targets[key.target],
            key,
        )?;
        self.pipelines.push((key, pipeline));
        Ok(pipeline)
    }

    /// Uploads icosphere `level` if it is not on the GPU yet.
    fn ensure_mesh(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        level: u32,
    ) -> Result<()> {
        if level > 4 {
            return Err(Error::invalid(
                "mesh level",
                format!("{level} is outside 0..=4"),
            ));
        }
        if self.meshes.iter().any(|(l, _)| *l == level) {
            return Ok(());
        }
        let mesh = icosphere(level);
        let vertex_bytes: Vec<u8> = mesh
            .positions
            .iter()
            .flatten()
            .flat_map(|v| v.to_ne_bytes())
            .collect();
        let index_bytes: Vec<u8> = mesh.indices.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let mut vertices = GpuBuffer::new(
            device,
            allocator,
            "icosphere vertices",
            vertex_bytes.len() as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mut indices = match GpuBuffer::new(
            device,
            allocator,
            "icosphere indices",
            index_bytes.len() as u64,
            vk::BufferUsageFlags::INDEX_BUFFER,
            MemoryLocation::CpuToGpu,
        ) {
            Ok(b) => b,
            Err(e) => {
                vertices.destroy(device, allocator);
                return Err(e);
            }
        };
        if let Err(e) = vertices
            .write(&vertex_bytes)
            .and_then(|_| indices.write(&index_bytes))
        {
            vertices.destroy(device, allocator);
            indices.destroy(device, allocator);
            return Err(e);
        }
        self.meshes.push((
            level,
            MeshBuffers {
                vertices,
                indices,
                index_count: mesh.indices.len() as u32,
            },
        ));
        Ok(())
    }

    /// The configuration a draw with `camera` uses: `config` with `Footprint::Auto` resolved
    /// from the sampled glyphs' mean projected area.
    pub fn effective_config(&self, camera: &Camera) -> DrawConfig {
        let mut config = self.config;
        if config.footprint == Footprint::Auto {
            let area = self.mean_projected_area(camera).unwrap_or(0.0);
            config.footprint = match Footprint::for_area(area) {
                Footprint::Triangle if !self.small_glyph_triangles => Footprint::OrientedRect,
                chosen => chosen,
            };
        }
        config
    }

    /// Mean projected area in square pixels of the sampled glyphs on screen beyond the near
    /// plane; `None` when no sampled glyph is on screen.
    fn mean_projected_area(&self, camera: &Camera) -> Option<f64> {
        let (sx, sy) = camera.ndc_scale();
        let pixels_per_unit = camera.height as f64 / (2.0 * sy);
        let screen = camera.width as f64 * camera.height as f64;
        let basis = camera.basis();
        let (mut sum, mut n) = (0.0, 0usize);
        for &(center, radius, area) in &self.size_sample {
            let depth = camera.view_depth(center);
            if depth <= camera.near {
                continue;
            }
            // Only glyphs that reach the screen (bounding sphere against the view rectangle,
            // widened by the radius), each counted for at most the whole screen.
            let offset = center - camera.eye;
            let (x, y) = (offset.dot(basis.right), offset.dot(basis.up));
            let (scale, half_x, half_y) = match camera.projection {
                Projection::Perspective { .. } => (pixels_per_unit / depth, sx * depth, sy * depth),
                Projection::Orthographic { .. } => (pixels_per_unit, sx, sy),
            };
            if x.abs() > half_x + radius * 1.5 || y.abs() > half_y + radius * 1.5 {
                continue;
            }
            sum += (area * scale * scale).min(screen);
            n += 1;
        }
        (n > 0).then(|| sum / n as f64)
    }

    /// Creates what `config` needs with `camera` (pipeline, mesh buffers) ahead of `record`, so
    /// recording itself allocates nothing. `record` calls it too.
    pub fn prepare(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        camera: &Camera,
    ) -> Result<()> {
        let orthographic = matches!(camera.projection, Projection::Orthographic { .. });
        let config = self.effective_config(camera);
        if orthographic && config.geometry != Geometry::Impostor {
            return Err(Error::invalid(
                "draw configuration",
                format!("{:?} supports perspective cameras only", config.geometry),
            ));
        }
        if let Geometry::Mesh(level) = config.geometry {
            self.ensure_mesh(device, allocator, level)?;
        }
        self.pipeline(device, self.pipeline_key(camera))?;
        Ok(())
    }

    /// What the pipeline of a draw with `camera` is specialised for.
    fn pipeline_key(&self, camera: &Camera) -> PipelineKey {
        let config = self.effective_config(camera);
        PipelineKey {
            orthographic: camera.is_orthographic(),
            config,
            target: self.target,
            reversed_z: camera.depth.reversed,
            count_fragments: self.count_fragments,
            culled: self.runs_prepass(&config, camera),
            preset: self.presets(&config, camera),
            spheres: self.spheres(),
            compact: self.uploaded_format == InstanceFormat::Compact,
            no_caps: self.cap_free(camera),
        }
    }

    /// Replaces the instance data with `scene`, recording the copy into `cmd`. Positions are
    /// stored relative to a scene origin chosen at the centre of the data's bounds, so float32
    /// keeps its precision where the data is, however far that is from the world origin.
    ///
    /// The bytes go to a staging buffer now; `cmd` gets a barrier ordering earlier reads of
    /// the instance buffer before the copy, the copy, and a barrier ordering it before vertex
    /// and compute shader reads. Buffers that are replaced are retired, not destroyed.
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::record_prepass`]: `cmd` is recording outside any pass and
    /// is submitted before, or is, the command buffer that draws this scene.
    pub unsafe fn upload(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        scene: &Scene,
    ) -> Result<()> {
        let packed = pack_scene(scene, self.instance_format)?;
        // Until the new scene is recorded, none is drawn (so a failed upload draws nothing).
        self.count = 0;
        self.uploaded_format = packed.format;
        self.descriptors_stale = true; // the chunks and slices change
        let step = scene.len().div_ceil(SIZE_SAMPLE).max(1);
        let size_sample = scene
            .ellipsoids
            .iter()
            .step_by(step)
            .map(|e| {
                let mut r = e.radii.to_array();
                r.sort_by(|a, b| b.total_cmp(a));
                (e.center, r[0], std::f64::consts::PI * r[0] * r[1])
            })
            .collect();
        let count = packed.len() as u32;
        self.resize_cull_buffers(device, allocator, count as usize)?;
        self.storage_at_least(
            device,
            allocator,
            |r| &mut r.instances,
            "ellipsoid instances",
            packed.bytes.len().max(1) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_copy(device, allocator, cmd, 0, &packed.bytes)? };
        self.origin = packed.origin;
        self.all_spheres = packed.all_spheres;
        self.extent = packed.extent;
        self.size_sample = size_sample;
        self.radius_scale = packed.radius_scale;
        self.count = count;
        Ok(())
    }

    /// Replaces instances `first..first + ellipsoids.len()` of the uploaded scene, recording
    /// the copy into `cmd` with the barriers of [`EllipsoidRenderer::upload`]. They keep the
    /// scene's origin, so they should lie near the uploaded data for full precision. The
    /// sphere path stays only if they are all spheres; the sample that picks the footprint is
    /// not updated.
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    pub unsafe fn update(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        first: u32,
        ellipsoids: &[Ellipsoid],
    ) -> Result<()> {
        let end = first as u64 + ellipsoids.len() as u64;
        if end > self.count as u64 {
            return Err(Error::invalid(
                "update",
                format!("instances {first}..{end} but {} are uploaded", self.count),
            ));
        }
        if ellipsoids.is_empty() {
            return Ok(());
        }
        let format = self.uploaded_format;
        let packed = pack_relative(
            ellipsoids,
            self.origin,
            first as usize,
            format,
            self.radius_scale,
        )?;
        let offset = first as u64 * format.bytes() as u64;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_copy(device, allocator, cmd, offset, &packed.bytes)? };
        self.all_spheres &= packed.all_spheres;
        if let (Some((lo, hi)), Some((new_lo, new_hi))) = (self.extent, packed.extent) {
            self.extent = Some((lo.min(new_lo), hi.max(new_hi)));
        }
        Ok(())
    }

    /// Stages `bytes` and records their copy to `offset` of the instance buffer, between the
    /// barriers [`barriers::INSTANCES_BEFORE_COPY`] and [`barriers::INSTANCES_AFTER_COPY`].
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    unsafe fn record_copy(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        offset: u64,
        bytes: &[u8],
    ) -> Result<()> {
        let Some(instances) = self.instances.as_ref().map(|b| b.handle()) else {
            return Err(Error::invalid("upload", "no instance buffer"));
        };
        if bytes.is_empty() {
            return Ok(());
        }
        let mut staging = GpuBuffer::new(
            device,
            allocator,
            "instance staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        if let Err(e) = staging.write(bytes) {
            staging.destroy(device, allocator);
            return Err(e);
        }
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: offset,
            size: bytes.len() as u64,
        };
        // SAFETY: `cmd` is recording outside a pass (caller contract); both buffers are live
        // and the region lies inside them; the staging buffer is retired below, so it lives
        // until the copy has executed.
        unsafe {
            barriers::INSTANCES_BEFORE_COPY.record(device, cmd);
            device.cmd_copy_buffer(cmd, staging.handle(), instances, &[region]);
            barriers::INSTANCES_AFTER_COPY.record(device, cmd);
        }
        self.slots.retire(Retired::Buffer(staging));
        Ok(())
    }

    /// Starts frame slot `slot` (in `0..frames_in_flight`): destroys the buffers and
    /// descriptor sets replaced while frames that might still read them were recorded. Call
    /// it once per frame, before recording anything else of the frame.
    ///
    /// # Safety
    /// Every command buffer recorded with this renderer since `slot` last began has finished
    /// executing (the host waited for that slot's fence).
    pub unsafe fn begin_frame(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        slot: u32,
    ) -> Result<()> {
        for object in self.slots.begin(slot)? {
            object.destroy(device, allocator);
        }
        Ok(())
    }

    /// Draws into `target` from the next `record` on (pipelines for earlier targets are
    /// kept, so switching back costs nothing). Errors say what the device or the description
    /// lacks.
    pub fn set_target(&mut self, target: Target) -> Result<()> {
        if let Some(k) = self.targets.iter().position(|t| *t == target) {
            self.target = k;
            return Ok(());
        }
        target.validate(&self.caps)?;
        self.targets.push(target);
        self.target = self.targets.len() - 1;
        Ok(())
    }

    /// The target the next `record` draws into.
    pub fn current_target(&self) -> &Target {
        self.target()
    }

    /// Bytes of GPU memory the scene's buffers take (instances, culling and set-up buffers,
    /// occlusion tiles; not the icosphere meshes of the `mesh-L*` baselines).
    pub fn gpu_memory_bytes(&self) -> u64 {
        [
            &self.instances,
            &self.counter,
            &self.visible,
            &self.indirect,
            &self.cull_groups,
            &self.occlusion_tiles,
            &self.shading_records,
            &self.footprint_records,
        ]
        .iter()
        .filter_map(|b| b.as_ref().map(GpuBuffer::size))
        .sum()
    }

    /// Number of instances uploaded.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The scene origin that instance positions are stored relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Records the draw into `cmd`, inside the host's pass. Sets viewport and scissor to the
    /// camera's whole image. Records nothing if the scene is empty. A draw through the
    /// pre-pass needs `record_prepass` first, before the pass (an error otherwise).
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` recording inside a pass compatible with the
    /// current [`Target`] (same attachments, formats and sample count; for a render pass,
    /// its subpass), whose attachments are the camera's image size; it is submitted as
    /// [`EllipsoidRenderer::record_prepass`] requires.
    pub unsafe fn record(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        camera.validate()?;
        if self.count == 0 {
            return Ok(());
        }
        self.prepare(device, allocator, camera)?;
        let config = self.effective_config(camera);
        // The indirect draw needs this frame's pre-pass, recorded with the same state.
        let prepass_recorded = std::mem::take(&mut self.prepass_recorded);
        if self.runs_prepass(&config, camera) && !prepass_recorded {
            return Err(Error::invalid(
                "record",
                "this draw goes through the culling pre-pass: call record_prepass first",
            ));
        }
        let key = self.pipeline_key(camera);
        let pipeline = self.pipeline(device, key)?;
        let sets = self.current_descriptor_sets(device)?;
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: camera.width as f32,
            height: camera.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: vk::Extent2D {
                width: camera.width,
                height: camera.height,
            },
        };
        // SAFETY: `cmd` is recording inside a compatible rendering pass (caller contract); every
        // bound object is owned by `self` and outlives the command buffer's execution.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[scissor]);
            if let Geometry::Mesh(level) = config.geometry {
                let (_, mesh) = self
                    .meshes
                    .iter()
                    .find(|(l, _)| *l == level)
                    .expect("prepare uploaded the mesh");
                device.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.handle()], &[0]);
                device.cmd_bind_index_buffer(cmd, mesh.indices.handle(), 0, vk::IndexType::UINT32);
            }
            // One draw per chunk, in instance order (so depth ties resolve as in one draw).
            for (k, ((first, count), set)) in
                self.chunks_of(self.count).into_iter().zip(sets).enumerate()
            {
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.pipeline_layout,
                    0,
                    &[set],
                    &[],
                );
                let push = self.push_constants(camera, first);
                device.cmd_push_constants(cmd, self.pipeline_layout, PUSH_STAGES, 0, &push);
                match config.geometry {
                    Geometry::Impostor => match (key.culled, self.indirect.as_ref()) {
                        (true, Some(indirect)) => {
                            let offset = k as u64 * SLICE_ALIGN;
                            device.cmd_draw_indirect(cmd, indirect.handle(), offset, 1, 16)
                        }
                        _ => device.cmd_draw(cmd, config.footprint.vertices(), count, 0, 0),
                    },
                    Geometry::BoxProxy => device.cmd_draw(cmd, 36, count, 0, 0),
                    Geometry::Mesh(_) => {
                        let indices = self
                            .meshes
                            .iter()
                            .find(|(l, _)| Geometry::Mesh(*l) == config.geometry)
                            .map_or(0, |(_, m)| m.index_count);
                        device.cmd_draw_indexed(cmd, indices, count, 0, 0, 0)
                    }
                }
            }
        }
        Ok(())
    }

    /// The camera push constants, relative to the scene origin, for the chunk whose first
    /// instance is `first`.
    fn push_constants(&self, camera: &Camera, first: u32) -> Vec<u8> {
        let b = camera.basis();
        let (sx, sy) = camera.ndc_scale();
        // The eye in view axes, relative to the scene origin, in float64 then rounded once.
        let rel = camera.eye - self.origin;
        let eye = glam::DVec3::new(rel.dot(b.right), rel.dot(b.up), rel.dot(b.forward)).as_vec3();
        let m = &self.material;
        let depth = camera.depth_map();
        let values: [f32; 28] = [
            eye.x,
            eye.y,
            eye.z,
            camera.near as f32,
            b.right.x as f32,
            b.right.y as f32,
            b.right.z as f32,
            sx as f32,
            b.up.x as f32,
            b.up.y as f32,
            b.up.z as f32,
            sy as f32,
            b.forward.x as f32,
            b.forward.y as f32,
            b.forward.z as f32,
            depth.a as f32,
            2.0 / camera.width as f32,
            2.0 / camera.height as f32,
            QUAD_MARGIN_PX,
            depth.b as f32,
            m.ambient,
            m.diffuse,
            m.specular,
            m.shininess,
            m.specular_color[0],
            m.specular_color[1],
            m.specular_color[2],
            depth.c as f32,
        ];
        let chunk = [first, self.radius_scale.to_bits(), 0, 0];
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.to_ne_bytes())
            .chain(chunk.iter().flat_map(|v| v.to_ne_bytes()))
            .collect();
        debug_assert_eq!(bytes.len(), PUSH_BYTES);
        bytes
    }

    /// Destroys everything the renderer created (nothing of the host's).
    ///
    /// # Safety
    /// No command buffer recorded with the renderer is pending or will be submitted again.
    pub unsafe fn destroy(mut self, device: &ash::Device, allocator: &mut Allocator) {
        for object in self.slots.drain() {
            object.destroy(device, allocator);
        }
        if let Some(buffer) = self.instances.take() {
            buffer.destroy(device, allocator);
        }
        for buffer in [
            self.counter.take(),
            self.visible.take(),
            self.indirect.take(),
            self.cull_groups.take(),
            self.occlusion_tiles.take(),
            self.shading_records.take(),
            self.footprint_records.take(),
        ]
        .into_iter()
        .flatten()
        {
            buffer.destroy(device, allocator);
        }
        for (_, mesh) in self.meshes.drain(..) {
            mesh.vertices.destroy(device, allocator);
            mesh.indices.destroy(device, allocator);
        }
        // SAFETY: all handles were created by `self` from `device` (or are null, which Vulkan
        // ignores); the caller guarantees no pending work uses them.
        unsafe {
            for (_, pipeline) in self.pipelines.drain(..) {
                device.destroy_pipeline(pipeline, None);
            }
            for (_, pipeline) in self.cull_pipelines.drain(..) {
                device.destroy_pipeline(pipeline, None);
            }
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_pipeline_layout(self.pipeline_layout, None);
            device.destroy_pipeline_layout(self.cull_layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}
