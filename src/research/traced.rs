//! The traced path (method `impostor-traced`, research): a bounding-volume hierarchy of the
//! glyphs' boxes, built on the GPU from the uploaded instances (`traced_boxes.comp`, then a
//! bottom-level acceleration structure of procedural boxes and a top-level one of one
//! instance), and a pass with one invocation per pixel that walks it with ray queries
//! (`traced.comp`) in place of the compute splat; the resolve shades what it kept. Needs
//! `DeviceFeatures::ray_query` (Mesa 25's lavapipe has it, Mesa 22's not).

use ash::khr::acceleration_structure;
use ash::vk;

use crate::allocator::{MemoryAllocator, MemoryUse};
use crate::barriers;
use crate::error::{Error, Result, VkCall};
use crate::gpu::shaders::spirv;
use crate::gpu::GpuBuffer;
use crate::gpu_layout::PushConstants;
use crate::renderer::pipelines::create_compute_pipeline;
use crate::renderer::pipelines::keys::SplatKey;
use crate::renderer::prepass::TracedDispatch;
use crate::renderer::{EllipsoidRenderer, FramePlan};
use crate::target::HostDevice;

/// The boxes shader.
const TRACED_BOXES_COMP: &[u8] = spirv!("traced_boxes.comp.spv");
/// The per-pixel traversal.
const TRACED_COMP: &[u8] = spirv!("traced.comp.spv");

/// Bytes before the boxes in the boxes buffer (the glyph count, padded to the 8 bytes a
/// build input's address needs).
const BOXES_HEADER: u64 = 8;
/// The traversal's workgroup edge: one invocation per pixel in squares of this edge
/// (`local_size_x`, `local_size_y` of `glsl/research/traced.comp`).
pub(crate) const TRACE_GROUP_EDGE: u32 = 8;
/// Bytes per box (`VkAabbPositionsKHR`).
const BOX_BYTES: u64 = 24;

/// When the hierarchy is built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TracedBuild {
    /// The traced path is off: frames splat.
    #[default]
    Off,
    /// Built on the first traced frame after each upload (what a shipped path would do).
    PerUpload,
    /// Built again every frame (the build's cost, measured against `PerUpload`).
    EveryFrame,
}

/// One scene's hierarchy and the buffers it is built from and in.
struct Structures {
    /// The glyph count it holds room for.
    capacity: u32,
    boxes: GpuBuffer,
    bottom_buffer: GpuBuffer,
    bottom: vk::AccelerationStructureKHR,
    top_buffer: GpuBuffer,
    top: vk::AccelerationStructureKHR,
    /// The top level's one instance (host-written once).
    instance: GpuBuffer,
    scratch: GpuBuffer,
}

/// The traced path's state in a renderer.
#[derive(Default)]
pub(crate) struct Traced {
    pub build: TracedBuild,
    loader: Option<acceleration_structure::Device>,
    scratch_align: u64,
    /// The glyph count the hierarchy was built for since the last upload (None: build).
    built_for: Option<u32>,
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
    boxes_pipelines: Vec<(SplatKey, vk::Pipeline)>,
    trace_pipelines: Vec<(SplatKey, vk::Pipeline)>,
    structures: Option<Structures>,
    /// Hierarchies of earlier scenes, kept until `destroy` (a benchmark uploads a few).
    retired: Vec<Structures>,
}

impl Traced {
    /// Takes the acceleration-structure functions of `host`'s device, which has ray queries
    /// enabled.
    fn connect(&mut self, host: &HostDevice) {
        self.loader = Some(acceleration_structure::Device::new(
            host.instance,
            host.device,
        ));
        let mut structures = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
        let mut props = vk::PhysicalDeviceProperties2::default().push_next(&mut structures);
        // SAFETY: the host's physical device of its instance (HostDevice's contract).
        unsafe {
            host.instance
                .get_physical_device_properties2(host.physical_device, &mut props)
        };
        self.scratch_align =
            u64::from(structures.min_acceleration_structure_scratch_offset_alignment).max(1);
    }

    /// A new scene (or new instances): build again before the next traced frame.
    pub fn forget_upload(&mut self) {
        self.built_for = None;
    }

    /// Destroys every object.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        let all = self
            .structures
            .take()
            .into_iter()
            .chain(self.retired.drain(..));
        let all: Vec<Structures> = all.collect();
        // SAFETY: caller contract; every object was made from `device` (null ones are
        // ignored).
        unsafe {
            for s in all {
                if let Some(loader) = &self.loader {
                    loader.destroy_acceleration_structure(s.bottom, None);
                    loader.destroy_acceleration_structure(s.top, None);
                }
                for buffer in [
                    s.boxes,
                    s.bottom_buffer,
                    s.top_buffer,
                    s.instance,
                    s.scratch,
                ] {
                    buffer.destroy(device, allocator);
                }
            }
            let pipelines = self
                .boxes_pipelines
                .drain(..)
                .chain(self.trace_pipelines.drain(..));
            for (_, pipeline) in pipelines {
                device.destroy_pipeline(pipeline, None);
            }
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_pipeline_layout(self.layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
        self.pool = vk::DescriptorPool::null();
        self.layout = vk::PipelineLayout::null();
        self.set_layout = vk::DescriptorSetLayout::null();
    }

    /// The set layout (set 1: the hierarchy, the boxes), the pipeline layout (set 0 the
    /// renderer's) and the set, made on first use.
    fn ensure_layouts(
        &mut self,
        device: &ash::Device,
        set0: vk::DescriptorSetLayout,
    ) -> Result<()> {
        if self.layout != vk::PipelineLayout::null() {
            return Ok(());
        }
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(0)
                .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
            vk::DescriptorSetLayoutBinding::default()
                .binding(1)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
        ];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; owned by `self`, destroyed in `destroy`.
        self.set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .call("vkCreateDescriptorSetLayout")?;
        let layouts = [set0, self.set_layout];
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::COMPUTE)
            .size(size_of::<PushConstants>() as u32)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: as above.
        self.layout =
            unsafe { device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")?;
        let sizes = [
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
                .descriptor_count(1),
            vk::DescriptorPoolSize::default()
                .ty(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1),
        ];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: as above.
        self.pool =
            unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
        let set_layouts = [self.set_layout];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.pool)
            .set_layouts(&set_layouts);
        // SAFETY: a pool with room for this one set; freed with the pool.
        self.set =
            unsafe { device.allocate_descriptor_sets(&info) }.call("vkAllocateDescriptorSets")?[0];
        Ok(())
    }

    /// The pipeline running `code` for `key`, built on first use.
    fn pipeline(
        &mut self,
        device: &ash::Device,
        cache: vk::PipelineCache,
        key: SplatKey,
        boxes: bool,
    ) -> Result<vk::Pipeline> {
        let list = if boxes {
            &mut self.boxes_pipelines
        } else {
            &mut self.trace_pipelines
        };
        if let Some((_, p)) = list.iter().find(|(k, _)| *k == key) {
            return Ok(*p);
        }
        let code = if boxes {
            TRACED_BOXES_COMP
        } else {
            TRACED_COMP
        };
        let pipeline =
            create_compute_pipeline(device, cache, self.layout, code, &key.spec_constants())?;
        list.push((key, pipeline));
        Ok(pipeline)
    }

    /// Room for `count` glyphs: the structures made now (the old ones retired) where they
    /// hold fewer, and the set pointed at them.
    fn ensure_structures(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        count: u32,
    ) -> Result<()> {
        if self
            .structures
            .as_ref()
            .is_some_and(|s| s.capacity >= count)
        {
            return Ok(());
        }
        let loader = self.loader.as_ref().ok_or_else(no_ray_query)?;
        let structures = make_structures(device, allocator, loader, count, self.scratch_align)?;
        let infos = [vk::DescriptorBufferInfo::default()
            .buffer(structures.boxes.handle())
            .offset(0)
            .range(vk::WHOLE_SIZE)];
        let tops = [structures.top];
        let mut top_info = vk::WriteDescriptorSetAccelerationStructureKHR::default()
            .acceleration_structures(&tops);
        let mut top_write = vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR)
            .push_next(&mut top_info);
        top_write.descriptor_count = 1;
        let writes = [
            top_write,
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(1)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(&infos),
        ];
        // SAFETY: the set is not in use by pending work: the old structures' frames used
        // it, and a benchmark changes scenes between waited-for frames (research only).
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        if let Some(old) = self.structures.replace(structures) {
            self.retired.push(old);
        }
        Ok(())
    }
}

/// The error of a traced frame on a device without ray queries.
fn no_ray_query() -> Error {
    Error::invalid(
        "traced path",
        "the device was not created with ray queries (the offscreen renderer enables them \
         where the device has them)",
    )
}

/// Whether `physical_device` has what the traced path needs: the extensions
/// `VK_KHR_acceleration_structure`, `VK_KHR_ray_query`, `VK_KHR_deferred_host_operations`
/// and the features `accelerationStructure`, `rayQuery` and `bufferDeviceAddress`.
///
/// # Safety
/// `physical_device` was enumerated from `instance`.
pub(crate) unsafe fn ray_query_supported(
    instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
) -> bool {
    // SAFETY: caller contract.
    let extensions = unsafe { instance.enumerate_device_extension_properties(physical_device) }
        .unwrap_or_default();
    let has = |name: &std::ffi::CStr| {
        extensions
            .iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
    };
    if !crate::gpu::context::RAY_QUERY_EXTENSIONS
        .iter()
        .all(|name| has(name))
    {
        return false;
    }
    let mut vulkan12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut queries = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut all = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut vulkan12)
        .push_next(&mut structures)
        .push_next(&mut queries);
    // SAFETY: caller contract; the chain points at locals that outlive the call, and its
    // structures belong to extensions the device has.
    unsafe { instance.get_physical_device_features2(physical_device, &mut all) };
    structures.acceleration_structure == vk::TRUE
        && queries.ray_query == vk::TRUE
        && vulkan12.buffer_device_address == vk::TRUE
}

/// A buffer's device address.
fn address(device: &ash::Device, buffer: &GpuBuffer) -> vk::DeviceAddress {
    let info = vk::BufferDeviceAddressInfo::default().buffer(buffer.handle());
    // SAFETY: the buffer was made with SHADER_DEVICE_ADDRESS usage on `device`.
    unsafe { device.get_buffer_device_address(&info) }
}

/// The bottom level's geometry: `count` boxes from `boxes`.
fn box_geometry(boxes: vk::DeviceAddress) -> vk::AccelerationStructureGeometryKHR<'static> {
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::AABBS)
        .geometry(vk::AccelerationStructureGeometryDataKHR {
            aabbs: vk::AccelerationStructureGeometryAabbsDataKHR::default()
                .data(vk::DeviceOrHostAddressConstKHR {
                    device_address: boxes,
                })
                .stride(BOX_BYTES),
        })
        .flags(vk::GeometryFlagsKHR::OPAQUE)
}

/// The top level's geometry: one instance from `instance`.
fn instance_geometry(instance: vk::DeviceAddress) -> vk::AccelerationStructureGeometryKHR<'static> {
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::INSTANCES)
        .geometry(vk::AccelerationStructureGeometryDataKHR {
            instances: vk::AccelerationStructureGeometryInstancesDataKHR::default().data(
                vk::DeviceOrHostAddressConstKHR {
                    device_address: instance,
                },
            ),
        })
}

/// Makes the buffers and structures for `count` glyphs.
fn make_structures(
    device: &ash::Device,
    allocator: &mut dyn MemoryAllocator,
    loader: &acceleration_structure::Device,
    count: u32,
    scratch_align: u64,
) -> Result<Structures> {
    let count = count.max(1);
    let sizes = |geometry: vk::AccelerationStructureGeometryKHR, ty, primitives: u32| {
        let geometries = [geometry];
        let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(ty)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .geometries(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        // SAFETY: a valid build info whose geometry addresses are not read by a size query.
        unsafe {
            loader.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &info,
                &[primitives],
                &mut sizes,
            )
        };
        sizes
    };
    let bottom_sizes = sizes(
        box_geometry(0),
        vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
        count,
    );
    let top_sizes = sizes(
        instance_geometry(0),
        vk::AccelerationStructureTypeKHR::TOP_LEVEL,
        1,
    );
    let address_usage = vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
    let input = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR;
    let storage = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR;
    let mut made: Vec<GpuBuffer> = Vec::new();
    let specs: [(&'static str, u64, vk::BufferUsageFlags, MemoryUse); 5] = [
        (
            "traced boxes",
            BOXES_HEADER + BOX_BYTES * u64::from(count),
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | input
                | address_usage,
            MemoryUse::GpuOnly,
        ),
        (
            "traced bottom level",
            bottom_sizes.acceleration_structure_size,
            storage | address_usage,
            MemoryUse::GpuOnly,
        ),
        (
            "traced top level",
            top_sizes.acceleration_structure_size,
            storage | address_usage,
            MemoryUse::GpuOnly,
        ),
        (
            "traced instance",
            size_of::<vk::AccelerationStructureInstanceKHR>() as u64,
            input | address_usage,
            MemoryUse::Upload,
        ),
        (
            "traced scratch",
            bottom_sizes
                .build_scratch_size
                .max(top_sizes.build_scratch_size)
                + scratch_align,
            vk::BufferUsageFlags::STORAGE_BUFFER | address_usage,
            MemoryUse::GpuOnly,
        ),
    ];
    let release =
        |device: &ash::Device, allocator: &mut dyn MemoryAllocator, made: Vec<GpuBuffer>| {
            for buffer in made {
                // SAFETY: just made, never used.
                unsafe { buffer.destroy(device, allocator) };
            }
        };
    for (name, size, usage, memory) in specs {
        match GpuBuffer::new(device, allocator, name, size, usage, memory) {
            Ok(buffer) => made.push(buffer),
            Err(e) => {
                release(device, allocator, made);
                return Err(e);
            }
        }
    }
    let make = |buffer: &GpuBuffer, size: u64, ty| {
        let info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.handle())
            .size(size)
            .ty(ty);
        // SAFETY: a valid create info on a buffer of at least `size` bytes with storage usage.
        unsafe { loader.create_acceleration_structure(&info, None) }
            .call("vkCreateAccelerationStructureKHR")
    };
    let bottom = match make(
        &made[1],
        bottom_sizes.acceleration_structure_size,
        vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
    ) {
        Ok(s) => s,
        Err(e) => {
            release(device, allocator, made);
            return Err(e);
        }
    };
    let top = match make(
        &made[2],
        top_sizes.acceleration_structure_size,
        vk::AccelerationStructureTypeKHR::TOP_LEVEL,
    ) {
        Ok(s) => s,
        Err(e) => {
            // SAFETY: just made, never used.
            unsafe { loader.destroy_acceleration_structure(bottom, None) };
            release(device, allocator, made);
            return Err(e);
        }
    };
    let info =
        vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(bottom);
    // SAFETY: a structure just made on this device.
    let bottom_address = unsafe { loader.get_acceleration_structure_device_address(&info) };
    let instance = vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR {
            matrix: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0],
        },
        instance_custom_index_and_mask: vk::Packed24_8::new(0, 0xff),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(0, 0),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
            device_handle: bottom_address,
        },
    };
    // SAFETY: the instance is a plain #[repr(C)] record of 64 bytes with no padding; the
    // slice lives as long as `instance`.
    let bytes = unsafe {
        std::slice::from_raw_parts(
            (&instance as *const vk::AccelerationStructureInstanceKHR).cast::<u8>(),
            size_of::<vk::AccelerationStructureInstanceKHR>(),
        )
    };
    let mut made = made.into_iter();
    let (boxes, bottom_buffer, top_buffer, mut instance_buffer, scratch) = (
        made.next().expect("five buffers"),
        made.next().expect("five buffers"),
        made.next().expect("five buffers"),
        made.next().expect("five buffers"),
        made.next().expect("five buffers"),
    );
    instance_buffer.write(bytes)?;
    Ok(Structures {
        capacity: count,
        boxes,
        bottom_buffer,
        bottom,
        top_buffer,
        top,
        instance: instance_buffer,
        scratch,
    })
}

impl EllipsoidRenderer {
    /// Lets the traced path run on `host`'s device, which was created with ray queries
    /// ([`ray_query_supported`]; the offscreen renderer's device has them where it can).
    pub(crate) fn connect_ray_query(&mut self, host: &HostDevice) {
        self.research.traced.connect(host);
    }

    /// Builds the traced path from the next frame on (`TracedBuild::Off`: the splat); frames
    /// that do not splat are unchanged. A traced frame on a device without ray queries, or of
    /// a scene in several chunks, is an error.
    pub fn set_traced(&mut self, build: TracedBuild) {
        self.research.traced.build = build;
    }

    /// Records what a traced frame needs before its pre-pass (the boxes, the hierarchy's
    /// build where due) and returns the traversal's dispatch; `None` where the frame splats.
    ///
    /// # Safety
    /// As [`EllipsoidRenderer::record_prepass`]; `set0` is the chunk's set and `push` the
    /// frame's push constants.
    pub(crate) unsafe fn record_traced_build(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        plan: &FramePlan,
        set0: vk::DescriptorSet,
        push: &PushConstants,
    ) -> Result<Option<TracedDispatch>> {
        let traced = &mut self.research.traced;
        if traced.build == TracedBuild::Off || plan.path.splat().is_none() {
            return Ok(None);
        }
        let loader = traced.loader.clone().ok_or_else(no_ray_query)?;
        if self.chunking().len() != 1 {
            return Err(Error::invalid(
                "traced path",
                "the scene is in several chunks (one hierarchy holds one chunk)",
            ));
        }
        let count = self.scene.count;
        let set_layout = self.pipelines.set_layout();
        let cache = self.pipelines.cache();
        let traced = &mut self.research.traced;
        traced.ensure_layouts(device, set_layout)?;
        traced.ensure_structures(device, allocator, count)?;
        let key = SplatKey::of(plan, &self.research);
        let traced = &mut self.research.traced;
        let trace = traced.pipeline(device, cache, key, false)?;
        let boxes_pipeline = traced.pipeline(device, cache, key, true)?;
        let dispatch = TracedDispatch {
            layout: traced.layout,
            set: traced.set,
            pipeline: trace,
            group_edge: TRACE_GROUP_EDGE,
        };
        if traced.build == TracedBuild::PerUpload && traced.built_for == Some(count) {
            return Ok(Some(dispatch));
        }
        let s = traced.structures.as_ref().ok_or_else(no_ray_query)?;
        let boxes = address(device, &s.boxes) + BOXES_HEADER;
        let scratch = address(device, &s.scratch).next_multiple_of(traced.scratch_align);
        let instance = address(device, &s.instance);
        let bottom_geometry = [box_geometry(boxes)];
        let bottom = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .dst_acceleration_structure(s.bottom)
            .geometries(&bottom_geometry)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch,
            });
        let top_geometry = [instance_geometry(instance)];
        let top = vk::AccelerationStructureBuildGeometryInfoKHR::default()
            .ty(vk::AccelerationStructureTypeKHR::TOP_LEVEL)
            .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
            .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
            .dst_acceleration_structure(s.top)
            .geometries(&top_geometry)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: scratch,
            });
        let range = |primitive_count| vk::AccelerationStructureBuildRangeInfoKHR {
            primitive_count,
            primitive_offset: 0,
            first_vertex: 0,
            transform_offset: 0,
        };
        let (bottom_range, top_range) = ([range(count)], [range(1)]);
        let header = [count, 0u32];
        // SAFETY: caller contract: `cmd` records outside a pass; every object is owned by
        // `self.research.traced` and outlives the submission (retired ones until `destroy`).
        unsafe {
            barriers::TRACED_BEFORE_BUILD.record(device, cmd);
            device.cmd_update_buffer(cmd, s.boxes.handle(), 0, bytemuck::cast_slice(&header));
            barriers::PREPASS_CLEARED.record(device, cmd);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, boxes_pipeline);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                traced.layout,
                0,
                &[set0, traced.set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                traced.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(push),
            );
            let (x, y) = crate::renderer::prepass::splat_grid(count);
            device.cmd_dispatch(cmd, x, y, 1);
            barriers::TRACED_BOXES_TO_BUILD.record(device, cmd);
            loader.cmd_build_acceleration_structures(cmd, &[bottom], &[&bottom_range]);
            barriers::TRACED_BOTTOM_TO_TOP.record(device, cmd);
            loader.cmd_build_acceleration_structures(cmd, &[top], &[&top_range]);
            barriers::TRACED_BUILT_TO_TRACE.record(device, cmd);
        }
        traced.built_for = Some(count);
        Ok(Some(dispatch))
    }
}
