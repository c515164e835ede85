//! Building the pipelines a frame plan asks for: the graphics pipeline of the draw and the
//! compute pipelines of the pre-pass's steps.

use ash::vk;

use crate::culling::{CullSelect, CullStep, Culling};
use crate::draw::{DrawConfig, Geometry, Intersection, Shading};
use crate::error::{Error, Result};
use crate::gpu::shaders;
use crate::gpu_layout::SpecConstants;
use crate::renderer::FramePlan;
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
    /// The impostor stages read the set-up the pre-pass computed (`SETUP_ONCE`).
    pub setup_once: bool,
    /// Every instance is a sphere (`SPHERES`).
    pub spheres: bool,
    /// Instances are in the compact format (`COMPACT`).
    pub compact: bool,
    /// Nothing reaches in front of the near plane (`NO_CAPS`).
    pub no_caps: bool,
    /// The compute splat's resolve instead of the instanced draw.
    pub compute_splat: bool,
    /// `COVERAGE_SAMPLES`: shaded once per pixel with this many samples tested (1: each
    /// sample shaded on its own, or a single-sample target).
    pub coverage_samples: u32,
    /// `FAR_PLANE`: pixel-rate coverage tests every sample in full.
    pub far_plane: bool,
}

impl PipelineKey {
    /// The compute splat's resolve that `plan` needs, if it splats.
    pub fn resolve(plan: &FramePlan) -> Option<Self> {
        let of = Self::of(plan);
        plan.resolve.then_some(Self {
            compute_splat: true,
            culled: false,
            // The resolve shades exactly, whichever way the visibility buffer was filled.
            config: DrawConfig {
                shading: match of.config.shading {
                    Shading::VisibilityBuffer => Shading::Exact,
                    shading => shading,
                },
                ..of.config
            },
            ..of
        })
    }

    /// The draw pipeline `plan` needs (in a splatted frame, for the glyphs the splat leaves
    /// to the draw).
    pub fn of(plan: &FramePlan) -> Self {
        Self {
            orthographic: plan.orthographic,
            config: plan.config,
            target: plan.target,
            reversed_z: plan.reversed_z,
            count_fragments: plan.count_fragments,
            culled: plan.indirect_draw,
            setup_once: plan.setup_once,
            spheres: plan.spheres,
            compact: plan.compact,
            no_caps: plan.no_caps,
            compute_splat: false,
            coverage_samples: plan.coverage_samples,
            far_plane: plan.far_plane,
        }
    }

    /// The specialization constants of the draw's stages.
    fn spec_constants(&self) -> SpecConstants {
        SpecConstants {
            orthographic: self.orthographic as u32,
            textbook: (self.config.intersection == Intersection::Textbook) as u32,
            bounds: self.config.footprint.bounds_mode(),
            corners: self.config.footprint.vertices(),
            fast_normal: (self.config.shading == Shading::FastNormal) as u32,
            culled: self.culled as u32,
            spheres: self.spheres as u32,
            no_caps: self.no_caps as u32,
            compact: self.compact as u32,
            reversed_z: self.reversed_z as u32,
            coverage_samples: self.coverage_samples,
            far_plane: self.far_plane as u32,
            ..SpecConstants::default()
        }
    }
}

/// What the compute splat's pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct SplatKey {
    pub orthographic: bool,
    pub no_caps: bool,
    pub reversed_z: bool,
    pub spheres: bool,
    pub compact: bool,
    /// The benchmark's floors (`SPLAT_FLOOR`; 0 the splat itself).
    pub floor: u32,
    /// `SPLAT_MAX_BOX_PIXELS`.
    pub max_box_pixels: u32,
    /// `COUNT_RAY_CASTS`: the benchmark's counting frames.
    pub count_ray_casts: bool,
    /// `SPLAT_LIST`: a pass of the visible-first splat over the pre-pass's list.
    pub list: bool,
}

impl SplatKey {
    /// The compute splat `plan` needs.
    pub fn of(plan: &FramePlan) -> Self {
        Self {
            orthographic: plan.orthographic,
            no_caps: plan.no_caps,
            reversed_z: plan.reversed_z,
            spheres: plan.spheres,
            compact: plan.compact,
            floor: 0,
            max_box_pixels: plan.splat_max_box_pixels,
            count_ray_casts: plan.count_fragments,
            list: false,
        }
    }

    fn spec_constants(&self) -> SpecConstants {
        SpecConstants {
            orthographic: self.orthographic as u32,
            no_caps: self.no_caps as u32,
            reversed_z: self.reversed_z as u32,
            spheres: self.spheres as u32,
            compact: self.compact as u32,
            splat_floor: self.floor,
            splat_max_box_pixels: self.max_box_pixels,
            count_ray_casts: self.count_ray_casts as u32,
            splat_list: self.list as u32,
            ..SpecConstants::default()
        }
    }
}

/// What one pre-pass pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct CullKey {
    pub orthographic: bool,
    pub culling: Culling,
    pub step: CullStep,
    /// The draw whose set-up the step computes, if it does.
    pub setup: Option<DrawConfig>,
    pub spheres: bool,
    pub compact: bool,
    /// `SAMPLE_GRID`: where the proofs find a pixel's samples.
    pub sample_grid: u32,
    /// `CULL_SELECT`: which glyphs CLASSIFY lists.
    pub select: CullSelect,
    /// `REVERSED_Z`: the visible-first splat's steps read the visibility keys.
    pub reversed_z: bool,
}

impl CullKey {
    /// The pre-pass pipeline of `step` that `plan` needs.
    pub fn of(plan: &FramePlan, step: CullStep) -> Self {
        Self {
            orthographic: plan.orthographic,
            culling: plan.culling,
            step,
            setup: plan.setup_once.then_some(plan.config),
            spheres: plan.spheres,
            compact: plan.compact,
            sample_grid: plan.sample_grid,
            select: CullSelect::All,
            reversed_z: plan.reversed_z,
        }
    }

    /// The specialization constants of the step; with a set-up, the footprint and
    /// intersection of that draw.
    fn spec_constants(&self) -> SpecConstants {
        let config = self.setup.unwrap_or_default();
        SpecConstants {
            orthographic: self.orthographic as u32,
            cull_frustum: self.culling.frustum as u32,
            cull_pixel_centres: self.culling.pixel_centres as u32,
            cull_step: self.step as u32,
            cull_occlusion: self.culling.occlusion as u32,
            cull_setup: self.setup.is_some() as u32,
            textbook: (config.intersection == Intersection::Textbook) as u32,
            bounds: config.footprint.bounds_mode(),
            corners: config.footprint.vertices(),
            spheres: self.spheres as u32,
            compact: self.compact as u32,
            sample_grid: self.sample_grid,
            cull_select: self.select as u32,
            reversed_z: self.reversed_z as u32,
            ..SpecConstants::default()
        }
    }
}

/// The SPIR-V of the two stages for `key`, the fragment stage writing the normal and ID
/// attachments when `aux_outputs`. The benchmark's baselines exist only with the `research`
/// feature.
fn stage_code(key: &PipelineKey, aux_outputs: bool) -> Result<(&'static [u8], &'static [u8])> {
    let config = &key.config;
    let (vertex, fragment) = match (config.geometry, config.shading) {
        (Geometry::Impostor, Shading::Exact | Shading::FastNormal) if key.compute_splat => {
            (shaders::RESOLVE_VERT, shaders::RESOLVE_FRAG)
        }
        (Geometry::Impostor, Shading::Exact | Shading::FastNormal) if key.setup_once => (
            shaders::ELLIPSOID_SETUP_ONCE_VERT,
            shaders::ELLIPSOID_SETUP_ONCE_FRAG,
        ),
        (Geometry::Impostor, Shading::Exact | Shading::FastNormal) => {
            (shaders::ELLIPSOID_VERT, shaders::ELLIPSOID_FRAG)
        }
        #[cfg(feature = "research")]
        (Geometry::Impostor, Shading::FlatDepth) => {
            (shaders::ELLIPSOID_VERT, shaders::ELLIPSOID_FLAT_DEPTH_FRAG)
        }
        #[cfg(feature = "research")]
        (Geometry::Impostor, Shading::VisibilityBuffer) => {
            (shaders::ELLIPSOID_VERT, shaders::ELLIPSOID_VISIBILITY_FRAG)
        }
        #[cfg(feature = "research")]
        (Geometry::Impostor, Shading::FlatFill) => {
            (shaders::ELLIPSOID_VERT, shaders::FLAT_FILL_FRAG)
        }
        #[cfg(feature = "research")]
        (Geometry::Mesh(_), _) => (shaders::MESH_VERT, shaders::MESH_FRAG),
        #[cfg(feature = "research")]
        (Geometry::BoxProxy, _) => (shaders::BOX_VERT, shaders::ELLIPSOID_FRAG),
        #[cfg(not(feature = "research"))]
        _ => {
            return Err(Error::invalid(
                "draw configuration",
                format!("{config:?} is a benchmark baseline: build with the `research` feature"),
            ))
        }
    };
    Ok((vertex, fragment.pick(aux_outputs, key.count_fragments)))
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
    let config = key.config;
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
    // Multisampled: either every sample runs the fragment shader at its own position
    // (gl_FragCoord is the sample's), so coverage and depth are exact per sample; or it runs
    // once per pixel and writes the exact coverage of each sample position in gl_SampleMask
    // (`COVERAGE_SAMPLES`), with one depth per pixel.
    let per_sample = target.multisampled() && key.coverage_samples == 1;
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(target.samples)
        .sample_shading_enable(per_sample)
        .min_sample_shading(1.0);
    // Reversed Z: larger is nearer; standard Z: smaller. Flat fill tests nothing, and the
    // visibility-buffer draw has no depth attachment (its atomics keep the nearest hit).
    let depth_on = !matches!(
        config.shading,
        Shading::FlatFill | Shading::VisibilityBuffer
    ) || config.geometry != Geometry::Impostor;
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

/// The compute splat's pipeline for `key` (`glsl/splat.comp`); the caller owns it.
pub(crate) fn create_splat_pipeline(
    device: &ash::Device,
    cache: vk::PipelineCache,
    layout: vk::PipelineLayout,
    key: SplatKey,
) -> Result<vk::Pipeline> {
    let constants = key.spec_constants();
    create_compute_pipeline(device, cache, layout, shaders::SPLAT_COMP, &constants)
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
