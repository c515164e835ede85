//! `ellipsoid-splat bench --skip`: each piece of work a scene may not need, measured on and
//! off, on a scene built to need it and on a plain scene that does not, with the frames
//! compared pixel for pixel.

use std::path::Path;

use glam::DVec3;

use crate::bench::{frustum_cloud, median, HEIGHT, WIDTH};
use crate::error::{Error, Result};
use crate::report::{bar_chart, format_table, write_csv, Axis};
use ellipsoid_splat::research::{DrawConfig, Method};
use ellipsoid_splat::Camera;
use ellipsoid_splat::Frame;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat::Scene;
use ellipsoid_splat::{Outputs, Settings};
use ellipsoid_splat::{PathKind, PlanMode};
use ellipsoid_splat_loaders::{packed_block, random_cloud, Progress};

/// Columns of `skip.csv`.
pub const CSV_HEADER: &[&str] = &[
    "feature",
    "scene",
    "applies",
    "on_ms",
    "off_ms",
    "pixels_changed",
];

/// A skippable piece of work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// Exact per-ellipsoid frustum culling in the pre-pass.
    FrustumCulling,
    /// Dropping ellipsoids whose silhouette holds no pixel centre, in the pre-pass.
    PixelCentreCulling,
    /// Dropping ellipsoids hidden behind nearer ones' inscribed spheres, in the pre-pass.
    OcclusionCulling,
    /// Each impostor's set-up computed once in the pre-pass, not in each of its vertices, and
    /// handed to the fragment stage through a buffer instead of flat varyings.
    SetupOnce,
    /// No near-plane cap code when no ellipsoid reaches in front of the near plane.
    CapFreePath,
    /// Glyphs of a few pixels drawn as one triangle (three vertices, one primitive) instead of
    /// the oriented rectangle's four and two (opt-in: it shades more fragments).
    SmallGlyphTriangles,
    /// Normal and ID outputs only when asked for (a colour-only pipeline and pass otherwise).
    AuxOutputsOnDemand,
    /// Instances uploaded sorted front to back by nearest depth (for early depth rejection on
    /// hardware that has it; lavapipe has none when the shader writes depth).
    FrontToBack,
    /// Many small and medium glyphs splatted by a compute pass and resolved once per pixel,
    /// instead of drawn through the rasterizer (the other features are measured on the draw).
    ComputeSplat,
    /// Hidden layers not shaded: the draw keeps each pixel's nearest hit in the visibility
    /// buffer, with no shading and no depth export, and a resolve shades each visible pixel
    /// once (`impostor-visbuffer`; measured, not shipped).
    VisibilityBuffer,
}

impl Feature {
    /// Every feature measured.
    pub const ALL: [Feature; 10] = [
        Feature::FrustumCulling,
        Feature::PixelCentreCulling,
        Feature::OcclusionCulling,
        Feature::SetupOnce,
        Feature::CapFreePath,
        Feature::SmallGlyphTriangles,
        Feature::AuxOutputsOnDemand,
        Feature::FrontToBack,
        Feature::ComputeSplat,
        Feature::VisibilityBuffer,
    ];

    /// The features named in `names` (every one when it is empty), or an error naming the
    /// first unknown name and the choices.
    pub fn parse_list(names: &[String]) -> Result<Vec<Feature>> {
        if names.is_empty() {
            return Ok(Feature::ALL.to_vec());
        }
        names
            .iter()
            .map(|name| {
                Feature::ALL
                    .into_iter()
                    .find(|f| f.name() == name.trim())
                    .ok_or_else(|| {
                        let choices: Vec<&str> = Feature::ALL.iter().map(|f| f.name()).collect();
                        Error::Invalid {
                            what: "--features".into(),
                            reason: format!(
                                "unknown feature '{name}' (choices: {})",
                                choices.join(", ")
                            ),
                        }
                    })
            })
            .collect()
    }

    /// Name in the `feature` column.
    pub fn name(self) -> &'static str {
        match self {
            Feature::FrustumCulling => "frustum-culling",
            Feature::PixelCentreCulling => "pixel-centre-culling",
            Feature::OcclusionCulling => "occlusion-culling",
            Feature::SetupOnce => "setup-once",
            Feature::CapFreePath => "cap-free-path",
            Feature::SmallGlyphTriangles => "small-glyph-triangles",
            Feature::AuxOutputsOnDemand => "aux-outputs-on-demand",
            Feature::FrontToBack => "front-to-back",
            Feature::ComputeSplat => "compute-splat",
            Feature::VisibilityBuffer => "visibility-buffer",
        }
    }

    /// The scene built to need it.
    fn scene_needing_it(self) -> &'static str {
        match self {
            Feature::FrustumCulling => "inside-field",
            Feature::PixelCentreCulling => "tiny-far",
            Feature::OcclusionCulling => "dense-block",
            Feature::SetupOnce => "tiny-visible",
            Feature::CapFreePath => "tiny-visible",
            Feature::SmallGlyphTriangles => "tiny-visible",
            Feature::AuxOutputsOnDemand => "molecule",
            Feature::FrontToBack => "heavy-overlap",
            Feature::ComputeSplat => "tiny-visible",
            Feature::VisibilityBuffer => "heavy-overlap",
        }
    }

    /// A scene that does not need it: the plain one, or for the cap-free path one whose
    /// glyphs cross the near plane.
    fn scene_not_needing_it(self) -> &'static str {
        match self {
            Feature::CapFreePath => "inside-field",
            // Its glyphs are large enough for the hexagon and octagon either way.
            Feature::SmallGlyphTriangles => "heavy-overlap",
            _ => "plain",
        }
    }

    /// Puts the renderer in the feature's on or off state (everything else as shipped);
    /// returns the outputs timed frames draw.
    fn apply(self, renderer: &mut OffscreenRenderer, on: bool) -> Outputs {
        // The draw's features are measured on the draw: the splat would take their frames.
        let mut settings = Settings::default();
        settings.plan = PlanMode::Fixed(PathKind::Draw);

        let mut timed = Outputs::COLOR_DEPTH;
        match self {
            Feature::FrustumCulling => settings.culling.frustum = on,
            Feature::PixelCentreCulling => settings.culling.pixel_centres = on,
            Feature::OcclusionCulling => settings.culling.occlusion = on,
            Feature::SetupOnce => settings.setup_once = on,
            Feature::CapFreePath => settings.cap_free_path = on,
            Feature::SmallGlyphTriangles => settings.small_glyph_triangles = on,
            Feature::ComputeSplat if on => settings.plan = PlanMode::Estimate,
            Feature::ComputeSplat => {}
            Feature::AuxOutputsOnDemand if !on => timed = Outputs::ALL,
            Feature::AuxOutputsOnDemand | Feature::FrontToBack | Feature::VisibilityBuffer => {}
        }
        renderer.set_settings(settings);
        renderer.set_draw_config(if self == Feature::VisibilityBuffer && on {
            Method::ImpostorVisbuffer.config()
        } else {
            DrawConfig::default()
        });
        timed
    }
}

/// One scene of the skip benchmark.
struct SkipScene {
    name: &'static str,
    scene: Scene,
    camera: Camera,
}

fn camera(eye: DVec3, target: DVec3, fov: f64, near: f64) -> Camera {
    Camera::look_at(eye, target, fov, near, WIDTH, HEIGHT).expect("skip-bench camera is valid")
}

/// The scenes: each built so that one feature has work to skip, plus a plain one.
fn scenes(quick: bool) -> Vec<SkipScene> {
    let scale = if quick { 1 } else { 4 };
    // Camera inside a large field, looking at a corner: most glyphs are off screen.
    let field = random_cloud(100_000 * scale, 31, 50.0, 0.15);
    // A million glyphs far beyond the point where they reach a pixel centre.
    let mut tiny = random_cloud(1_000_000, 32, 40.0, 0.01);
    for e in &mut tiny.ellipsoids {
        e.center.z -= 2_000.0;
    }
    // Many layers of overlap in front of the camera.
    let overlap = random_cloud(3_000, 33, 3.0, 0.8);
    // A million glyphs of about two pixels, all on screen.
    let tiny_visible = frustum_cloud(1_000_000, 2.0, 36);
    // A small molecule: about 1,600 atoms as spheres in a ball, filling the view. Light
    // enough that per-pixel output work is a large share of the frame.
    let mut molecule = random_cloud(3_000, 38, 18.0, 1.0);
    molecule.ellipsoids.retain(|e| e.center.length() < 18.0);
    for e in &mut molecule.ellipsoids {
        e.radii = DVec3::splat(1.2 + 0.6 * e.radii.x);
    }
    let (centre, radius) = molecule.bounding_sphere().expect("the molecule has atoms");
    let molecule_camera =
        Camera::framing(centre, radius, WIDTH, HEIGHT).expect("skip-bench camera is valid");
    // A packed block seen corner on: only its shell can show.
    let side = if quick { 40 } else { 64 };
    let block = packed_block(side, 35);
    // Every glyph on screen, a few pixels to tens of pixels across, little overlap.
    let plain = random_cloud(20_000, 34, 12.0, 0.25);
    vec![
        SkipScene {
            name: "inside-field",
            scene: field,
            camera: camera(
                DVec3::new(-45.0, -45.0, -45.0),
                DVec3::new(-50.0, -50.0, -60.0),
                45.0,
                0.05,
            ),
        },
        SkipScene {
            name: "tiny-far",
            scene: tiny,
            camera: camera(
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(0.0, 0.0, -1.0),
                45.0,
                1.0,
            ),
        },
        SkipScene {
            name: "heavy-overlap",
            scene: overlap,
            camera: camera(DVec3::new(0.0, 0.0, 9.0), DVec3::ZERO, 45.0, 1.0),
        },
        SkipScene {
            name: "tiny-visible",
            scene: tiny_visible.scene,
            camera: tiny_visible.camera,
        },
        SkipScene {
            name: "molecule",
            scene: molecule,
            camera: molecule_camera,
        },
        SkipScene {
            name: "dense-block",
            camera: camera(
                DVec3::new(55.0, 45.0, 70.0) * (side as f64 / 40.0),
                DVec3::ZERO,
                45.0,
                1.0,
            ),
            scene: block,
        },
        SkipScene {
            name: "plain",
            scene: plain,
            camera: camera(DVec3::new(0.0, 0.0, 30.0), DVec3::ZERO, 45.0, 1.0),
        },
    ]
}

/// The scene sorted front to back by each ellipsoid's nearest view depth.
fn front_to_back(scene: &Scene, camera: &Camera) -> Scene {
    let mut sorted = scene.clone();
    let nearest =
        |e: &ellipsoid_splat::Ellipsoid| camera.view_depth(e.center) - e.bounding_radius();
    sorted
        .ellipsoids
        .sort_by(|a, b| nearest(a).total_cmp(&nearest(b)));
    sorted
}

/// Pixels whose colour or depth differ between two frames.
fn pixels_changed(a: &Frame, b: &Frame) -> usize {
    (0..a.len())
        .filter(|&k| a.color[k] != b.color[k] || a.depth[k].to_bits() != b.depth[k].to_bits())
        .count()
}

/// One measured row.
pub struct SkipResult {
    /// The feature.
    pub feature: Feature,
    /// Scene name.
    pub scene: &'static str,
    /// Whether the scene was built to need the feature.
    pub applies: bool,
    /// Median frame time with the feature on.
    pub on_ms: f64,
    /// Median frame time with it off.
    pub off_ms: f64,
    /// Pixels whose colour or depth change when the feature is turned on.
    pub pixels_changed: usize,
}

impl SkipResult {
    /// Whether the row meets its target: 1.25x faster with no pixel changed where the feature
    /// applies, at most 5 % slower where it does not.
    pub fn meets_target(&self) -> bool {
        if self.applies {
            self.pixels_changed == 0 && self.on_ms <= 0.8 * self.off_ms
        } else {
            self.pixels_changed == 0 && self.on_ms <= 1.05 * self.off_ms
        }
    }
}

/// Measures every feature on its scene and on the plain scene: `2 frames` interleaved on/off
/// pairs (twice the method benchmark's count: the rows compare ratios near 1.05 and 0.8, and
/// this machine's frame times wander by several percent).
pub fn run(
    renderer: &mut OffscreenRenderer,
    quick: bool,
    frames: usize,
    features: &[Feature],
) -> Result<Vec<SkipResult>> {
    let scenes = scenes(quick);
    let progress = Progress::new((features.len() * 2) as u64, "skip");
    let mut results = Vec::new();
    let splat_capable = renderer.context().info().compute_splat;
    for &feature in features {
        // Both need the splat's 64-bit atomics (without them the compute splat is never
        // planned, and the visibility-buffer draw cannot be).
        if matches!(feature, Feature::ComputeSplat | Feature::VisibilityBuffer) && !splat_capable {
            continue;
        }
        let targets = [feature.scene_needing_it(), feature.scene_not_needing_it()];
        for name in targets {
            progress.inc(&format!("{} on {name}", feature.name()));
            let s = scenes
                .iter()
                .find(|s| s.name == name)
                .expect("scene exists");
            let sorted =
                (feature == Feature::FrontToBack).then(|| front_to_back(&s.scene, &s.camera));
            let scene_for = |on: bool| -> &Scene {
                match (&sorted, on) {
                    (Some(sorted), true) => sorted,
                    _ => &s.scene,
                }
            };
            // Read-back frames for the pixel comparison (they also warm up the pipelines).
            let mut frames_read = Vec::new();
            for on in [false, true] {
                let timed = feature.apply(renderer, on);
                renderer.upload(scene_for(on))?;
                frames_read.push(renderer.render_uploaded(&s.camera, Outputs::ALL)?.0);
                renderer.render_timed(&s.camera, timed)?;
            }
            let changed = pixels_changed(&frames_read[0], &frames_read[1]);
            let (mut on_ms, mut off_ms) = (Vec::new(), Vec::new());
            let uploads_differ = sorted.is_some();
            for round in 0..2 * frames {
                // Alternate which state goes first, so neither always follows the other.
                for on in if round % 2 == 0 {
                    [true, false]
                } else {
                    [false, true]
                } {
                    let timed = feature.apply(renderer, on);
                    if uploads_differ {
                        renderer.upload(scene_for(on))?;
                    }
                    let ms = renderer
                        .render_timed(&s.camera, timed)?
                        .gpu_wall
                        .as_secs_f64()
                        * 1e3;
                    if on {
                        on_ms.push(ms)
                    } else {
                        off_ms.push(ms)
                    }
                }
            }
            results.push(SkipResult {
                feature,
                scene: name,
                applies: name == feature.scene_needing_it(),
                on_ms: median(&mut on_ms),
                off_ms: median(&mut off_ms),
                pixels_changed: changed,
            });
        }
    }
    progress.finish();
    renderer.set_settings(Settings::default());
    Ok(results)
}

/// Writes `skip.csv` and `skip.png` into `dir`; returns the printed table.
pub fn write_report(results: &[SkipResult], dir: &Path) -> Result<String> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            vec![
                r.feature.name().to_string(),
                r.scene.to_string(),
                if r.applies { "yes" } else { "no" }.to_string(),
                format!("{:.3}", r.on_ms),
                format!("{:.3}", r.off_ms),
                r.pixels_changed.to_string(),
            ]
        })
        .collect();
    write_csv(&dir.join("skip.csv"), CSV_HEADER, &rows)?;
    let bars: Vec<(String, f64)> = results
        .iter()
        .map(|r| {
            (
                format!("{} / {}", r.feature.name(), r.scene),
                r.off_ms / r.on_ms,
            )
        })
        .collect();
    bar_chart(
        &dir.join("skip.png"),
        "speed-up with the feature on (off_ms / on_ms; target >= 1.25 where it applies)",
        &Axis::log("off_ms / on_ms"),
        &bars,
    )?;
    let mut header: Vec<&str> = CSV_HEADER.to_vec();
    header.push("target");
    let table: Vec<Vec<String>> = rows
        .into_iter()
        .zip(results)
        .map(|(mut row, r)| {
            row.push(if r.meets_target() { "met" } else { "MISSED" }.to_string());
            row
        })
        .collect();
    Ok(format_table(&header, &table))
}
