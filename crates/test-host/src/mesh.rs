//! [`MeshPipeline`]: the host's own draws, flat-coloured triangle lists in a vertex buffer,
//! drawn unlit by a graphics pipeline built for one kind of [`HostTarget`].

use ash::vk;
use glam::DMat4;
use gpu_allocator::MemoryLocation;

use crate::buffer::OwnedBuffer;
use crate::{fail, Host, HostResult, HostTarget, TargetKind};

/// One vertex of a host mesh: world position and flat colour (24 bytes, two `vec3`s).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshVertex {
    /// World-space position.
    pub position: [f32; 3],
    /// Linear RGB in [0, 1], written unlit.
    pub color: [f32; 3],
}

/// A triangle list in a vertex buffer plus a pipeline drawing it, unlit, into one kind of
/// [`HostTarget`] (its kind, formats, samples and depth compare op).
pub struct MeshPipeline {
    vertices: Option<OwnedBuffer>,
    vertex_count: u32,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
}

impl MeshPipeline {
    /// Uploads `vertices` (a triangle list) and builds a pipeline compatible with `target`.
    pub fn new(
        host: &mut Host,
        target: &HostTarget,
        vertices: &[MeshVertex],
    ) -> HostResult<MeshPipeline> {
        if vertices.is_empty() || vertices.len() % 3 != 0 {
            return Err(format!(
                "{} vertices is not a non-empty triangle list",
                vertices.len()
            ));
        }
        let bytes: Vec<u8> = vertices
            .iter()
            .flat_map(|v| v.position.into_iter().chain(v.color))
            .flat_map(f32::to_ne_bytes)
            .collect();
        let mut mesh = MeshPipeline {
            vertices: None,
            vertex_count: vertices.len() as u32,
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
        };
        let result = mesh.create(host, target, &bytes);
        match result {
            Ok(()) => Ok(mesh),
            Err(e) => {
                mesh.destroy(host);
                Err(e)
            }
        }
    }

    fn create(&mut self, host: &mut Host, target: &HostTarget, bytes: &[u8]) -> HostResult<()> {
        let mut buffer = OwnedBuffer::new(
            host,
            "host mesh vertices",
            bytes.len() as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        // CpuToGpu memory is host-coherent: the write is visible to the GPU at submission.
        let uploaded = buffer
            .mapped_mut()
            .map(|mapped| mapped[..bytes.len()].copy_from_slice(bytes));
        self.vertices = Some(buffer);
        uploaded?;

        let device = host.device();
        let push_constants = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: 64,
        }];
        let layout_info =
            vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push_constants);
        // SAFETY: valid device and create info.
        self.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
            .map_err(fail("vkCreatePipelineLayout"))?;

        let vert = shader_module(
            device,
            include_bytes!(concat!(env!("OUT_DIR"), "/host_mesh.vert.spv")),
        )?;
        let frag = match shader_module(
            device,
            include_bytes!(concat!(env!("OUT_DIR"), "/host_mesh.frag.spv")),
        ) {
            Ok(frag) => frag,
            Err(e) => {
                // SAFETY: the module is not used by anything.
                unsafe { device.destroy_shader_module(vert, None) };
                return Err(e);
            }
        };
        let result = self.create_pipeline(device, target, vert, frag);
        // SAFETY: modules may be destroyed once the pipeline is created (or creation failed).
        unsafe {
            device.destroy_shader_module(vert, None);
            device.destroy_shader_module(frag, None);
        }
        result
    }

    fn create_pipeline(
        &mut self,
        device: &ash::Device,
        target: &HostTarget,
        vert: vk::ShaderModule,
        frag: vk::ShaderModule,
    ) -> HostResult<()> {
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag)
                .name(c"main"),
        ];
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<MeshVertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes = [
            vk::VertexInputAttributeDescription {
                location: 0,
                binding: 0,
                format: vk::Format::R32G32B32_SFLOAT,
                offset: std::mem::offset_of!(MeshVertex, position) as u32,
            },
            vk::VertexInputAttributeDescription {
                location: 1,
                binding: 0,
                format: vk::Format::R32G32B32_SFLOAT,
                offset: std::mem::offset_of!(MeshVertex, color) as u32,
            },
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes);
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(target.samples());
        let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(target.depth_compare());
        let blend_attachments = [vk::PipelineColorBlendAttachmentState::default()
            .blend_enable(false)
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats = [HostTarget::COLOR_FORMAT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(HostTarget::DEPTH_FORMAT);
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&rasterization)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_stencil)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(self.layout);
        info = match target.kind() {
            TargetKind::Dynamic => info.push_next(&mut rendering),
            TargetKind::RenderPass => info.render_pass(target.render_pass()).subpass(0),
        };
        // SAFETY: every pointer in `info` refers to locals alive during the call; the layout,
        // modules and render pass are valid.
        let pipelines =
            unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, e)| format!("vkCreateGraphicsPipelines failed: {e:?}"))?;
        self.pipeline = pipelines[0];
        Ok(())
    }

    /// Records the draw: binds the pipeline and vertex buffer, pushes `view_projection` and
    /// draws every vertex. Call between [`HostTarget::begin_pass`] and
    /// [`HostTarget::end_pass`] of the target the pipeline was built for.
    pub fn record(&self, device: &ash::Device, cmd: vk::CommandBuffer, view_projection: DMat4) {
        let matrix: Vec<u8> = view_projection
            .as_mat4()
            .to_cols_array()
            .into_iter()
            .flat_map(f32::to_ne_bytes)
            .collect();
        let buffer = self
            .vertices
            .as_ref()
            .expect("created in MeshPipeline::new")
            .buffer;
        // SAFETY: `cmd` is recording inside a compatible pass with viewport and scissor set;
        // the push constant range is 64 bytes at offset 0 for the vertex stage.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.cmd_bind_vertex_buffers(cmd, 0, &[buffer], &[0]);
            device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, &matrix);
            device.cmd_draw(cmd, self.vertex_count, 1, 0, 0);
        }
    }

    /// Destroys the pipeline and frees the vertex buffer. The GPU must be done with them.
    pub fn destroy(mut self, host: &mut Host) {
        let (device, allocator) = host.device_and_allocator();
        // SAFETY: the caller guarantees no pending work uses the pipeline or the buffer; null
        // handles are ignored by Vulkan.
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
        }
        if let Some(vertices) = self.vertices.take() {
            vertices.destroy(device, allocator);
        }
    }
}

/// A shader module from SPIR-V bytes.
fn shader_module(device: &ash::Device, spv: &[u8]) -> HostResult<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spv))
        .map_err(|e| format!("invalid SPIR-V: {e}"))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: `words` is SPIR-V compiled and validated by build.rs.
    unsafe { device.create_shader_module(&info, None) }.map_err(fail("vkCreateShaderModule"))
}
