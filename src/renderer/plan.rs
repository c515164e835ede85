//! The frame plan: every decision a frame needs -- its path, the footprint, the shader
//! variants, how a multisampled target is culled and shaded -- made once from the scene, the
//! settings, the target and the camera (and, for the path, what the renderer measured), and
//! then only read. The pipeline keys and specialization constants are derived from it in one
//! place (`pipelines/keys.rs`).

use ash::vk;

use crate::camera::Camera;
use crate::culling::Culling;
use crate::error::{Error, Result};
use crate::footprint::Footprint;
use crate::gpu_layout::{visibility_bytes, ShadingRecord};
use crate::instances::InstanceFormat;
use crate::path::{DrawPath, FramePath, HiddenLayers, PathKind, PlanMode, SplatPath};
use crate::research::Baseline;
use crate::settings::Settings;
use crate::target::Target;

use super::estimate::{first_guess, Sizes};
use super::learning::{PlanLearning, SceneClass};
use super::plan_reason::{DrawReason, PlanReason};
use super::uploaded::UploadedScene;

/// The largest mean projected glyph area (square pixels) for which the pre-pass sets up the
/// impostors once. On lavapipe the fragment stage's record loads cost more than the flat
/// varyings they replace once glyphs cover more than a few pixels (`docs/culling.md`).
pub const SETUP_ONCE_MAX_AREA_PX: f64 = 12.0;

/// The most pixel centres a glyph's box may hold for the compute splat to walk it; larger
/// glyphs are drawn in the same frame. One invocation walks each glyph, so a much larger one
/// would hold up its workgroup. Chosen by measuring 1,024, 4,096 and 16,384 at 50,000 glyphs
/// of 946 px^2 on average: the figures are in `docs/compute-splat.md`.
pub const SPLAT_MAX_BOX_PIXELS: u32 = 4096;

/// The most glyphs per image pixel for which the compute splat sets glyphs up once for its
/// resolve: each glyph with a hit then stores a 128-byte record, and each resolved pixel reads
/// one instead of setting its glyph up again. A conservative limit from lavapipe runs
/// (2026-11-28, 1920x1080, `docs/deep-scenes.md`): the plain splat took a quarter to a third
/// less on the clouds of 10,000 and 100,000 2-pixel and 1,000 to 10,000 16-pixel glyphs, its
/// resolve a quarter to a third less on `lattice`, and a million 2-pixel glyphs read 7 % slower
/// (within the noise), where nearly as many stores as pixels are expected to outweigh it.
pub const SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL: f64 = 0.25;

/// The most chunks a splatted frame may have: each chunk resolves over every marked tile.
pub const MAX_SPLAT_CHUNKS: u32 = 8;

/// The most instances whose set-up records fit the 128 MiB storage-buffer range every Vulkan
/// device supports; larger scenes set up in the vertex stage.
pub const MAX_SETUP_ONCE_INSTANCES: u32 = (1 << 27) / size_of::<ShadingRecord>() as u32;

/// What one frame does, decided once (see [`crate::EllipsoidRenderer::plan`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
///
/// **The frame plan.** `plan(&camera)` returns the `FramePlan`  a frame
/// with that camera gets, every decision made once: `path` (a `FramePath`: the draw with the
/// culling it does and whether it sets glyphs up once, or the splat with what it does about
/// hidden layers -- `SplatAll`, `StampShown`, `VisibleFirst { rest }` --, the largest box it
/// walks and whether it sets glyphs up once for its resolve; no invalid combination can be
/// written), `reason` (why: the only path, fixed, the first
/// guess, exploring, or measured, design §5.8), `candidates()`, `footprint` (design §5.1), `mean_area_px` (the
/// sampled glyphs' mean projected area, if any is on screen), `depth_complexity` and
/// `hidden_area_px` (about how many glyphs deep the scene lies where it covers the image, and
/// the area per glyph it is expected to hide, design §5.7), `sample_grid` (where the culling proofs find
/// a pixel's samples, design §5.3), `spheres`, `no_caps`, `compact`, `orthographic`, `reversed_z`,
/// `coverage_samples` and `far_plane` ([`crate::Target`]); `prepass()`, `culling()` and `setup_once()` read
/// the path. The pipeline keys and specialization constants are derived from it in one place
/// (`pipelines/keys.rs`). A camera the renderer refuses, or an orthographic camera with a
/// baseline that supports perspective only, is an error. The path depends on the frames recorded
/// before (the camera of the view's last pre-pass and of its last stamping one) and on what was
/// measured, so `plan` says what the next `record_prepass` with that camera would do, and
/// `last_plan()` what the last one did. `record_prepass` makes the plan and keeps
/// it with its camera; `record` with the same camera draws with that plan, so the pre-pass and the
/// draw agree even if settings change between them; `record` with another camera makes a new plan
/// and fails if that plan needs a pre-pass. The target is part of the plan: `set_target` applies
/// from the next plan made (by `record_prepass`, or by `record` in a frame without a pre-pass), so
/// call it before `record_prepass`.
pub struct FramePlan {
    /// The exact path the frame takes.
    pub path: FramePath,
    /// Why it takes that path.
    pub reason: PlanReason,
    /// The polygon the draw rasterizes each glyph as (every glyph, or in a splatted frame
    /// those the splat leaves to the draw), from the glyphs' mean size on screen; its
    /// `vertices()` per instance.
    pub footprint: Footprint,
    /// Mean projected area of the sampled glyphs on screen (square pixels), if any is.
    pub mean_area_px: Option<f64>,
    /// About how many glyphs deep the scene lies where it covers the image: the total
    /// projected area of the glyphs on screen (from the size sample) over the image area the
    /// box around them covers.
    pub depth_complexity: Option<f64>,
    /// The area per glyph, in square pixels, the scene is expected to hide: `mean_area_px`
    /// times `1 - 1 / depth_complexity` (0 at or below one layer).
    pub hidden_area_px: Option<f64>,
    /// The shaders leave out the near-plane cap code.
    pub no_caps: bool,
    /// The instances are compact records.
    pub compact: bool,
    /// The camera is orthographic.
    pub orthographic: bool,
    /// Depth is reversed Z.
    pub reversed_z: bool,
    /// Where the pre-pass's pixel-centre and occlusion proofs find a pixel's samples: 1 at its
    /// centre (single-sample targets); R > 1 at the cell centres of a grid R times finer
    /// than the pixels (the standard locations of 2, 4 and 8 samples); 0 anywhere in it.
    pub sample_grid: u32,
    /// On a multisampled target shaded once per pixel, its sample count (the fragment stage
    /// tests each standard sample position and writes `gl_SampleMask`); 1 for single-sample
    /// targets and for sample-rate shading ([`Settings::per_sample_shading`], and devices
    /// without the standard sample locations or counts other than 2 and 4).
    pub coverage_samples: u32,
    /// Shaded once per pixel (`coverage_samples` above 1) with a camera whose finite far
    /// plane may cut a glyph inside a pixel: the coverage then tests every sample in full,
    /// never only the silhouette.
    pub far_plane: bool,
    /// The kinds of path that could serve this frame (the draw always).
    pub(crate) candidates: Candidates,
    /// The kind chosen (the visible-first splat while its first frame only stamps).
    pub(crate) chosen: PathKind,
    /// The frame's scene class where the plan measures, for timing it.
    pub(crate) class: Option<SceneClass>,
    /// Index of the renderer's target drawn into.
    pub(crate) target: usize,
    /// The benchmark baseline drawn instead of the shipped impostor (`research`).
    pub(crate) baseline: Option<Baseline>,
}

/// A set of path kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub(crate) struct Candidates(u8);

impl Candidates {
    fn with(self, kind: PathKind) -> Self {
        Self(self.0 | 1 << kind.index())
    }

    /// Whether `kind` is one.
    pub fn contains(self, kind: PathKind) -> bool {
        self.0 & 1 << kind.index() != 0
    }

    /// The kinds, in order.
    pub fn kinds(self) -> Vec<PathKind> {
        PathKind::ALL
            .into_iter()
            .filter(|&k| self.contains(k))
            .collect()
    }
}

impl FramePlan {
    /// Whether a pre-pass runs before the host's pass (to cull, to set up, to splat, or the
    /// benchmark's visibility-buffer draw).
    pub fn prepass(&self) -> bool {
        match &self.path {
            FramePath::Draw(draw) => draw.prepass() || self.visibility_draw(),
            FramePath::Splat(_) => true,
        }
    }

    /// The culling the pre-pass does (none in a splatted frame: the splat culls as it goes).
    pub fn culling(&self) -> Culling {
        self.path.draw().map_or(Culling::OFF, |d| d.culling)
    }

    /// Whether the pre-pass sets the glyphs up once for the draw.
    pub fn setup_once(&self) -> bool {
        self.path.draw().is_some_and(|d| d.setup_once)
    }

    /// The kinds of path that could serve this frame: the candidates the plan measures.
    pub fn candidates(&self) -> Vec<PathKind> {
        self.candidates.kinds()
    }

    /// Whether a resolve inside the host's pass shades the visibility buffer's pixels.
    pub(crate) fn resolves(&self) -> bool {
        self.path.splat().is_some() || self.visibility_draw()
    }

    /// The benchmark's visibility-buffer draw (`research`).
    pub(crate) fn visibility_draw(&self) -> bool {
        self.baseline.is_some_and(|b| b.visibility_draw())
    }

    /// Whether the draw in the host's pass reads the pre-pass's list through an indirect
    /// command (every pre-pass but the visibility-buffer draw's, which leaves only the
    /// resolve).
    pub(crate) fn indirect_draw(&self) -> bool {
        self.prepass() && !self.visibility_draw()
    }

    /// Vertices per instance of the draw.
    pub(crate) fn vertices(&self) -> u32 {
        self.baseline
            .map_or(self.footprint.vertices(), |b| b.vertices(self.footprint))
    }
}

/// What a plan is made from.
pub(crate) struct PlanInputs<'a> {
    /// The device has the compute splat's features enabled.
    pub compute_splat_features: bool,
    /// The largest visibility buffer in bytes: one storage-buffer binding
    /// (`maxStorageBufferRange`) and one texel view of 8-byte keys (`maxTexelBufferElements`).
    pub max_visibility_bytes: u64,
    /// The device uses the standard sample locations (`standardSampleLocations`).
    pub standard_sample_locations: bool,
    /// The host enabled `sampleRateShading` (shading every sample needs it).
    pub sample_rate_shading: bool,
    /// The renderer can time its frames (timestamps on the queue family).
    pub timed: bool,
    /// Chunks the scene is drawn in (the splat resolves once per chunk).
    pub chunks: u32,
    /// Every chunk's shading records fit their binding and a texel view of the device
    /// (`maxTexelBufferElements`, 8 texels a record), so the splat can set up once.
    pub shading_records_fit: bool,
    /// The last pre-pass recorded had this camera.
    pub still: bool,
    /// A pre-pass since the upload stamped the glyphs its frame showed (with any camera).
    pub shown_stamped: bool,
    pub scene: &'a UploadedScene,
    pub settings: &'a Settings,
    /// What the renderer measured so far.
    pub learning: &'a PlanLearning,
    /// The benchmark's baseline, if one is drawn.
    pub baseline: Option<Baseline>,
    /// The benchmark replaces the splat by a floor (no visible-first splat then).
    pub splat_floor: bool,
    /// The benchmark replaces the splat by its tiled or traced variant, which store no
    /// set-up for the resolve.
    pub splat_variant: bool,
    pub target: (usize, &'a Target),
    pub camera: &'a Camera,
}

/// The scene as a frame's camera sees it, from the size sample.
struct OnScreen {
    mean_area_px: Option<f64>,
    depth_complexity: Option<f64>,
    hidden_area_px: Option<f64>,
}

impl OnScreen {
    fn new(scene: &UploadedScene, camera: &Camera) -> Self {
        let sample = scene.projected_sample(camera);
        // The glyphs on screen (a share of the sample) over the image area the scene covers.
        let image_px = camera.width as f64 * camera.height as f64;
        let depth_complexity = sample.map(|(area, on_screen)| {
            let glyphs = on_screen * scene.count as f64;
            area * glyphs / (scene.screen_share(camera) * image_px).max(1.0)
        });
        let mean_area_px = sample.map(|(area, _)| area);
        Self {
            mean_area_px,
            depth_complexity,
            hidden_area_px: mean_area_px
                .zip(depth_complexity)
                .map(|(area, layers)| area * (1.0 - 1.0 / layers.max(1.0))),
        }
    }
}

impl FramePlan {
    /// Decides everything a frame with `inputs` does. Errors when the configuration cannot
    /// draw with this camera.
    pub(crate) fn new(inputs: PlanInputs) -> Result<Self> {
        let PlanInputs {
            scene,
            settings,
            baseline,
            target: (target_index, target),
            camera,
            ..
        } = inputs;
        let orthographic = camera.is_orthographic();
        if let Some(baseline) = baseline {
            baseline.check_camera(orthographic)?;
        }
        let seen = OnScreen::new(scene, camera);
        let area = seen.mean_area_px.unwrap_or(0.0);
        let footprint = if target.multisampled() {
            Footprint::for_area_multisampled(area)
        } else {
            Footprint::for_area(area, settings.small_glyph_triangles)
        };
        let splat = splat_possible(&inputs, &seen);
        if baseline.is_some_and(|b| b.visibility_draw()) {
            if let Err(why) = splat {
                return Err(Error::invalid(
                    "draw configuration",
                    format!("the visibility-buffer draw needs what the splat needs, but {why}"),
                ));
            }
        }
        let candidates = candidates(&inputs, splat.is_ok());
        let (chosen, reason, class) = choose(&inputs, &seen, candidates, splat)?;
        let path = match chosen {
            PathKind::Draw => FramePath::Draw(draw_path(&inputs, area)),
            kind => FramePath::Splat(splat_path(&inputs, kind)),
        };
        Ok(Self {
            path,
            reason,
            footprint,
            mean_area_px: seen.mean_area_px,
            depth_complexity: seen.depth_complexity,
            hidden_area_px: seen.hidden_area_px,
            no_caps: settings.cap_free_path && scene.beyond_near_plane(camera),
            compact: scene.format == InstanceFormat::Compact,
            orthographic,
            reversed_z: camera.depth.reversed,
            sample_grid: sample_grid(target, inputs.standard_sample_locations),
            coverage_samples: coverage_samples(&inputs)?,
            far_plane: coverage_samples(&inputs)? > 1 && camera.depth.far.is_some(),
            candidates,
            chosen,
            class,
            target: target_index,
            baseline,
        })
    }
}

/// Whether the compute splat can serve the frame, or the first reason it cannot: a
/// baseline is drawn, the device lacks its features, the target is multisampled or its depth
/// not float32 (the keys order float32 depths, and the draw's depth test must break ties the
/// same way), the visibility buffer exceeds one binding, too many chunks resolve, or nothing
/// is on screen.
fn splat_possible(inputs: &PlanInputs, seen: &OnScreen) -> std::result::Result<(), DrawReason> {
    let (_, target) = inputs.target;
    let camera = inputs.camera;
    let float_depth = matches!(
        target.depth_format(),
        vk::Format::D32_SFLOAT | vk::Format::D32_SFLOAT_S8_UINT
    );
    let visibility_fits =
        visibility_bytes(camera.width, camera.height) <= inputs.max_visibility_bytes;
    let visibility_draw = inputs.baseline.is_some_and(|b| b.visibility_draw());
    [
        (
            inputs.baseline.is_some() && !visibility_draw,
            DrawReason::Baseline,
        ),
        (!inputs.compute_splat_features, DrawReason::MissingFeatures),
        (target.multisampled(), DrawReason::Multisampled),
        (!float_depth, DrawReason::DepthFormat),
        (!visibility_fits, DrawReason::ImageTooLarge),
        (inputs.chunks > MAX_SPLAT_CHUNKS, DrawReason::TooManyChunks),
        (
            seen.mean_area_px.is_none() || inputs.scene.count == 0,
            DrawReason::NothingOnScreen,
        ),
    ]
    .into_iter()
    .find_map(|(refused, reason)| refused.then_some(reason))
    .map_or(Ok(()), Err)
}

/// The kinds of path that can serve the frame: the draw always; the splat where it can run;
/// the visible-first splat besides where the scene is one chunk (stamps and lists are per
/// chunk) and occlusion culling is on (its second pass's test is an occlusion test).
fn candidates(inputs: &PlanInputs, splat: bool) -> Candidates {
    let mut candidates = Candidates::default().with(PathKind::Draw);
    if splat && inputs.baseline.is_none() {
        candidates = candidates.with(PathKind::Splat);
        if inputs.chunks == 1 && inputs.settings.culling.occlusion {
            candidates = candidates.with(PathKind::VisibleFirst);
        }
    }
    candidates
}

/// The kind the frame takes, why, and its class where the plan measures.
fn choose(
    inputs: &PlanInputs,
    seen: &OnScreen,
    candidates: Candidates,
    splat: std::result::Result<(), DrawReason>,
) -> Result<(PathKind, PlanReason, Option<SceneClass>)> {
    if let Some(baseline) = inputs.baseline {
        let reason = PlanReason::Only(if baseline.visibility_draw() {
            DrawReason::Baseline
        } else {
            splat.err().unwrap_or(DrawReason::Baseline)
        });
        return Ok((PathKind::Draw, reason, None));
    }
    if let Err(why) = splat {
        return Ok((PathKind::Draw, PlanReason::Only(why), None));
    }
    let kinds = candidates.kinds();
    let sizes = Sizes {
        glyphs: inputs.scene.count,
        mean_area_px: seen.mean_area_px.unwrap_or(0.0),
        hidden_area_px: seen.hidden_area_px.unwrap_or(0.0),
        still: inputs.still,
    };
    let (guess, why) = first_guess(&sizes, &kinds);
    let estimated = (guess, PlanReason::Estimated(why));
    Ok(match inputs.settings.plan {
        PlanMode::Fixed(kind) => {
            // The visible-first splat of a scene in several chunks is the plain splat.
            let kind = match kind {
                PathKind::VisibleFirst if !candidates.contains(kind) => PathKind::Splat,
                kind => kind,
            };
            (kind, PlanReason::Fixed, None)
        }
        PlanMode::Estimate => (estimated.0, estimated.1, None),
        PlanMode::Measure if !inputs.timed => (estimated.0, estimated.1, None),
        PlanMode::Measure => {
            let (_, target) = inputs.target;
            let camera = inputs.camera;
            let class = inputs.learning.classify(
                inputs.scene.count,
                sizes.mean_area_px,
                seen.depth_complexity.unwrap_or(1.0),
                camera.width as u64 * camera.height as u64,
                target.samples.as_raw(),
                inputs.still,
            );
            let (kind, reason) = inputs.learning.choose(&class, &kinds, estimated);
            (kind, reason, Some(class))
        }
    })
}

/// The draw's path: the culling the settings ask for (occlusion only over float32 depth,
/// whose rounding its 1e-4 depth gap survives), and set-up once for glyphs of a few pixels
/// where the records fit; neither where the draw's stages do not go through the pre-pass
/// (a baseline whose coverage the proofs do not assume) or nothing is uploaded.
fn draw_path(inputs: &PlanInputs, mean_area_px: f64) -> DrawPath {
    let (_, target) = inputs.target;
    let settings = inputs.settings;
    let count = inputs.scene.count;
    let through_prepass = count > 0
        && inputs
            .baseline
            .is_none_or(|b| b.through_prepass() && !b.visibility_draw());
    if !through_prepass {
        return DrawPath {
            culling: Culling::OFF,
            setup_once: false,
        };
    }
    let culling = Culling {
        occlusion: settings.culling.occlusion && target.depth_format() == vk::Format::D32_SFLOAT,
        ..settings.culling
    };
    let setup_once = settings.setup_once
        && inputs.baseline.is_none_or(|b| b.setup_once_allowed())
        && inputs.scene.count > 0
        && mean_area_px > 0.0
        && mean_area_px <= SETUP_ONCE_MAX_AREA_PX
        && inputs.shading_records_fit;
    DrawPath {
        culling,
        setup_once,
    }
}

/// The splat's path for `kind`: the visible-first splat (its first frame since the upload
/// stamps what it shows; every later one splats first what the last stamped, whatever the
/// camera, and stamps again), else every glyph; set up once where the settings ask, the
/// records fit and the glyphs are few enough for the image
/// ([`SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL`]).
fn splat_path(inputs: &PlanInputs, kind: PathKind) -> SplatPath {
    let image_px = inputs.camera.width as f64 * inputs.camera.height as f64;
    let visible_first = kind == PathKind::VisibleFirst
        && inputs.chunks == 1
        && inputs.settings.culling.occlusion
        && !inputs.splat_floor;
    let hidden = match (visible_first, inputs.shown_stamped) {
        (false, _) => HiddenLayers::SplatAll,
        (true, false) => HiddenLayers::StampShown,
        (true, true) => HiddenLayers::VisibleFirst {
            rest: Culling {
                occlusion: false,
                ..inputs.settings.culling
            },
        },
    };
    SplatPath {
        hidden,
        max_box_pixels: SPLAT_MAX_BOX_PIXELS,
        setup_once: inputs.settings.setup_once
            && inputs.shading_records_fit
            && inputs.scene.count as f64 <= SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL * image_px
            && !inputs.splat_floor
            && !inputs.splat_variant,
    }
}

/// Where the culling proofs find a pixel's samples: the standard locations of 2, 4 and 8
/// samples are odd multiples of 1 / (2 R); those of 16 include 0 and 1/2, on no such grid.
fn sample_grid(target: &Target, standard_sample_locations: bool) -> u32 {
    match target.samples {
        vk::SampleCountFlags::TYPE_1 => 1,
        vk::SampleCountFlags::TYPE_2
        | vk::SampleCountFlags::TYPE_4
        | vk::SampleCountFlags::TYPE_8
            if standard_sample_locations =>
        {
            target.samples.as_raw()
        }
        _ => 0,
    }
}

/// Pixel-rate shading needs the sample positions in the shader: the standard ones, written
/// out there for 2 and 4 samples. Shading every sample instead needs `sampleRateShading`.
fn coverage_samples(inputs: &PlanInputs) -> Result<u32> {
    let (_, target) = inputs.target;
    let samples = match target.samples {
        vk::SampleCountFlags::TYPE_2 | vk::SampleCountFlags::TYPE_4
            if inputs.standard_sample_locations && !inputs.settings.per_sample_shading =>
        {
            target.samples.as_raw()
        }
        _ => 1,
    };
    if target.multisampled() && samples == 1 && !inputs.sample_rate_shading {
        return Err(Error::invalid(
            "multisampled target",
            "shading every sample needs sampleRateShading, which the host did not enable \
             (HostDevice::enabled_features); with 2 or 4 samples and the standard sample \
             locations, Settings::per_sample_shading off shades once per pixel without it",
        ));
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::super::estimate::SPLAT_MAX_MEAN_AREA_PX;
    use super::super::plan_reason::Guess;
    use super::*;
    use crate::instances::{pack_scene, Placement};
    use crate::path::PathKind;
    use crate::target::Pass;
    use crate::{Ellipsoid, Scene};
    use glam::{DQuat, DVec3};

    /// 60,000 glyphs in a 10-unit cube seen from 40 units at 640x480, semi-axes `scale`
    /// times (0.02, 0.015, 0.01) (about a pixel at 1); with `big`, the first is a sphere of
    /// radius 4 (about 10,000 pixels).
    fn scene_of(big: bool, scale: f64) -> (UploadedScene, Camera) {
        let mut glyphs: Vec<Ellipsoid> = (0..60_000)
            .map(|k| {
                let t = k as f64;
                let centre = DVec3::new(
                    (t * 0.618_034).fract() * 10.0 - 5.0,
                    (t * 0.414_214).fract() * 10.0 - 5.0,
                    (t * 0.732_051).fract() * 10.0 - 5.0,
                );
                let radii = DVec3::new(0.02, 0.015, 0.01) * scale;
                Ellipsoid::new(centre, radii, DQuat::IDENTITY, None).unwrap()
            })
            .collect();
        if big {
            glyphs[0] =
                Ellipsoid::new(DVec3::ZERO, DVec3::splat(4.0), DQuat::IDENTITY, None).unwrap();
        }
        let scene = Scene::new(glyphs);
        let packed = pack_scene(&scene, InstanceFormat::Full, Placement::of(&scene)).unwrap();
        let camera =
            Camera::look_at(DVec3::new(0.0, 0.0, 40.0), DVec3::ZERO, 45.0, 1.0, 640, 480).unwrap();
        (UploadedScene::new(&scene, &packed, u32::MAX), camera)
    }

    fn target(samples: vk::SampleCountFlags) -> Target {
        Target {
            pass: Pass::Dynamic {
                color_formats: vec![vk::Format::R8G8B8A8_SRGB],
                depth_format: vk::Format::D32_SFLOAT,
            },
            samples,
            aux_outputs: false,
        }
    }

    /// The plan of a frame; `history` is (still, shown stamped).
    fn plan_with(
        scene: &UploadedScene,
        camera: &Camera,
        samples: vk::SampleCountFlags,
        features: bool,
        settings: &Settings,
        history: (bool, bool),
        learning: &PlanLearning,
    ) -> FramePlan {
        let target = target(samples);
        FramePlan::new(PlanInputs {
            compute_splat_features: features,
            max_visibility_bytes: 1 << 27,
            standard_sample_locations: true,
            sample_rate_shading: true,
            timed: true,
            chunks: 1,
            shading_records_fit: true,
            still: history.0,
            shown_stamped: history.1,
            scene,
            settings,
            learning,
            baseline: None,
            splat_floor: false,
            splat_variant: false,
            target: (0, &target),
            camera,
        })
        .unwrap()
    }

    fn plan(
        scene: &UploadedScene,
        camera: &Camera,
        samples: vk::SampleCountFlags,
        features: bool,
        settings: &Settings,
    ) -> FramePlan {
        let learning = PlanLearning::default();
        plan_with(
            scene,
            camera,
            samples,
            features,
            settings,
            (false, false),
            &learning,
        )
    }

    fn mode(plan: PlanMode) -> Settings {
        Settings {
            plan,
            ..Settings::default()
        }
    }

    /// Multisampled targets are shaded once per pixel with the sample count's exact coverage
    /// by default, per sample when the settings ask for it or the sample count has no
    /// positions in the shader; single-sample targets never test coverage.
    #[test]
    fn multisampled_targets_shade_once_per_pixel_unless_asked_otherwise() {
        let (scene, camera) = scene_of(false, 1.0);
        let shipped = Settings::default();
        let per_sample = Settings {
            per_sample_shading: true,
            ..shipped
        };
        use vk::SampleCountFlags as S;
        for (samples, settings, expected) in [
            (S::TYPE_1, &shipped, 1),
            (S::TYPE_1, &per_sample, 1),
            (S::TYPE_2, &shipped, 2),
            (S::TYPE_4, &shipped, 4),
            (S::TYPE_4, &per_sample, 1),
            (S::TYPE_8, &shipped, 1),
        ] {
            let plan = plan(&scene, &camera, samples, true, settings);
            assert_eq!(plan.coverage_samples, expected, "{samples:?} {settings:?}");
        }
    }

    /// Multisampled frames draw, keep every culling (proved at their samples' grid) and
    /// draw one or two triangles per glyph.
    #[test]
    fn multisampled_frames_draw_and_cull_at_their_samples_with_few_primitives() {
        use vk::SampleCountFlags as S;
        let shipped = Settings::default();
        for (scale, single, multi) in [
            (1.0, Footprint::OrientedRect, Footprint::Triangle),
            (60.0, Footprint::Hexagon, Footprint::OrientedRect),
        ] {
            let (scene, camera) = scene_of(false, scale);
            for (samples, grid) in [(S::TYPE_2, 2), (S::TYPE_4, 4), (S::TYPE_8, 8)] {
                let plan = plan(&scene, &camera, samples, true, &shipped);
                assert_eq!(plan.sample_grid, grid, "{samples:?}");
                assert_eq!(plan.culling(), Culling::ON, "{samples:?}");
                assert_eq!(plan.footprint, multi, "{samples:?} at {scale}x");
                assert_eq!(plan.reason, PlanReason::Only(DrawReason::Multisampled));
                assert_eq!(plan.candidates(), [PathKind::Draw]);
            }
            let one = plan(&scene, &camera, S::TYPE_1, false, &shipped);
            assert_eq!((one.sample_grid, one.footprint), (1, single));
            let sixteen = plan(&scene, &camera, S::TYPE_16, false, &shipped);
            assert_eq!(sixteen.sample_grid, 0);
        }
    }

    /// The first guess splats many small glyphs and draws few or large ones; a fixed path
    /// holds wherever it can serve the frame; where the splat cannot, the draw says why.
    #[test]
    fn the_first_guess_and_fixed_paths_choose_among_what_can_serve() {
        let one = vk::SampleCountFlags::TYPE_1;
        let estimate = mode(PlanMode::Estimate);
        let (tiny, camera) = scene_of(false, 1.0);
        let splat = plan(&tiny, &camera, one, true, &estimate);
        assert!(splat.path.splat().is_some(), "{splat:?}");
        assert_eq!(splat.reason, PlanReason::Estimated(Guess::SmallGlyphs));
        assert_eq!(splat.candidates(), PathKind::ALL);
        // One glyph of thousands of pixels among them: splatted all the same (the splat
        // leaves that one to the draw).
        let (mixed, camera) = scene_of(true, 1.0);
        assert!(plan(&mixed, &camera, one, true, &estimate)
            .path
            .splat()
            .is_some());
        // Glyphs of thousands of pixels on average: the draw, with its culling.
        let (large, camera) = scene_of(false, 150.0);
        let drawn = plan(&large, &camera, one, true, &estimate);
        assert!(
            drawn.mean_area_px.unwrap() > SPLAT_MAX_MEAN_AREA_PX,
            "{drawn:?}"
        );
        assert_eq!(drawn.reason, PlanReason::Estimated(Guess::LargeGlyphs));
        assert_eq!(drawn.culling(), Culling::ON);
        // Fixed: the draw of small glyphs sets them up once; the splat takes large ones.
        let (_, camera) = scene_of(false, 1.0);
        let fixed_draw = plan(
            &tiny,
            &camera,
            one,
            true,
            &mode(PlanMode::Fixed(PathKind::Draw)),
        );
        assert!(
            fixed_draw.setup_once() && fixed_draw.prepass(),
            "{fixed_draw:?}"
        );
        assert_eq!(fixed_draw.reason, PlanReason::Fixed);
        let (_, camera) = scene_of(false, 150.0);
        let fixed_splat = plan(
            &large,
            &camera,
            one,
            true,
            &mode(PlanMode::Fixed(PathKind::Splat)),
        );
        assert!(fixed_splat.path.splat().is_some() && !fixed_splat.setup_once());
        // Without the host's 64-bit atomics: the draw, whatever is asked.
        let (_, camera) = scene_of(false, 1.0);
        let missing = plan(
            &tiny,
            &camera,
            one,
            false,
            &mode(PlanMode::Fixed(PathKind::Splat)),
        );
        assert!(
            missing.path.draw().is_some_and(|d| d.setup_once),
            "{missing:?}"
        );
        assert_eq!(
            missing.reason,
            PlanReason::Only(DrawReason::MissingFeatures)
        );
        let reason = DrawReason::Multisampled.to_string();
        assert!(reason.contains("per sample"), "{reason}");
    }

    /// The visible-first splat's first frame stamps what it shows and the next starts from
    /// it, the camera still or moving.
    #[test]
    fn visible_first_needs_stamps() {
        let (scene, camera) = scene_of(false, 20.0);
        let one = vk::SampleCountFlags::TYPE_1;
        let fixed = mode(PlanMode::Fixed(PathKind::VisibleFirst));
        let learning = PlanLearning::default();
        let hidden = |history| {
            let plan = plan_with(&scene, &camera, one, true, &fixed, history, &learning);
            plan.path.splat().map(|s| s.hidden)
        };
        for still in [false, true] {
            assert_eq!(hidden((still, false)), Some(HiddenLayers::StampShown));
            assert!(
                matches!(hidden((still, true)), Some(HiddenLayers::VisibleFirst { rest }) if !rest.occlusion && rest.frustum)
            );
        }
        let still = plan_with(&scene, &camera, one, true, &fixed, (true, true), &learning);
        assert_eq!(still.candidates(), PathKind::ALL);
        // Without occlusion culling the second pass has no test: no candidate.
        let no_occlusion = Settings {
            culling: Culling {
                occlusion: false,
                ..Culling::ON
            },
            ..fixed
        };
        let plan = plan_with(
            &scene,
            &camera,
            one,
            true,
            &no_occlusion,
            (true, true),
            &learning,
        );
        assert_eq!(plan.candidates(), [PathKind::Draw, PathKind::Splat]);
        assert_eq!(
            plan.path.splat().map(|s| s.hidden),
            Some(HiddenLayers::SplatAll)
        );
    }

    /// The splat sets glyphs up once where the settings ask and the scene has at most a glyph
    /// per `1 / SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL` image pixels.
    #[test]
    fn the_splat_sets_up_once_for_sparse_enough_scenes() {
        let (scene, camera) = scene_of(false, 20.0);
        let one = vk::SampleCountFlags::TYPE_1;
        let fixed = mode(PlanMode::Fixed(PathKind::Splat));
        let learning = PlanLearning::default();
        let once = |camera: &Camera, settings: &Settings| {
            let plan = plan_with(
                &scene,
                camera,
                one,
                true,
                settings,
                (true, false),
                &learning,
            );
            plan.path.splat().map(|s| s.setup_once)
        };
        // 60,000 glyphs: 640x480 has 5.1 pixels a glyph, 320x240 1.3.
        assert_eq!(once(&camera, &fixed), Some(true));
        let not_asked = Settings {
            setup_once: false,
            ..fixed
        };
        assert_eq!(once(&camera, &not_asked), Some(false));
        let small = Camera {
            width: 320,
            height: 240,
            ..camera
        };
        assert_eq!(once(&small, &fixed), Some(false));
    }

    /// Measuring: the first frames take the first guess; once the class is timed the plan
    /// takes the fastest candidate and says what it measured.
    #[test]
    fn measured_plans_take_the_fastest_candidate() {
        let (scene, camera) = scene_of(false, 20.0);
        let one = vk::SampleCountFlags::TYPE_1;
        let settings = Settings::default();
        let mut learning = PlanLearning::default();
        let first = plan_with(
            &scene,
            &camera,
            one,
            true,
            &settings,
            (false, false),
            &learning,
        );
        assert!(
            matches!(first.reason, PlanReason::Estimated(_)),
            "{first:?}"
        );
        let class = first.class.expect("a measured plan has a class");
        // The draw is twice as fast as the splat on this device, the visible-first splat
        // (whose first frame stamps) four times slower.
        let mut stamped = false;
        for _ in 0..40 {
            let plan = plan_with(
                &scene,
                &camera,
                one,
                true,
                &settings,
                (false, stamped),
                &learning,
            );
            stamped |= plan
                .path
                .splat()
                .is_some_and(|s| s.hidden != HiddenLayers::SplatAll);
            let candidates = plan.candidates();
            let ran = plan.path.timed_kind();
            if let Some(token) = learning.commit(class, &candidates, plan.chosen, ran) {
                let ms = match token.ran {
                    PathKind::Draw => 5.0,
                    PathKind::Splat => 10.0,
                    PathKind::VisibleFirst => 20.0,
                };
                learning.record(token, ms);
            }
        }
        let learned = plan_with(
            &scene,
            &camera,
            one,
            true,
            &settings,
            (false, false),
            &learning,
        );
        assert!(learned.path.draw().is_some(), "{learned:?}");
        match learned.reason {
            PlanReason::Measured(m) => {
                assert_eq!(m.ms, 5.0);
                assert_eq!(m.runner_up, Some((PathKind::Splat, 10.0)));
            }
            other => panic!("not measured: {other:?}"),
        }
        assert!(
            learned.reason.to_string().contains("against splat"),
            "{}",
            learned.reason
        );
        // The estimate ignores what was learned.
        let estimate = plan_with(
            &scene,
            &camera,
            one,
            true,
            &mode(PlanMode::Estimate),
            (false, false),
            &learning,
        );
        assert!(estimate.path.splat().is_some());
    }
}
