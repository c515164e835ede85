//! The antialiased points of `stress`: scenes where coverage is hardest to get right -- thin
//! needles, glyphs smaller than a pixel, a glyph cut by the near plane, overlapping glyphs --
//! drawn with 4x multisampling (shaded once per pixel and once per sample) and with 2 x 2 and
//! 4 x 4 supersampling, each pixel's resolved coverage compared with the float64 reference's
//! count of covered samples at the same positions (`ellipsoid_splat_reference::coverage`).
//! The bound: no pixel off by half a sample or more.

use ash::vk;
use glam::{DQuat, DVec3};

use crate::error::Result;
use ellipsoid_splat::research::DrawConfig;
use ellipsoid_splat::Camera;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat::{Ellipsoid, Material, Outputs, Scene, Settings};
use ellipsoid_splat_reference::coverage::{
    compare_coverage, reference_coverage, CoverageStats, SamplePattern,
};

use crate::report::{format_table, write_csv};
use ellipsoid_splat::supersample::{box_filter, supersampled_camera};

/// How a point is antialiased.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AntialiasMode {
    /// 4x MSAA shaded once per pixel, exact coverage in the sample mask (the default).
    Msaa4,
    /// 4x MSAA shaded at every sample.
    Msaa4PerSample,
    /// `--supersample K`.
    Supersample(u32),
}

impl AntialiasMode {
    /// Every mode measured.
    pub const ALL: [AntialiasMode; 4] = [
        AntialiasMode::Msaa4,
        AntialiasMode::Msaa4PerSample,
        AntialiasMode::Supersample(2),
        AntialiasMode::Supersample(4),
    ];

    /// The name in `stress_aa.csv`.
    pub fn name(self) -> String {
        match self {
            AntialiasMode::Msaa4 => "msaa4-per-pixel".into(),
            AntialiasMode::Msaa4PerSample => "msaa4-per-sample".into(),
            AntialiasMode::Supersample(k) => format!("supersample{k}"),
        }
    }

    /// The positions its samples lie at.
    pub fn pattern(self) -> SamplePattern {
        match self {
            AntialiasMode::Msaa4 | AntialiasMode::Msaa4PerSample => SamplePattern::Standard4,
            AntialiasMode::Supersample(k) => SamplePattern::Grid(k),
        }
    }
}

/// One antialiased point: what is drawn and how it is seen.
pub struct AntialiasPoint {
    /// What it stresses.
    pub case: &'static str,
    /// Unlit white glyphs.
    pub scene: Scene,
    /// 96 x 64 pixels.
    pub camera: Camera,
}

/// A white glyph.
fn glyph(center: DVec3, radii: DVec3, rotation: DQuat) -> Ellipsoid {
    Ellipsoid::new(center, radii, rotation, Some([1.0, 1.0, 1.0])).expect("valid glyph")
}

/// The points: needles a tenth to a third of a pixel thick across the view, glyphs of a third
/// of a pixel to two pixels, a glyph cut by the near plane, and overlapping glyphs.
pub fn antialias_points() -> Vec<AntialiasPoint> {
    let camera = |eye: DVec3, near: f64| {
        Camera::look_at(eye, DVec3::ZERO, 40.0, near, 96, 64).expect("valid camera")
    };
    let eye = DVec3::new(0.3, 0.4, 20.0);
    // At 20 units a pixel is about 0.23 units across.
    let needles = (0..8)
        .map(|n| {
            let t = n as f64;
            glyph(
                DVec3::new(0.5 * t - 1.8, 0.3 * t - 1.0, 0.2 * t),
                DVec3::new(5.0, 0.012 + 0.005 * t, 0.012 + 0.005 * t),
                DQuat::from_rotation_z(0.4 * t + 0.1) * DQuat::from_rotation_y(0.3),
            )
        })
        .collect();
    let tiny = (0..300)
        .map(|n| {
            let t = n as f64;
            glyph(
                DVec3::new(
                    (t * 0.618_034).fract() * 14.0 - 7.0,
                    (t * 0.414_214).fract() * 9.0 - 4.5,
                    (t * 0.732_051).fract() * 4.0 - 2.0,
                ),
                DVec3::new(0.04, 0.03, 0.02) * (1.0 + 4.0 * (t * 0.577_215).fract()),
                DQuat::from_rotation_z(t),
            )
        })
        .collect();
    let cut = vec![
        glyph(
            DVec3::new(1.0, 0.6, 18.2),
            DVec3::new(1.0, 0.4, 0.9),
            DQuat::from_rotation_z(0.3),
        ),
        glyph(
            DVec3::ZERO,
            DVec3::new(3.0, 2.0, 1.5),
            DQuat::from_rotation_x(0.5),
        ),
    ];
    let overlapping = (0..12)
        .map(|n| {
            let t = n as f64;
            glyph(
                DVec3::new(
                    1.3 * (t * 1.7).sin() * 3.0,
                    2.0 * (t * 0.9).cos(),
                    t * 0.3 - 2.0,
                ),
                DVec3::new(1.6, 0.5 + 0.05 * t, 0.8),
                DQuat::from_rotation_z(0.6 * t) * DQuat::from_rotation_x(0.2 * t),
            )
        })
        .collect();
    vec![
        AntialiasPoint {
            case: "thin needles",
            scene: Scene::new(needles),
            camera: camera(eye, 1.0),
        },
        AntialiasPoint {
            case: "sub-pixel glyphs",
            scene: Scene::new(tiny),
            camera: camera(eye, 1.0),
        },
        AntialiasPoint {
            case: "near-plane cut",
            scene: Scene::new(cut),
            camera: camera(eye, 1.2),
        },
        AntialiasPoint {
            case: "overlapping glyphs",
            scene: Scene::new(overlapping),
            camera: camera(eye, 1.0),
        },
    ]
}

/// One point drawn in one mode.
pub struct AntialiasResult {
    /// The point's case.
    pub case: &'static str,
    /// The mode.
    pub mode: AntialiasMode,
    /// Its coverage error against the reference.
    pub stats: CoverageStats,
}

impl AntialiasResult {
    /// No pixel is off by half a sample or more.
    pub fn exact(&self) -> bool {
        self.stats.wrong == 0
    }
}

/// Draws `point` in `mode` with unlit white glyphs and compares its coverage.
pub fn run_antialias_point(
    renderer: &mut OffscreenRenderer,
    point: &AntialiasPoint,
    mode: AntialiasMode,
) -> Result<AntialiasResult> {
    // The shipped draw, whatever a sweep point before it drew with (the textbook baseline).
    renderer.set_draw_config(DrawConfig::default());
    renderer.set_settings({
        let mut settings = Settings::default();
        settings.material = Material::unlit();
        settings.per_sample_shading = mode == AntialiasMode::Msaa4PerSample;
        settings
    });
    let frame = match mode {
        AntialiasMode::Msaa4 | AntialiasMode::Msaa4PerSample => {
            renderer.set_samples(vk::SampleCountFlags::TYPE_4)?;
            let frame = renderer.render(&point.scene, &point.camera, Outputs::COLOR_DEPTH);
            renderer.set_samples(vk::SampleCountFlags::TYPE_1)?;
            frame?
        }
        AntialiasMode::Supersample(k) => {
            let big = supersampled_camera(&point.camera, k)?;
            let frame = renderer.render(&point.scene, &big, Outputs::COLOR_DEPTH)?;
            box_filter(&frame, k)?
        }
    };
    let coverage = reference_coverage(&point.scene, &point.camera, mode.pattern())?;
    Ok(AntialiasResult {
        case: point.case,
        mode,
        stats: compare_coverage(&frame, &coverage)?,
    })
}

/// Writes `stress_aa.csv` into `dir` and returns the table.
pub fn write_antialias_report(
    results: &[AntialiasResult],
    dir: &std::path::Path,
) -> Result<String> {
    let header = [
        "case",
        "mode",
        "compared_px",
        "partly_covered_px",
        "wrong_px",
        "mean_error_samples",
        "max_error_samples",
        "bound",
    ];
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            vec![
                r.case.to_string(),
                r.mode.name(),
                r.stats.compared.to_string(),
                r.stats.partly_covered.to_string(),
                r.stats.wrong.to_string(),
                format!("{:.4}", r.stats.mean_error),
                format!("{:.3}", r.stats.max_error),
                if r.exact() { "met" } else { "BROKEN" }.to_string(),
            ]
        })
        .collect();
    write_csv(&dir.join("stress_aa.csv"), &header, &rows)?;
    Ok(format_table(&header, &rows))
}
