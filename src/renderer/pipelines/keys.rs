//! What each pipeline is specialised for, derived from the frame plan in this one place:
//! the draw's and the resolve's graphics pipelines, the compute splat's and the pre-pass
//! steps', and the specialization constants of each (`SpecConstants` in `src/gpu_layout.rs`).

use crate::culling::Culling;
use crate::footprint::Footprint;
use crate::gpu_layout::SpecConstants;
use crate::research::{Baseline, Research};

use super::super::plan::FramePlan;
use super::super::prepass::steps::{CullSelect, CullStep, TiledStep};

/// What a graphics pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    pub orthographic: bool,
    /// The polygon drawn (the plan's choice; a baseline may fix another).
    pub footprint: Footprint,
    /// Index of the renderer's `Target` the pipeline draws into.
    pub target: usize,
    /// Reversed Z (compare `GREATER`, `depth_less`) or standard (`LESS`, `depth_greater`).
    pub reversed_z: bool,
    /// Fragment shaders count shaded pixels into binding 1 (`research`).
    pub count_fragments: bool,
    /// The vertex stage reads instance indices compacted by the culling pre-pass.
    pub culled: bool,
    /// The impostor stages read the set-up the pre-pass computed (`SETUP_ONCE`); the resolve
    /// the set-up the splat stored (`SPLAT_SETUP_ONCE`).
    pub setup_once: bool,
    /// Instances are in the compact format (`COMPACT`).
    pub compact: bool,
    /// Nothing reaches in front of the near plane (`NO_CAPS`).
    pub no_caps: bool,
    /// The compute splat's resolve instead of the instanced draw.
    pub resolve: bool,
    /// `COVERAGE_SAMPLES`: shaded once per pixel with this many samples tested (1: each
    /// sample shaded on its own, or a single-sample target).
    pub coverage_samples: u32,
    /// `FAR_PLANE`: pixel-rate coverage tests every sample in full.
    pub far_plane: bool,
    /// A benchmark baseline drawn instead of the impostor (`research`).
    pub baseline: Option<Baseline>,
}

impl PipelineKey {
    /// The draw pipeline `plan` needs (in a splatted frame, for the glyphs the splat leaves
    /// to the draw).
    pub fn draw(plan: &FramePlan, research: &Research) -> Self {
        Self {
            orthographic: plan.orthographic,
            footprint: plan.footprint,
            target: plan.target,
            reversed_z: plan.reversed_z,
            count_fragments: research.count_fragments(),
            culled: plan.indirect_draw(),
            setup_once: plan.setup_once(),
            compact: plan.compact,
            no_caps: plan.no_caps,
            resolve: false,
            coverage_samples: plan.coverage_samples,
            far_plane: plan.far_plane,
            baseline: plan.baseline,
        }
    }

    /// The resolve `plan` needs, if it resolves: the shipped exact shading, whichever way
    /// the visibility buffer was filled.
    pub fn resolve(plan: &FramePlan, research: &Research) -> Option<Self> {
        plan.resolves().then(|| Self {
            resolve: true,
            culled: false,
            setup_once: plan.path.splat().is_some_and(|s| s.setup_once),
            baseline: None,
            ..Self::draw(plan, research)
        })
    }

    /// The specialization constants of the draw's stages.
    pub fn spec_constants(&self) -> SpecConstants {
        let mut constants = SpecConstants {
            orthographic: self.orthographic as u32,
            corners: self.footprint.vertices(),
            culled: self.culled as u32,
            no_caps: self.no_caps as u32,
            compact: self.compact as u32,
            reversed_z: self.reversed_z as u32,
            coverage_samples: self.coverage_samples,
            far_plane: self.far_plane as u32,
            splat_setup_once: (self.resolve && self.setup_once) as u32,
            ..SpecConstants::default()
        };
        if let Some(baseline) = self.baseline {
            baseline.specialize(self.footprint, &mut constants);
        }
        constants
    }
}

/// What the compute splat's pipeline is specialised for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct SplatKey {
    pub orthographic: bool,
    pub no_caps: bool,
    pub reversed_z: bool,
    pub compact: bool,
    /// The benchmark's floors (`SPLAT_FLOOR`; 0 the splat itself).
    pub floor: u32,
    /// `SPLAT_MAX_BOX_PIXELS`.
    pub max_box_pixels: u32,
    /// `COUNT_RAY_CASTS`: the benchmark's counting frames.
    pub count_ray_casts: bool,
    /// `SPLAT_LIST` and `CULL_SELECT`: a pass of the visible-first splat over the pre-pass's
    /// list of the glyphs it names (the second pass, `Rest`, skips the tiles the first hides).
    pub list: Option<CullSelect>,
    /// `SPLAT_SETUP_ONCE`: the splat stores each glyph's shading set-up for the resolve.
    pub setup_once: bool,
    /// A step of the benchmark's tiled splat (`research/tiled_splat.comp`) instead.
    pub tiled: Option<TiledStep>,
}

impl SplatKey {
    /// The compute splat `plan` needs (a whole pass over the chunk).
    pub fn of(plan: &FramePlan, research: &Research) -> Self {
        Self {
            orthographic: plan.orthographic,
            no_caps: plan.no_caps,
            reversed_z: plan.reversed_z,
            compact: plan.compact,
            floor: research.splat_floor(),
            max_box_pixels: plan.path.splat().map_or(0, |s| s.max_box_pixels),
            count_ray_casts: research.count_fragments(),
            list: None,
            setup_once: plan.path.splat().is_some_and(|s| s.setup_once),
            tiled: None,
        }
    }

    /// Its specialization constants.
    pub fn spec_constants(&self) -> SpecConstants {
        SpecConstants {
            orthographic: self.orthographic as u32,
            no_caps: self.no_caps as u32,
            reversed_z: self.reversed_z as u32,
            compact: self.compact as u32,
            splat_floor: self.floor,
            splat_max_box_pixels: self.max_box_pixels,
            count_ray_casts: self.count_ray_casts as u32,
            splat_list: self.list.is_some() as u32,
            cull_select: self.list.unwrap_or_default() as u32,
            splat_setup_once: self.setup_once as u32,
            cull_step: self
                .tiled
                .map_or(SpecConstants::default().cull_step, |s| s as u32),
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
    /// The set-up computed once for the draw, if it is: the draw's footprint and baseline.
    pub setup: Option<(Footprint, Option<Baseline>)>,
    pub compact: bool,
    /// `SAMPLE_GRID`: where the proofs find a pixel's samples.
    pub sample_grid: u32,
    /// `CULL_SELECT`: which glyphs CLASSIFY lists.
    pub select: CullSelect,
    /// `REVERSED_Z`: the visible-first splat's steps read the visibility keys.
    pub reversed_z: bool,
}

impl CullKey {
    /// The pre-pass pipeline of `step` that `plan` needs, listing what `select` picks with
    /// `culling`.
    pub fn of(plan: &FramePlan, step: CullStep, select: CullSelect, culling: Culling) -> Self {
        Self {
            orthographic: plan.orthographic,
            culling,
            step,
            setup: plan.setup_once().then_some((plan.footprint, plan.baseline)),
            compact: plan.compact,
            sample_grid: plan.sample_grid,
            select,
            reversed_z: plan.reversed_z,
        }
    }

    /// The specialization constants of the step; with a set-up, the footprint (and a
    /// baseline's intersection) of that draw.
    pub fn spec_constants(&self) -> SpecConstants {
        let mut constants = SpecConstants {
            orthographic: self.orthographic as u32,
            cull_frustum: self.culling.frustum as u32,
            cull_pixel_centres: self.culling.pixel_centres as u32,
            cull_step: self.step as u32,
            cull_occlusion: self.culling.occlusion as u32,
            cull_setup: self.setup.is_some() as u32,
            compact: self.compact as u32,
            sample_grid: self.sample_grid,
            cull_select: self.select as u32,
            reversed_z: self.reversed_z as u32,
            ..SpecConstants::default()
        };
        if let Some((footprint, baseline)) = self.setup {
            constants.corners = footprint.vertices();
            if let Some(baseline) = baseline {
                baseline.specialize(footprint, &mut constants);
            }
        }
        constants
    }
}
