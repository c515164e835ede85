//! The frame plan: every decision a frame needs (footprint, culling steps, set-up once,
//! shader variants), made once from the scene, the settings, the target and the camera, and
//! then only read.

use ash::vk;

use crate::camera::Camera;
use crate::culling::Culling;
use crate::draw::{DrawConfig, Footprint, Geometry, Intersection, Shading};
use crate::error::{Error, Result};
use crate::gpu_layout::{visibility_bytes, ShadingRecord};
use crate::instances::InstanceFormat;
use crate::settings::Settings;
use crate::target::Target;

use super::draw_reason::DrawReason;
use super::uploaded::UploadedScene;

/// The largest mean projected glyph area (square pixels) for which the pre-pass sets up the
/// impostors once. On lavapipe the fragment stage's record loads cost more than the flat
/// varyings they replace once glyphs cover more than a few pixels (README, `bench --skip`).
pub const SETUP_ONCE_MAX_AREA_PX: f64 = 12.0;

/// The largest mean projected glyph area (square pixels) for which the compute splat takes
/// the frame. Each glyph whose pixel box holds more than 4,096 pixel centres, or that reaches
/// the eye plane, is drawn instead (`glsl/splat.comp`), and splat frames run no culling
/// steps: scenes of mostly large glyphs keep the draw with its occlusion culling.
pub const SPLAT_MAX_MEAN_AREA_PX: f64 = 1024.0;

/// The most pixel centres a glyph's box may hold for the compute splat to walk it; larger
/// glyphs are drawn in the same frame. One invocation walks each glyph, so a much larger one
/// would hold up its workgroup. Measured at 50,000 glyphs of 946 px^2 on average: 1,024 takes
/// 458-461 ms (many glyphs drawn), 4,096 271-284 ms, 16,384 277-278 ms (README).
pub const SPLAT_MAX_BOX_PIXELS: u32 = 4096;

/// The most chunks a splatted frame may have: each chunk resolves over every marked tile.
pub const MAX_SPLAT_CHUNKS: u32 = 8;

/// The most instances whose set-up records fit the 128 MiB storage-buffer range every Vulkan
/// device supports; larger scenes set up in the vertex stage.
pub const MAX_SETUP_ONCE_INSTANCES: u32 = (1 << 27) / size_of::<ShadingRecord>() as u32;

/// What one frame does, decided once (see [`crate::EllipsoidRenderer::plan`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FramePlan {
    /// How the glyphs are drawn, with the footprint resolved from their size on screen.
    pub config: DrawConfig,
    /// Mean projected area of the sampled glyphs on screen (square pixels), if any is.
    pub mean_area_px: Option<f64>,
    /// About how many glyphs deep the scene lies where it covers the image: the total
    /// projected area of the glyphs on screen (from the size sample) over the image area the
    /// box around them covers.
    pub depth_complexity: Option<f64>,
    /// The area per glyph, in square pixels, the scene is expected to hide: `mean_area_px`
    /// times `1 - 1 / depth_complexity` (0 at or below one layer).
    pub hidden_area_px: Option<f64>,
    /// The culling the pre-pass does.
    pub culling: Culling,
    /// The pre-pass runs (to cull, to set up, to splat, or the benchmark's visibility-buffer
    /// draw).
    pub prepass: bool,
    /// The draw in the host's pass reads the pre-pass's compacted list through an indirect
    /// command (every pre-pass but the visibility-buffer draw's, which leaves only the
    /// resolve).
    pub indirect_draw: bool,
    /// The pre-pass computes each impostor's set-up once for the draw (never together with
    /// the compute splat, which computes the set-up where it needs it).
    pub setup_once: bool,
    /// The shaders take the sphere path.
    pub spheres: bool,
    /// The fragment stage leaves out the near-plane cap code.
    pub no_caps: bool,
    /// The glyphs are splatted by a compute pass into a visibility buffer and shaded by a
    /// resolve over the tiles they touch, instead of drawn (those too large to splat are
    /// drawn in the same frame).
    pub compute_splat: bool,
    /// Why the glyphs are drawn rather than splatted, when they are.
    pub drawn_because: Option<DrawReason>,
    /// The most pixel centres a glyph's box may hold for the compute splat to walk it.
    pub splat_max_box_pixels: u32,
    /// The compute splat stamps the glyphs its finished frame shows, so that the next frame
    /// with the same camera can splat them first (a camera that held still since the last
    /// frame; docs/design.md §5.7).
    pub mark_shown: bool,
    /// The visible-first splat (docs/design.md §5.7): the camera is the last pre-pass's and
    /// the last stamping frame's, so the glyphs that frame showed are splatted first and the
    /// others only where its hits do not hide them.
    pub visible_first: bool,
    /// The culling the visible-first splat's second pass lists its glyphs with (its occlusion
    /// test is the first pass's hits, not the tiles of `culling`).
    pub rest_culling: Culling,
    /// The benchmark's visibility-buffer draw (`Shading::VisibilityBuffer`): the pre-pass
    /// draws every glyph into the visibility buffer, in a pass of its own, and the host's
    /// pass only resolves.
    pub visibility_draw: bool,
    /// A resolve inside the host's pass shades the visibility buffer's pixels (after the
    /// compute splat or the visibility-buffer draw).
    pub resolve: bool,
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
    /// Index of the renderer's target drawn into.
    pub(crate) target: usize,
    /// Fragment shaders count shaded pixels.
    pub(crate) count_fragments: bool,
}

/// What a plan is made from.
pub(crate) struct PlanInputs<'a> {
    /// The device has the compute splat's features enabled.
    pub compute_splat_features: bool,
    /// The device's `maxStorageBufferRange` (the visibility buffer is one binding).
    pub max_storage_buffer_range: u32,
    /// The device uses the standard sample locations (`standardSampleLocations`).
    pub standard_sample_locations: bool,
    /// The host enabled `sampleRateShading` (shading every sample needs it).
    pub sample_rate_shading: bool,
    /// Chunks the scene is drawn in (the splat resolves once per chunk).
    pub chunks: u32,
    /// The last pre-pass recorded had this camera.
    pub still: bool,
    /// The last pre-pass since the upload that stamped the glyphs its frame showed had this
    /// camera.
    pub shown_stamped: bool,
    pub scene: &'a UploadedScene,
    pub settings: &'a Settings,
    pub config: DrawConfig,
    pub count_fragments: bool,
    pub target: (usize, &'a Target),
    pub camera: &'a Camera,
}

impl FramePlan {
    /// Decides everything a frame with `inputs` does. Errors when the configuration cannot
    /// draw with this camera.
    pub(crate) fn new(inputs: PlanInputs) -> Result<Self> {
        let PlanInputs {
            compute_splat_features,
            max_storage_buffer_range,
            standard_sample_locations,
            sample_rate_shading,
            chunks,
            still,
            shown_stamped,
            scene,
            settings,
            mut config,
            count_fragments,
            target: (target_index, target),
            camera,
        } = inputs;
        let orthographic = camera.is_orthographic();
        if orthographic && config.geometry != Geometry::Impostor {
            return Err(Error::invalid(
                "draw configuration",
                format!("{:?} supports perspective cameras only", config.geometry),
            ));
        }
        let sample = scene.projected_sample(camera);
        let mean_area_px = sample.map(|(area, _)| area);
        // The glyphs on screen (a share of the sample) over the image area the scene covers.
        let image_px = camera.width as f64 * camera.height as f64;
        let depth_complexity = sample.map(|(area, on_screen)| {
            let glyphs = on_screen * scene.count as f64;
            area * glyphs / (scene.screen_share(camera) * image_px).max(1.0)
        });
        let hidden_area_px = mean_area_px
            .zip(depth_complexity)
            .map(|(area, layers)| area * (1.0 - 1.0 / layers.max(1.0)));
        // The benchmark's footprint variants measure the draw: only the shipped choice splats.
        let auto_footprint = config.footprint == Footprint::Auto;
        if auto_footprint {
            let area = mean_area_px.unwrap_or(0.0);
            config.footprint = if target.multisampled() {
                Footprint::for_area_multisampled(area)
            } else {
                match Footprint::for_area(area) {
                    Footprint::Triangle if !settings.small_glyph_triangles => {
                        Footprint::OrientedRect
                    }
                    chosen => chosen,
                }
            };
        }
        // Only impostors with the exact hit go through the pre-pass (the culling proofs assume
        // its coverage and depth); set-up once also needs the exact fragment stage.
        let exact_impostor = config.geometry == Geometry::Impostor
            && config.intersection == Intersection::Stable
            && matches!(config.shading, Shading::Exact | Shading::FastNormal);
        let small_glyphs = exact_impostor
            && config.footprint != Footprint::WorldQuad
            && mean_area_px.is_some_and(|area| area <= SETUP_ONCE_MAX_AREA_PX);
        // Occlusion needs float32 depth (its 1e-4 depth gap must survive the depth buffer's
        // rounding). On multisampled targets the pre-pass's proofs cover every sample of a
        // pixel, not only its centre (`sample_grid`).
        let single = !target.multisampled();
        let culling = Culling {
            occlusion: settings.culling.occlusion
                && target.depth_format() == vk::Format::D32_SFLOAT,
            ..settings.culling
        };
        // The compute splat takes scenes of many glyphs, small on average, on devices with its
        // features and single-sample targets: enough glyphs pay for its fixed cost (clearing
        // and resolving), it beats the draw up to its mean size (README), and the glyphs too
        // large for it are drawn in the same frame.
        // What any frame that fills the visibility buffer needs: its features, a single-sample
        // target, a float32 depth attachment (the keys order float32 depths; the draw's test
        // compares them in the attachment's format, which must then be float32 too to break
        // ties the same way), a buffer within one binding and few enough chunks (each
        // resolves over every marked tile).
        let visibility_possible = compute_splat_features
            && single
            && matches!(
                target.depth_format(),
                vk::Format::D32_SFLOAT | vk::Format::D32_SFLOAT_S8_UINT
            )
            && visibility_bytes(camera.width, camera.height) <= max_storage_buffer_range as u64
            && chunks <= MAX_SPLAT_CHUNKS;
        let visibility_draw = config.shading == Shading::VisibilityBuffer;
        if visibility_draw && (!visibility_possible || config.geometry != Geometry::Impostor) {
            return Err(Error::invalid(
                "draw configuration",
                "the visibility-buffer draw needs 64-bit buffer atomics, a single-sample target \
                 with float32 depth, a visibility buffer within one storage binding and at most \
                 MAX_SPLAT_CHUNKS chunks",
            ));
        }
        // The first condition of the splat the frame does not meet, if any.
        let drawn_because = [
            (!settings.compute_splat, DrawReason::SplatOff),
            (!(exact_impostor && auto_footprint), DrawReason::Baseline),
            (!compute_splat_features, DrawReason::MissingFeatures),
            (!single, DrawReason::Multisampled),
            (
                !matches!(
                    target.depth_format(),
                    vk::Format::D32_SFLOAT | vk::Format::D32_SFLOAT_S8_UINT
                ),
                DrawReason::DepthFormat,
            ),
            (
                visibility_bytes(camera.width, camera.height) > max_storage_buffer_range as u64,
                DrawReason::ImageTooLarge,
            ),
            (chunks > MAX_SPLAT_CHUNKS, DrawReason::TooManyChunks),
            (
                mean_area_px.is_none() || scene.count == 0,
                DrawReason::NothingOnScreen,
            ),
            (
                mean_area_px.is_some_and(|area| area > SPLAT_MAX_MEAN_AREA_PX),
                DrawReason::GlyphsTooLarge,
            ),
            (
                scene.count < settings.compute_splat_min_glyphs,
                DrawReason::TooFewGlyphs,
            ),
        ]
        .into_iter()
        .find_map(|(refused, reason)| refused.then_some(reason));
        let compute_splat = drawn_because.is_none();

        // What the last frame showed is splatted first where the frame is one chunk (stamps
        // and lists are per chunk), occlusion culling is on (the second pass's test is an
        // occlusion test), the glyphs hide enough, and the camera holds still: a frame whose
        // camera is the last one's stamps what it shows, the next with the same camera
        // splats that first.
        let mark_shown = still
            && compute_splat
            && chunks == 1
            && settings.visible_first
            && settings.culling.occlusion
            && hidden_area_px.is_some_and(|hidden| hidden >= settings.visible_first_min_hidden_px);
        let visible_first = mark_shown && shown_stamped;
        // Otherwise such glyphs are set up once by the pre-pass, where the records fit.
        let setup_once = settings.setup_once
            && !compute_splat
            && small_glyphs
            && (1..=MAX_SETUP_ONCE_INSTANCES).contains(&scene.count);
        let draws_through_prepass = config.geometry == Geometry::Impostor
            && config.intersection == Intersection::Stable
            && config.shading != Shading::FlatFill;
        let prepass = scene.count > 0
            && (visibility_draw
                || draws_through_prepass && (culling.any() || setup_once || compute_splat));
        // Pixel-rate shading needs the sample positions in the shader: the standard ones,
        // written out there for 2 and 4 samples.
        let coverage_samples = match target.samples {
            vk::SampleCountFlags::TYPE_2 | vk::SampleCountFlags::TYPE_4
                if standard_sample_locations && !settings.per_sample_shading =>
            {
                target.samples.as_raw()
            }
            _ => 1,
        };
        if target.multisampled() && coverage_samples == 1 && !sample_rate_shading {
            return Err(Error::invalid(
                "multisampled target",
                "shading every sample needs sampleRateShading, which the host did not enable \
                 (HostDevice::enabled_features); with 2 or 4 samples and the standard sample \
                 locations, Settings::per_sample_shading off shades once per pixel without it",
            ));
        }
        Ok(Self {
            compute_splat,
            drawn_because,
            splat_max_box_pixels: SPLAT_MAX_BOX_PIXELS,
            mark_shown,
            visible_first,
            rest_culling: Culling {
                occlusion: false,
                ..settings.culling
            },
            visibility_draw,
            resolve: compute_splat || visibility_draw,
            indirect_draw: prepass && !visibility_draw,
            config,
            mean_area_px,
            depth_complexity,
            hidden_area_px,
            // The splat culls as it goes (off-screen glyphs, empty pixel boxes): the culling
            // steps would only add dispatches.
            culling: if compute_splat || visibility_draw {
                Culling::OFF
            } else {
                culling
            },
            prepass,
            setup_once,
            spheres: settings.sphere_path && scene.all_spheres,
            no_caps: settings.cap_free_path && scene.beyond_near_plane(camera),
            compact: scene.format == InstanceFormat::Compact,
            orthographic,
            reversed_z: camera.depth.reversed,
            // The standard locations of 2, 4 and 8 samples are odd multiples of 1 / (2 R);
            // those of 16 include 0 and 1/2, on no such grid.
            sample_grid: match target.samples {
                vk::SampleCountFlags::TYPE_1 => 1,
                vk::SampleCountFlags::TYPE_2
                | vk::SampleCountFlags::TYPE_4
                | vk::SampleCountFlags::TYPE_8
                    if standard_sample_locations =>
                {
                    target.samples.as_raw()
                }
                _ => 0,
            },
            coverage_samples,
            far_plane: coverage_samples > 1 && camera.depth.far.is_some(),
            target: target_index,
            count_fragments,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instances::pack_scene;
    use crate::target::Pass;
    use crate::{Ellipsoid, Scene};
    use glam::{DQuat, DVec3};

    /// 60,000 glyphs of about a pixel in a 10-unit cube, seen from 40 units at 640x480;
    /// with `big`, the first is a sphere of radius 4 (about 10,000 pixels).
    fn tiny_scene(big: bool) -> (UploadedScene, Camera) {
        scene_of(big, 1.0)
    }

    /// As `tiny_scene`, with semi-axes `scale` times larger.
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
        let packed = pack_scene(&scene, InstanceFormat::Full).unwrap();
        let camera =
            Camera::look_at(DVec3::new(0.0, 0.0, 40.0), DVec3::ZERO, 45.0, 1.0, 640, 480).unwrap();
        (UploadedScene::new(&scene, &packed, u32::MAX), camera)
    }

    fn plan(
        scene: &UploadedScene,
        camera: &Camera,
        samples: vk::SampleCountFlags,
        features: bool,
        settings: &Settings,
    ) -> FramePlan {
        let target = Target {
            pass: Pass::Dynamic {
                color_formats: vec![vk::Format::R8G8B8A8_SRGB],
                depth_format: vk::Format::D32_SFLOAT,
            },
            samples,
            aux_outputs: false,
        };
        FramePlan::new(PlanInputs {
            compute_splat_features: features,
            max_storage_buffer_range: 1 << 27,
            standard_sample_locations: true,
            sample_rate_shading: true,
            chunks: 1,
            still: false,
            shown_stamped: false,
            scene,
            settings,
            config: DrawConfig::default(),
            count_fragments: false,
            target: (0, &target),
            camera,
        })
        .unwrap()
    }

    /// Multisampled targets are shaded once per pixel with the sample count's exact coverage
    /// by default, per sample when the settings ask for it or the sample count has no
    /// positions in the shader; single-sample targets never test coverage.
    #[test]
    fn multisampled_targets_shade_once_per_pixel_unless_asked_otherwise() {
        let (scene, camera) = tiny_scene(false);
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

    /// Multisampled frames keep every culling, proved at their samples' grid, and draw one
    /// or two triangles per glyph.
    #[test]
    fn multisampled_frames_cull_at_their_samples_with_few_primitives() {
        use vk::SampleCountFlags as S;
        let shipped = Settings::default();
        for (scale, single, multi) in [
            (1.0, Footprint::OrientedRect, Footprint::Triangle),
            (60.0, Footprint::Hexagon, Footprint::OrientedRect),
        ] {
            let (scene, camera) = scene_of(false, scale);
            for (samples, grid) in [
                (S::TYPE_1, 1),
                (S::TYPE_2, 2),
                (S::TYPE_4, 4),
                (S::TYPE_8, 8),
            ] {
                let plan = plan(&scene, &camera, samples, false, &shipped);
                assert_eq!(plan.sample_grid, grid, "{samples:?}");
                assert_eq!(plan.culling, Culling::ON, "{samples:?}");
                let expected = if samples == S::TYPE_1 { single } else { multi };
                assert_eq!(plan.config.footprint, expected, "{samples:?} at {scale}x");
            }
            let sixteen = plan(&scene, &camera, S::TYPE_16, false, &shipped);
            assert_eq!(sixteen.sample_grid, 0);
        }
    }

    #[test]
    fn the_compute_splat_runs_only_where_it_may_and_pays() {
        let (scene, camera) = tiny_scene(false);
        let shipped = Settings::default();
        let one = vk::SampleCountFlags::TYPE_1;
        let splat = plan(&scene, &camera, one, true, &shipped);
        assert!(
            splat.mean_area_px.unwrap() <= SETUP_ONCE_MAX_AREA_PX,
            "{splat:?}"
        );
        assert!(
            splat.compute_splat && splat.prepass && !splat.setup_once,
            "{splat:?}"
        );
        // Without the host's 64-bit atomics: the draw, set up once.
        let draw = plan(&scene, &camera, one, false, &shipped);
        assert!(!draw.compute_splat && draw.setup_once, "{draw:?}");
        // Multisampled targets keep the draw (it is exact per sample; the splat keys pixels).
        let msaa = plan(
            &scene,
            &camera,
            vk::SampleCountFlags::TYPE_4,
            true,
            &shipped,
        );
        assert!(!msaa.compute_splat, "{msaa:?}");
        // Fewer glyphs than pay for the splat's fixed cost: the draw.
        let few = Settings {
            compute_splat_min_glyphs: 60_001,
            ..shipped
        };
        assert!(!plan(&scene, &camera, one, true, &few).compute_splat);
        // Switched off.
        let off = Settings {
            compute_splat: false,
            ..shipped
        };
        assert!(!plan(&scene, &camera, one, true, &off).compute_splat);
        // One glyph of thousands of pixels among them: splatted all the same (the splat
        // leaves that one to the draw).
        let (big, camera) = tiny_scene(true);
        let mixed = plan(&big, &camera, one, true, &shipped);
        assert!(
            mixed.mean_area_px.unwrap() <= SETUP_ONCE_MAX_AREA_PX,
            "{mixed:?}"
        );
        assert!(mixed.compute_splat, "{mixed:?}");
        // Glyphs of thousands of pixels on average: the draw, with its culling.
        let (large, camera) = scene_of(false, 150.0);
        let plan_large = plan(&large, &camera, one, true, &shipped);
        assert!(
            plan_large.mean_area_px.unwrap() > SPLAT_MAX_MEAN_AREA_PX,
            "{plan_large:?}"
        );
        assert!(!plan_large.compute_splat, "{plan_large:?}");
        // Glyphs of tens of pixels splat too (never set up once)...
        let (medium, camera) = scene_of(false, 20.0);
        let plan_medium = plan(&medium, &camera, one, true, &shipped);
        let area = plan_medium.mean_area_px.unwrap();
        assert!(area > 4.0 * SETUP_ONCE_MAX_AREA_PX, "{plan_medium:?}");
        assert!(
            plan_medium.compute_splat && !plan_medium.setup_once,
            "{plan_medium:?}"
        );
        // ...but not when a benchmark variant picks the footprint: that measures the draw.
        let target = Target {
            pass: Pass::Dynamic {
                color_formats: vec![vk::Format::R8G8B8A8_SRGB],
                depth_format: vk::Format::D32_SFLOAT,
            },
            samples: one,
            aux_outputs: false,
        };
        let hexagon = FramePlan::new(PlanInputs {
            compute_splat_features: true,
            max_storage_buffer_range: 1 << 27,
            standard_sample_locations: true,
            sample_rate_shading: true,
            chunks: 1,
            still: false,
            shown_stamped: false,
            scene: &medium,
            settings: &shipped,
            config: DrawConfig {
                footprint: Footprint::Hexagon,
                ..DrawConfig::default()
            },
            count_fragments: false,
            target: (0, &target),
            camera: &camera,
        })
        .unwrap();
        assert!(!hexagon.compute_splat, "{hexagon:?}");
        assert_eq!(hexagon.drawn_because, Some(DrawReason::Baseline));
    }

    /// The visible-first splat runs for a still camera that an earlier frame stamped, one
    /// chunk and glyphs that hide enough; stamping needs only the still camera.
    #[test]
    fn visible_first_needs_a_still_stamped_camera_one_chunk_and_enough_hidden() {
        let (scene, camera) = scene_of(false, 20.0);
        let shipped = Settings::default();
        let target = Target {
            pass: Pass::Dynamic {
                color_formats: vec![vk::Format::R8G8B8A8_SRGB],
                depth_format: vk::Format::D32_SFLOAT,
            },
            samples: vk::SampleCountFlags::TYPE_1,
            aux_outputs: false,
        };
        let make = |still, shown_stamped, chunks, settings: &Settings| {
            FramePlan::new(PlanInputs {
                compute_splat_features: true,
                max_storage_buffer_range: 1 << 27,
                standard_sample_locations: true,
                sample_rate_shading: true,
                chunks,
                still,
                shown_stamped,
                scene: &scene,
                settings,
                config: DrawConfig::default(),
                count_fragments: false,
                target: (0, &target),
                camera: &camera,
            })
            .unwrap()
        };
        let hidden = make(true, true, 1, &shipped).hidden_area_px.unwrap();
        let deep_enough = Settings {
            visible_first_min_hidden_px: hidden * 0.5,
            ..shipped
        };
        let too_shallow = Settings {
            visible_first_min_hidden_px: hidden * 2.0,
            ..shipped
        };
        let off = Settings {
            visible_first: false,
            ..deep_enough
        };
        for (still, stamped, chunks, settings, marks, first) in [
            (true, true, 1, &deep_enough, true, true),
            (true, false, 1, &deep_enough, true, false),
            (false, true, 1, &deep_enough, false, false),
            (false, false, 1, &deep_enough, false, false),
            (true, true, 2, &deep_enough, false, false),
            (true, true, 1, &too_shallow, false, false),
            (true, true, 1, &off, false, false),
        ] {
            let plan = make(still, stamped, chunks, settings);
            assert!(plan.compute_splat, "{plan:?}");
            let case = format!("still {still}, stamped {stamped}, {chunks} chunks");
            assert_eq!(
                (plan.mark_shown, plan.visible_first),
                (marks, first),
                "{case}"
            );
        }
    }

    /// A drawn frame says why: the first condition of the splat it does not meet.
    #[test]
    fn drawn_frames_say_why() {
        let (scene, camera) = tiny_scene(false);
        let shipped = Settings::default();
        use vk::SampleCountFlags as S;
        let why = |samples, features, settings: &Settings| {
            plan(&scene, &camera, samples, features, settings).drawn_because
        };
        assert_eq!(why(S::TYPE_1, true, &shipped), None);
        assert_eq!(
            why(S::TYPE_4, true, &shipped),
            Some(DrawReason::Multisampled)
        );
        assert_eq!(
            why(S::TYPE_1, false, &shipped),
            Some(DrawReason::MissingFeatures)
        );
        let off = Settings {
            compute_splat: false,
            ..shipped
        };
        assert_eq!(why(S::TYPE_4, false, &off), Some(DrawReason::SplatOff));
        let few = Settings {
            compute_splat_min_glyphs: 100_000,
            ..shipped
        };
        assert_eq!(why(S::TYPE_1, true, &few), Some(DrawReason::TooFewGlyphs));
        let reason = DrawReason::Multisampled.to_string();
        assert!(reason.contains("per sample"), "{reason}");
    }
}
