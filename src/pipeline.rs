//! Building the graphics pipeline for one [`DrawConfig`] and projection kind.

use ash::vk;

use crate::culling::{CullStep, Culling};
use crate::draw::{DrawConfig, Geometry, Intersection, Shading};
use crate::error::{Error, Result};
use crate::gpu::shaders;
use crate::target::{Pass, Target};

/// What a pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    pub orthographic: bool,
    pub config: DrawConfig,
    /// Index of the renderer's `Target` the pipeline draws into.
    pub target: usize,
    /// Reversed Z (compare `GREATER`, `depth_less`) or standard (`LESS`, `depth_greater`).
    pub reversed_z: bool,
    /// Fragment shaders count shaded pixels into binding 1.
    pub count_fragments: bool,
    /// The vertex stage reads instance indices compacted by the culling pre-pass.
    pub culled: bool,
    /// The impostor stages read the set-up the pre-pass computed (`PRESET_SETUP`).
    pub preset: bool,
    /// Every instance is a sphere (`SPHERES`).
    pub spheres: bool,
    /// Instances are in the compact format (`COMPACT`).
    pub compact: bool,
    /// Nothing reaches in front of the near plane (`NO_CAPS`).
    pub no_caps: bool,
}

/// The SPIR-V of the two stages for `key`, the fragment stage writing the normal and ID
/// attachments when `aux_outputs`.
fn stage_code(key: &PipelineKey, aux_outputs: bool) -> (&'static [u8], &'static [u8]) {
    let config = &key.config;
    let (vertex, fragment) = match config.geometry {
        Geometry::Mesh(_) => (shaders::MESH_VERT, shaders::MESH_FRAG),
        Geometry::BoxProxy => (shaders::BOX_VERT, shaders::ELLIPSOID_FRAG),
        Geometry::Impostor if key.preset => (
            shaders::ELLIPSOID_PRESET_VERT,
            shaders::ELLIPSOID_PRESET_FRAG,
        ),
        Geometry::Impostor => (
            shaders::ELLIPSOID_VERT,
            match config.shading {
                Shading::FlatDepth => shaders::ELLIPSOID_FLAT_DEPTH_FRAG,
                Shading::FlatFill => shaders::FLAT_FILL_FRAG,
                Shading::Exact | Shading::FastNormal => shaders::ELLIPSOID_FRAG,
            },
        ),
    };
    (vertex, fragment.pick(aux_outputs, key.count_fragments))
}

/// Creates the pipeline for `key`, drawing into `target`; the caller owns it.
pub(crate) fn create_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    target: &Target,
    key: PipelineKey,
) -> Result<vk::Pipeline> {
    let (vert_code, frag_code) = stage_code(&key, target.aux_outputs);
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
    let config = key.config;
    // Specialization constants, 4 bytes each (glsl/include/ellipsoid_common.glsl and the
    // fragment shaders): 0 ORTHOGRAPHIC, 2 TEXTBOOK, 3 BOUNDS, 4 CORNERS, 5 FAST_NORMAL,
    // 8 CULLED, 13 SPHERES, 14 NO_CAPS, 15 COMPACT. Stages ignore the ones they do not declare.
    let values: [u32; 9] = [
        key.orthographic as u32,
        (config.intersection == Intersection::Textbook) as u32,
        config.footprint.bounds_mode(),
        config.footprint.vertices(),
        (config.shading == Shading::FastNormal) as u32,
        key.culled as u32,
        key.spheres as u32,
        key.no_caps as u32,
        key.compact as u32,
    ];
    let ids: [u32; 9] = [0, 2, 3, 4, 5, 8, 13, 14, 15];
    let spec_data: Vec<u8> = values.iter().flat_map(|v| v.to_ne_bytes()).collect();
    let entries: Vec<vk::SpecializationMapEntry> = (0..values.len() as u32)
        .map(|i| vk::SpecializationMapEntry {
            constant_id: ids[i as usize],
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
    let vertex_input = match config.geometry {
        Geometry::Mesh(_) => vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes),
        _ => vk::PipelineVertexInputStateCreateInfo::default(),
    };
    let topology = match config.geometry {
        Geometry::Impostor => vk::PrimitiveTopology::TRIANGLE_STRIP,
        Geometry::BoxProxy | Geometry::Mesh(_) => vk::PrimitiveTopology::TRIANGLE_LIST,
    };
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(topology);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    // Closed meshes and boxes show only their front faces. Their triangles wind counter-
    // clockwise seen from outside in a y-up view; the y flip into Vulkan's framebuffer makes
    // that clockwise there.
    let cull = match config.geometry {
        Geometry::Impostor => vk::CullModeFlags::NONE,
        Geometry::BoxProxy | Geometry::Mesh(_) => vk::CullModeFlags::BACK,
    };
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(cull)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    // Multisampled: every sample runs the fragment shader at its own position (gl_FragCoord
    // is the sample's), so coverage and depth are exact per sample.
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(target.samples)
        .sample_shading_enable(target.multisampled())
        .min_sample_shading(1.0);
    // Reversed Z: larger is nearer; standard Z: smaller. Flat fill tests nothing.
    let depth_on = config.shading != Shading::FlatFill || config.geometry != Geometry::Impostor;
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
        .rasterization_state(&raster)
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

/// One step of the culling pre-pass (`glsl/cull.comp`) for one projection kind and choice of
/// culling; with `setup`, it also computes the set-up of that draw's impostors.
#[allow(clippy::too_many_arguments)]
pub(crate) fn create_cull_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    orthographic: bool,
    culling: Culling,
    step: CullStep,
    setup: Option<DrawConfig>,
    spheres: bool,
    compact: bool,
) -> Result<vk::Pipeline> {
    let module = shaders::create_module(device, shaders::CULL_COMP)?;
    // Specialization constants 0 ORTHOGRAPHIC, 6 CULL_FRUSTUM, 7 CULL_PIXEL_CENTRES,
    // 9 CULL_STEP, 10 CULL_OCCLUSION, 11 CULL_SETUP, and for the set-up the footprint and
    // intersection of the draw: 2 TEXTBOOK, 3 BOUNDS, 4 CORNERS; 13 SPHERES; 15 COMPACT.
    let config = setup.unwrap_or_default();
    let values: [(u32, u32); 11] = [
        (0, orthographic as u32),
        (6, culling.frustum as u32),
        (7, culling.pixel_centres as u32),
        (9, step as u32),
        (10, culling.occlusion as u32),
        (11, setup.is_some() as u32),
        (2, (config.intersection == Intersection::Textbook) as u32),
        (3, config.footprint.bounds_mode()),
        (4, config.footprint.vertices()),
        (13, spheres as u32),
        (15, compact as u32),
    ];
    let data: Vec<u8> = values.iter().flat_map(|(_, v)| v.to_ne_bytes()).collect();
    let entries: Vec<vk::SpecializationMapEntry> = values
        .iter()
        .enumerate()
        .map(|(k, &(constant_id, _))| vk::SpecializationMapEntry {
            constant_id,
            offset: 4 * k as u32,
            size: 4,
        })
        .collect();
    let spec = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(&data);
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
