//! `EllipsoidRenderer`: the pipeline, the instance buffer and the recorded draw. It records into
//! a command buffer it is given and never submits.

use ash::vk;
use glam::DVec3;
use gpu_allocator::vulkan::Allocator;
use gpu_allocator::MemoryLocation;

use crate::camera::{Camera, Projection};
use crate::error::{Error, Result, VkCall};
use crate::gpu::{shaders, GpuBuffer};
use crate::scene::Scene;

/// Bytes per instance on the GPU (`Instance` in `glsl/include/ellipsoid_common.glsl`).
pub const INSTANCE_BYTES: usize = 48;
/// Bytes of camera push constants (`CameraPush` in the shader).
const PUSH_BYTES: usize = 112;
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

/// Formats of the attachments the renderer draws into (dynamic rendering).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetFormats {
    /// Colour attachment 0.
    pub color: vk::Format,
    /// Depth attachment; the renderer writes reversed-Z depth (`near / view depth`).
    pub depth: vk::Format,
    /// With `true`, attachment 1 is the world normal (`R32G32B32A32_SFLOAT`) and attachment 2
    /// the instance ID (`R32_UINT`).
    pub aux_outputs: bool,
}

/// How the fragment shader intersects the pixel's ray with the ellipsoid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Intersection {
    /// Gumhold's closed form in the silhouette frame: no cancellation at any distance.
    #[default]
    Stable,
    /// The textbook quadratic `b^2 - ac` in parameter space, in float32: the baseline that
    /// shows what the stable form buys (it loses hits and normals at large distance/radius).
    Textbook,
}

/// The screen-space polygon each instance is drawn as.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Footprint {
    /// The oriented rectangle around the projected ellipse: at most 4/pi of the covered
    /// pixels, for any shape and orientation (the shipped default).
    #[default]
    OrientedRect,
    /// A hexagon around the projected ellipse (area ratio 1.10; 6 vertices).
    Hexagon,
    /// An octagon around the projected ellipse (area ratio 1.05; 8 vertices).
    Octagon,
    /// The axis-aligned bounding rectangle of the projected ellipse (loose for thin glyphs at
    /// 45 degrees).
    AxisRect,
    /// Gumhold's square around the silhouette circle in the silhouette plane, projected.
    WorldQuad,
}

impl Footprint {
    /// Vertices per instance (a triangle strip over the polygon).
    pub fn vertices(self) -> u32 {
        match self {
            Footprint::Hexagon => 6,
            Footprint::Octagon => 8,
            _ => 4,
        }
    }

    /// The `BOUNDS` specialization constant.
    fn bounds_mode(self) -> u32 {
        match self {
            Footprint::OrientedRect | Footprint::Hexagon | Footprint::Octagon => 0,
            Footprint::AxisRect => 1,
            Footprint::WorldQuad => 2,
        }
    }
}

/// What a pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Variant {
    orthographic: bool,
    intersection: Intersection,
    footprint: Footprint,
}

/// Normal attachment format when `aux_outputs` is set.
pub const NORMAL_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
/// Instance-ID attachment format when `aux_outputs` is set.
pub const ID_FORMAT: vk::Format = vk::Format::R32_UINT;

/// Pipeline, descriptor and instance data for drawing one scene.
pub struct EllipsoidRenderer {
    set_layout: vk::DescriptorSetLayout,
    pipeline_layout: vk::PipelineLayout,
    descriptor_pool: vk::DescriptorPool,
    descriptor_set: vk::DescriptorSet,
    formats: TargetFormats,
    pipelines: Vec<(Variant, vk::Pipeline)>,
    instances: Option<GpuBuffer>,
    count: u32,
    origin: DVec3,
    /// Shading parameters, applied at the next `record`.
    pub material: Material,
    /// Intersection formulation used from the next `record` on.
    pub intersection: Intersection,
    /// Screen polygon per instance used from the next `record` on.
    pub footprint: Footprint,
}

impl EllipsoidRenderer {
    /// Creates the descriptor and pipeline layouts; pipelines are built on first use of each
    /// variant (projection kind x intersection), so a scene pays only for what it draws.
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        formats: TargetFormats,
    ) -> Result<Self> {
        let mut renderer = Self {
            set_layout: vk::DescriptorSetLayout::null(),
            pipeline_layout: vk::PipelineLayout::null(),
            descriptor_pool: vk::DescriptorPool::null(),
            descriptor_set: vk::DescriptorSet::null(),
            formats,
            pipelines: Vec::new(),
            instances: None,
            count: 0,
            origin: DVec3::ZERO,
            material: Material::default(),
            intersection: Intersection::default(),
            footprint: Footprint::default(),
        };
        // On failure, `destroy` releases whatever was created (null handles are skipped).
        match renderer.create_objects(device) {
            Ok(()) => Ok(renderer),
            Err(e) => {
                renderer.destroy(device, allocator);
                Err(e)
            }
        }
    }

    fn create_objects(&mut self, device: &ash::Device) -> Result<()> {
        let bindings = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::VERTEX)];
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: valid create info; owned by `self`, destroyed in `destroy`.
        self.set_layout = unsafe { device.create_descriptor_set_layout(&info, None) }
            .call("vkCreateDescriptorSetLayout")?;

        let ranges = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .size(PUSH_BYTES as u32)];
        let layouts = [self.set_layout];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(&ranges);
        // SAFETY: as above.
        self.pipeline_layout =
            unsafe { device.create_pipeline_layout(&info, None) }.call("vkCreatePipelineLayout")?;

        let sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)];
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: as above.
        self.descriptor_pool =
            unsafe { device.create_descriptor_pool(&info, None) }.call("vkCreateDescriptorPool")?;
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.descriptor_pool)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for exactly this set; freed with the pool.
        self.descriptor_set =
            unsafe { device.allocate_descriptor_sets(&info) }.call("vkAllocateDescriptorSets")?[0];
        Ok(())
    }

    /// The pipeline for `variant`, built now if this is its first use.
    fn pipeline(&mut self, device: &ash::Device, variant: Variant) -> Result<vk::Pipeline> {
        if let Some((_, p)) = self.pipelines.iter().find(|(v, _)| *v == variant) {
            return Ok(*p);
        }
        let pipeline = create_pipeline(device, self.pipeline_layout, self.formats, variant)?;
        self.pipelines.push((variant, pipeline));
        Ok(pipeline)
    }

    /// Replaces the instance data with `scene`. Positions are stored relative to a scene origin
    /// chosen at the centre of the data's bounds, so float32 keeps its precision where the data
    /// is, however far that is from the world origin. The GPU must not be using the old buffer.
    pub fn upload(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        scene: &Scene,
    ) -> Result<()> {
        let count = u32::try_from(scene.len()).map_err(|_| {
            Error::invalid("scene", format!("{} ellipsoids exceed u32", scene.len()))
        })?;
        let bytes = INSTANCE_BYTES * scene.len();
        self.origin = scene
            .bounds()
            .map(|(lo, hi)| (lo + hi) * 0.5)
            .unwrap_or(DVec3::ZERO);
        let mut data = Vec::with_capacity(bytes);
        for e in &scene.ellipsoids {
            let c = (e.center - self.origin).as_vec3();
            let q = e.rotation.as_quat();
            let r = e.radii.as_vec3();
            if !(r.is_finite() && r.min_element() > 0.0) {
                return Err(Error::invalid(
                    "ellipsoid radii",
                    format!("{} does not fit float32 as a positive number", e.radii),
                ));
            }
            let color = e.color.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u32);
            let packed = color[0] | (color[1] << 8) | (color[2] << 16) | (255 << 24);
            for v in [c.x, c.y, c.z] {
                data.extend_from_slice(&v.to_ne_bytes());
            }
            data.extend_from_slice(&packed.to_ne_bytes());
            for v in [q.x, q.y, q.z, q.w, r.x, r.y, r.z, 0.0] {
                data.extend_from_slice(&v.to_ne_bytes());
            }
        }
        let reuse = self
            .instances
            .as_ref()
            .is_some_and(|b| b.size() >= bytes.max(1) as u64);
        if !reuse {
            if let Some(old) = self.instances.take() {
                old.destroy(device, allocator);
            }
            let buffer = GpuBuffer::new(
                device,
                allocator,
                "ellipsoid instances",
                bytes as u64,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::CpuToGpu,
            )?;
            let infos = [vk::DescriptorBufferInfo::default()
                .buffer(buffer.handle())
                .offset(0)
                .range(vk::WHOLE_SIZE)];
            let write = vk::WriteDescriptorSet::default()
                .dst_set(self.descriptor_set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(&infos);
            // SAFETY: the set is not in use by pending work (caller contract), the buffer is live.
            unsafe { device.update_descriptor_sets(&[write], &[]) };
            self.instances = Some(buffer);
        }
        if let Some(buffer) = self.instances.as_mut() {
            buffer.write(&data)?;
        }
        self.count = count;
        Ok(())
    }

    /// Number of instances uploaded.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The scene origin that instance positions are stored relative to.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Records the draw into `cmd`, which must be inside a dynamic-rendering pass whose
    /// attachments match the `TargetFormats` and whose viewport is the camera's image size.
    /// Sets viewport and scissor itself. Records nothing if the scene is empty.
    pub fn record(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        camera.validate()?;
        if self.count == 0 {
            return Ok(());
        }
        let push = self.push_constants(camera);
        let variant = Variant {
            orthographic: matches!(camera.projection, Projection::Orthographic { .. }),
            intersection: self.intersection,
            footprint: self.footprint,
        };
        let pipeline = self.pipeline(device, variant)?;
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
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.pipeline_layout,
                0,
                &[self.descriptor_set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                self.pipeline_layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                &push,
            );
            device.cmd_draw(cmd, self.footprint.vertices(), self.count, 0, 0);
        }
        Ok(())
    }

    /// The camera push constants, relative to the scene origin.
    fn push_constants(&self, camera: &Camera) -> Vec<u8> {
        let b = camera.basis();
        let (sx, sy) = camera.ndc_scale();
        // The eye in view axes, relative to the scene origin, in float64 then rounded once.
        let rel = camera.eye - self.origin;
        let eye = glam::DVec3::new(rel.dot(b.right), rel.dot(b.up), rel.dot(b.forward)).as_vec3();
        let m = &self.material;
        let values: [f32; PUSH_BYTES / 4] = [
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
            0.0,
            2.0 / camera.width as f32,
            2.0 / camera.height as f32,
            QUAD_MARGIN_PX,
            0.0,
            m.ambient,
            m.diffuse,
            m.specular,
            m.shininess,
            m.specular_color[0],
            m.specular_color[1],
            m.specular_color[2],
            0.0,
        ];
        values.iter().flat_map(|v| v.to_ne_bytes()).collect()
    }

    /// Destroys everything the renderer created. The GPU must be done with it.
    pub fn destroy(mut self, device: &ash::Device, allocator: &mut Allocator) {
        if let Some(buffer) = self.instances.take() {
            buffer.destroy(device, allocator);
        }
        // SAFETY: all handles were created by `self` from `device` (or are null, which Vulkan
        // ignores); the caller guarantees no pending work uses them.
        unsafe {
            for (_, pipeline) in self.pipelines.drain(..) {
                device.destroy_pipeline(pipeline, None);
            }
            device.destroy_descriptor_pool(self.descriptor_pool, None);
            device.destroy_pipeline_layout(self.pipeline_layout, None);
            device.destroy_descriptor_set_layout(self.set_layout, None);
        }
    }
}

/// Builds the impostor pipeline for one projection kind.
fn create_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    formats: TargetFormats,
    variant: Variant,
) -> Result<vk::Pipeline> {
    let vert = shaders::create_module(device, shaders::ELLIPSOID_VERT)?;
    let frag = match shaders::create_module(device, shaders::ELLIPSOID_FRAG) {
        Ok(m) => m,
        Err(e) => {
            // SAFETY: just created, unused.
            unsafe { device.destroy_shader_module(vert, None) };
            return Err(e);
        }
    };
    let result = build_pipeline(device, layout, formats, variant, vert, frag);
    // SAFETY: modules are no longer needed once pipeline creation returned.
    unsafe {
        device.destroy_shader_module(vert, None);
        device.destroy_shader_module(frag, None);
    }
    result
}

fn build_pipeline(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    formats: TargetFormats,
    variant: Variant,
    vert: vk::ShaderModule,
    frag: vk::ShaderModule,
) -> Result<vk::Pipeline> {
    // Specialization constants, 4 bytes each: 0 = ORTHOGRAPHIC, 1 = AUX_OUTPUTS, 2 = TEXTBOOK
    // (VkBool32), 3 = BOUNDS, 4 = CORNERS (int).
    let values: [u32; 5] = [
        variant.orthographic as u32,
        formats.aux_outputs as u32,
        (variant.intersection == Intersection::Textbook) as u32,
        variant.footprint.bounds_mode(),
        variant.footprint.vertices(),
    ];
    let spec_data: Vec<u8> = values.iter().flat_map(|v| v.to_ne_bytes()).collect();
    let entries: Vec<vk::SpecializationMapEntry> = (0..values.len() as u32)
        .map(|i| vk::SpecializationMapEntry {
            constant_id: i,
            offset: 4 * i,
            size: 4,
        })
        .collect();
    let spec = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(&spec_data);
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vert)
            .name(c"main")
            .specialization_info(&spec),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(frag)
            .name(c"main")
            .specialization_info(&spec),
    ];
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_STRIP);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    // Reversed-Z: larger is nearer, cleared to 0 (infinitely far).
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::GREATER);
    let attachment_count = if formats.aux_outputs { 3 } else { 1 };
    let blend_attachments = vec![
        vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA);
        attachment_count
    ];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats: Vec<vk::Format> = if formats.aux_outputs {
        vec![formats.color, NORMAL_FORMAT, ID_FORMAT]
    } else {
        vec![formats.color]
    };
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(formats.depth);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    // SAFETY: every pointer in `info` refers to locals alive for the call; the pipeline is owned
    // by the renderer.
    let pipelines =
        unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
            .map_err(|(_, result)| Error::Vulkan {
                call: "vkCreateGraphicsPipelines",
                result,
            })?;
    Ok(pipelines[0])
}
