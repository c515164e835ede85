//! Creating the pipelines the keys describe: the graphics pipelines of the draw and the
//! resolve, and the compute pipelines of the splat and the pre-pass's steps.

use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::shaders::{self, FragmentShader};
use crate::gpu_layout::SpecConstants;
use crate::research;
use crate::target::{Pass, Target};

use super::super::prepass::steps::TiledStep;
use super::keys::{CullKey, PipelineKey, SplatKey};
use super::raster::Raster;

/// The SPIR-V of the two stages for `key`, the fragment stage writing the normal and ID
/// attachments when `aux_outputs` (and counting shaded pixels in the `research` builds that
/// do).
fn stage_code(key: &PipelineKey, aux_outputs: bool) -> Result<(&'static [u8], &'static [u8])> {
    let (vertex, fragment): (&'static [u8], FragmentShader) = match key.baseline {
        Some(baseline) => baseline.stages(key.setup_once)?,
        None if key.resolve => (shaders::RESOLVE_VERT, shaders::RESOLVE_FRAG),
        None if key.setup_once => (
            shaders::ELLIPSOID_SETUP_ONCE_VERT,
            shaders::ELLIPSOID_SETUP_ONCE_FRAG,
        ),
        None => (shaders::ELLIPSOID_VERT, shaders::ELLIPSOID_FRAG),
    };
    let fragment = if key.count_fragments {
        research::counted(&fragment, aux_outputs)?
    } else {
        fragment.pick(aux_outputs)
    };
    Ok((vertex, fragment))
}

/// Creates the pipeline for `key`, drawing into `target`; the caller owns it.
pub(crate) fn create_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    target: &Target,
    key: PipelineKey,
) -> Result<vk::Pipeline> {
    let (vert_code, frag_code) = stage_code(&key, target.aux_outputs)?;
    let vert = shaders::create_module(device, vert_code)?;
    // The fragment shaders declare `depth_less` (reversed Z); standard Z needs the mirror.
    let frag = match shaders::create_fragment_module(device, frag_code, key.reversed_z) {
        Ok(m) => m,
        Err(e) => {
            // SAFETY: just created, unused.
            unsafe { device.destroy_shader_module(vert, None) };
            return Err(e);
        }
    };
    let result = build(device, cache, layout, target, key, vert, frag);
    // SAFETY: modules are no longer needed once pipeline creation returned.
    unsafe {
        device.destroy_shader_module(vert, None);
        device.destroy_shader_module(frag, None);
    }
    result
}

fn build(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    target: &Target,
    key: PipelineKey,
    vert: vk::ShaderModule,
    frag: vk::ShaderModule,
) -> Result<vk::Pipeline> {
    let raster = key.baseline.map_or(Raster::IMPOSTOR, |b| b.raster());
    let constants = key.spec_constants();
    let entries = SpecConstants::map_entries();
    let spec = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(bytemuck::bytes_of(&constants));
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
    // Meshes read unit-sphere positions; everything else builds its vertices from indices.
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: 12,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let attributes = [vk::VertexInputAttributeDescription {
        location: 0,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    }];
    let vertex_input = if raster.mesh_vertices {
        vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes)
    } else {
        vk::PipelineVertexInputStateCreateInfo::default()
    };
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(raster.topology);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster_state = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(raster.cull_mode)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    // Multisampled: either every sample runs the fragment shader at its own position
    // (gl_FragCoord is the sample's), so coverage and depth are exact per sample; or it runs
    // once per pixel and writes the exact coverage of each sample position in gl_SampleMask
    // (`COVERAGE_SAMPLES`), with one depth per pixel.
    let per_sample = target.multisampled() && key.coverage_samples == 1;
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(target.samples)
        .sample_shading_enable(per_sample)
        .min_sample_shading(1.0);
    // Reversed Z: larger is nearer; standard Z: smaller.
    let depth_on = raster.depth;
    let compare = if key.reversed_z {
        vk::CompareOp::GREATER
    } else {
        vk::CompareOp::LESS
    };
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(depth_on)
        .depth_write_enable(depth_on)
        .depth_compare_op(compare);
    // Attachment 0, and 1-2 with aux outputs; the pass's other attachments are left alone.
    let written = if target.aux_outputs { 3 } else { 1 };
    let blend_attachments: Vec<_> = (0..target.color_attachment_count())
        .map(|k| {
            let mask = if k < written {
                vk::ColorComponentFlags::RGBA
            } else {
                vk::ColorComponentFlags::empty()
            };
            vk::PipelineColorBlendAttachmentState::default().color_write_mask(mask)
        })
        .collect();
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster_state)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout);
    let mut rendering;
    match &target.pass {
        Pass::Dynamic {
            color_formats,
            depth_format,
        } => {
            rendering = vk::PipelineRenderingCreateInfo::default()
                .color_attachment_formats(color_formats)
                .depth_attachment_format(*depth_format);
            info = info.push_next(&mut rendering);
        }
        Pass::RenderPass {
            render_pass,
            subpass,
            ..
        } => info = info.render_pass(*render_pass).subpass(*subpass),
    }
    // SAFETY: every pointer in `info` refers to locals alive for the call; the pipeline is owned
    // by the caller; `cache` is the host's (or null) and outlives the renderer.
    let pipelines = unsafe { device.create_graphics_pipelines(cache, &[info], None) }
        .map_err(|(_, result)| Error::vulkan("vkCreateGraphicsPipelines", result))?;
    Ok(pipelines[0])
}

/// The pre-pass pipeline for `key` (`glsl/cull.comp`); the caller owns it.
pub(crate) fn create_cull_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    key: CullKey,
) -> Result<vk::Pipeline> {
    let constants = key.spec_constants();
    create_compute_pipeline(device, cache, layout, shaders::CULL_COMP, &constants)
}

/// The compute splat's pipeline for `key` (`glsl/splat.comp`, or a step of the benchmark's
/// tiled splat); the caller owns it.
pub(crate) fn create_splat_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    key: SplatKey,
) -> Result<vk::Pipeline> {
    let constants = key.spec_constants();
    let code = match key.tiled {
        Some(_) if research::TILED_SPLAT_COMP.is_empty() => {
            return Err(Error::invalid(
                "tiled splat",
                "the benchmark's tiled splat needs the `research` feature",
            ));
        }
        Some(TiledStep::Tiles) => research::TILED_SPLAT_COMP,
        Some(_) => research::TILED_BINS_COMP,
        None => shaders::SPLAT_COMP,
    };
    create_compute_pipeline(device, cache, layout, code, &constants)
}

/// A compute pipeline running `code` with `constants`; the caller owns it.
pub(crate) fn create_compute_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    code: &[u8],
    constants: &SpecConstants,
) -> Result<vk::Pipeline> {
    let module = shaders::create_module(device, code)?;
    let entries = SpecConstants::map_entries();
    let spec = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(bytemuck::bytes_of(constants));
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(c"main")
        .specialization_info(&spec);
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout);
    // SAFETY: `info` points at locals alive for the call; the module is destroyed right after.
    let result = unsafe { device.create_compute_pipelines(cache, &[info], None) };
    // SAFETY: pipeline creation has returned; the module is no longer needed.
    unsafe { device.destroy_shader_module(module, None) };
    result
        .map(|p| p[0])
        .map_err(|(_, result)| Error::vulkan("vkCreateComputePipelines", result))
}
