//! `ellipsoid-splat bench --antialias`: what antialiasing costs and what it buys -- one
//! sample, 4x MSAA shaded per pixel and per sample, 2 x 2 and 4 x 4 supersampling, a renderer
//! each, interleaved round by round. The scenes, the timing and the two errors (against the
//! area covered, on a quarter-size view; and at each way's own samples, the axis `bench`'s
//! time-versus-error chart joins them on) are defined once, in the repository's
//! `docs/antialiasing.md` (time against error through the offscreen renderer).

use std::path::Path;

use ash::vk;

use crate::error::Result;
use ellipsoid_splat::ContextOptions;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat::{Outputs, Settings};
use ellipsoid_splat::{PathKind, PlanMode};

use crate::antialias_stress::AntialiasMode;
use crate::bench::{frustum_cloud, median, tensor_field_scene, BenchScene, RoundOrder};
use crate::error::Error;
use crate::report::{format_table, scatter_chart, write_csv, Axis, Series};
use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::Camera;
use ellipsoid_splat::Material;
use ellipsoid_splat_reference::coverage::{compare_coverage, coverage_from, SamplePattern};
use ellipsoid_splat_reference::{render_reference, Bounds};

/// One way of drawing a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Variant {
    /// The antialiasing, or none.
    pub mode: Option<AntialiasMode>,
    /// The compute splat may take the frame (it takes single-sample frames of many small
    /// glyphs, supersampled ones included; never multisampled ones).
    pub compute_splat: bool,
}

impl Variant {
    /// The name in `antialias.csv`.
    pub fn name(self) -> String {
        let mode = self.mode.map_or("1-sample".into(), |m| m.name());
        if self.compute_splat {
            mode
        } else {
            format!("{mode}-drawn")
        }
    }
}

/// One scene drawn one way.
pub struct AntialiasTiming {
    /// Scene name.
    pub scene: String,
    /// How.
    pub variant: Variant,
    /// Median submit-to-fence time.
    pub wall_ms: f64,
    /// `wall_ms` over the same scene's one-sample median (the shipped renderer's).
    pub ratio: f64,
    /// Mean distance of the partly covered pixels from the covered area (16 samples), as a
    /// fraction of a pixel.
    pub area_error: f64,
    /// The error at the variant's own samples over its strict bound, as `bench` charts every
    /// method's coverage: the fraction of the covered pixels whose light is off the
    /// reference's count of covered samples by half a sample or more, over the coverage
    /// bound, floored at 1 (1: exact). Coverage only: depth and normal are one sample's.
    pub sample_error_ratio: f64,
}

/// The variants: one sample (shipped, and drawn without the compute splat, which
/// multisampled frames cannot use), 4x MSAA per pixel and per sample, 2 x 2 and 4 x 4
/// supersampling.
const VARIANTS: [Variant; 6] = [
    Variant {
        mode: None,
        compute_splat: true,
    },
    Variant {
        mode: None,
        compute_splat: false,
    },
    Variant {
        mode: Some(AntialiasMode::Msaa4),
        compute_splat: true,
    },
    Variant {
        mode: Some(AntialiasMode::Msaa4PerSample),
        compute_splat: true,
    },
    Variant {
        mode: Some(AntialiasMode::Supersample(2)),
        compute_splat: true,
    },
    Variant {
        mode: Some(AntialiasMode::Supersample(4)),
        compute_splat: true,
    },
];

/// The view of `camera` at a quarter of its size, where the error is measured.
fn quarter(camera: &Camera) -> Camera {
    Camera {
        width: camera.width / 4,
        height: camera.height / 4,
        ..*camera
    }
}

/// Where the samples of a variant lie.
fn pattern(variant: Variant) -> SamplePattern {
    variant
        .mode
        .map_or(SamplePattern::Grid(1), AntialiasMode::pattern)
}

/// Each variant's error against the area the glyphs cover and its error ratio at its own
/// samples (see the module documentation and [`AntialiasTiming`]).
fn measure_errors(
    renderers: &mut [OffscreenRenderer],
    bench: &BenchScene,
    settings: &[Settings],
) -> Result<Vec<(f64, f64)>> {
    let small = quarter(&bench.camera);
    // The reference on each grid the variants' samples (and the area's 4 x 4) lie on, drawn
    // once.
    let mut grids = Vec::new();
    for pattern in VARIANTS
        .map(pattern)
        .into_iter()
        .chain([SamplePattern::Grid(4)])
    {
        let k = pattern.grid();
        if grids.iter().any(|(g, _)| *g == k) {
            continue;
        }
        let big = Camera {
            width: small.width * k,
            height: small.height * k,
            ..small
        };
        grids.push((k, render_reference(&bench.scene, &big)?));
    }
    let coverage = |pattern: SamplePattern| {
        let (_, reference) = grids
            .iter()
            .find(|(k, _)| *k == pattern.grid())
            .ok_or_else(|| Error::invalid("antialiasing bench", "no reference on that grid"))?;
        coverage_from(reference, &small, pattern).map_err(Error::from)
    };
    let area = coverage(SamplePattern::Grid(4))?;
    let unlit = Material::unlit();
    let white = ellipsoid_splat::Scene::new(
        bench
            .scene
            .ellipsoids
            .iter()
            .map(|e| ellipsoid_splat::Ellipsoid {
                color: [1.0, 1.0, 1.0],
                ..*e
            })
            .collect(),
    );
    let mut errors = Vec::new();
    for ((renderer, variant), settings) in renderers.iter_mut().zip(VARIANTS).zip(settings) {
        renderer.set_settings({
            let mut settings = *settings;
            settings.material = unlit;
            settings
        });
        let frame = match variant.mode {
            Some(AntialiasMode::Supersample(k)) => {
                let big = supersampled_camera(&small, k)?;
                box_filter(&renderer.render(&white, &big, Outputs::COLOR_DEPTH)?, k)?
            }
            _ => renderer.render(&white, &small, Outputs::COLOR_DEPTH)?,
        };
        // No upload back: the next scene's timed frames upload their own scene.
        renderer.set_settings(*settings);
        let own = compare_coverage(&frame, &coverage(pattern(variant))?)?;
        // As `bench` counts coverage mismatches: over the pixels the glyphs cover.
        let wrong = own.wrong as f64 / own.covered.max(1) as f64;
        errors.push((
            compare_coverage(&frame, &area)?.mean_error / 16.0,
            (wrong / Bounds::STRICT.coverage_fraction).max(1.0),
        ));
    }
    Ok(errors)
}

/// The scenes of `bench --antialias`: the tensor field and a cloud of 16-pixel glyphs.
pub fn scenes() -> Vec<BenchScene> {
    vec![tensor_field_scene(), frustum_cloud(10_000, 16.0, 7)]
}

/// Times every variant on each of `scenes`, `frames` interleaved rounds after one warm-up
/// round. Each variant has a renderer of its own, made with `options`, so no frame pays for
/// re-making another variant's targets.
pub fn run(
    options: &ContextOptions,
    frames: usize,
    scenes: &[BenchScene],
) -> Result<Vec<AntialiasTiming>> {
    let mut renderers = Vec::new();
    let mut settings = Vec::new();
    for variant in VARIANTS {
        let mut renderer = OffscreenRenderer::new(options)?;
        let samples = match variant.mode {
            Some(AntialiasMode::Msaa4 | AntialiasMode::Msaa4PerSample) => {
                vk::SampleCountFlags::TYPE_4
            }
            _ => vk::SampleCountFlags::TYPE_1,
        };
        renderer.set_samples(samples)?;
        let these = {
            let mut settings = Settings::default();
            settings.per_sample_shading = variant.mode == Some(AntialiasMode::Msaa4PerSample);
            // Reproducible: the first guess, or the draw alone.
            settings.plan = if variant.compute_splat {
                PlanMode::Estimate
            } else {
                PlanMode::Fixed(PathKind::Draw)
            };
            settings
        };
        renderer.set_settings(these);
        settings.push(these);
        renderers.push(renderer);
    }
    let mut out = Vec::new();
    for bench in scenes {
        let mut cameras = Vec::new();
        for (renderer, variant) in renderers.iter_mut().zip(VARIANTS) {
            renderer.upload(&bench.scene)?;
            cameras.push(match variant.mode {
                Some(AntialiasMode::Supersample(k)) => supersampled_camera(&bench.camera, k)?,
                _ => bench.camera,
            });
        }
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); VARIANTS.len()];
        let mut order = RoundOrder::new(VARIANTS.len());
        for round in 0..=frames {
            for &k in order.next_round() {
                let timing = renderers[k].render_timed(&cameras[k], Outputs::COLOR_DEPTH)?;
                if round > 0 {
                    times[k].push(timing.gpu_wall.as_secs_f64() * 1e3);
                }
            }
        }
        let medians: Vec<f64> = times.iter_mut().map(|t| median(t)).collect();
        let errors = measure_errors(&mut renderers, bench, &settings)?;
        for ((variant, wall_ms), (area_error, sample_error_ratio)) in
            VARIANTS.iter().zip(&medians).zip(errors)
        {
            out.push(AntialiasTiming {
                scene: bench.name.clone(),
                variant: *variant,
                wall_ms: *wall_ms,
                ratio: wall_ms / medians[0],
                area_error,
                sample_error_ratio,
            });
        }
    }
    for renderer in renderers {
        renderer.context().check_validation()?;
        renderer.finish()?;
    }
    Ok(out)
}

/// Writes `antialias.csv` and `antialias_vs_error.png` (the tensor field) into `dir` and
/// returns the table.
pub fn write_report(results: &[AntialiasTiming], dir: &Path) -> Result<String> {
    let header = [
        "scene",
        "variant",
        "wall_ms",
        "ratio_to_1_sample",
        "area_error_px",
        "sample_error_ratio",
    ];
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            vec![
                r.scene.clone(),
                r.variant.name(),
                format!("{:.2}", r.wall_ms),
                format!("{:.2}", r.ratio),
                format!("{:.4}", r.area_error),
                format!("{:.2}", r.sample_error_ratio),
            ]
        })
        .collect();
    write_csv(&dir.join("antialias.csv"), &header, &rows)?;
    let series: Vec<Series> = results
        .iter()
        .filter(|r| r.scene == "tensor-field")
        .map(|r| Series::new(r.variant.name(), vec![(r.wall_ms, r.area_error.max(1e-4))]))
        .collect();
    scatter_chart(
        &dir.join("antialias_vs_error.png"),
        "antialiasing: time versus error, tensor field (1920x1080, lavapipe)",
        &Axis::log("median frame time, submit to fence (ms)"),
        &Axis::log("mean error of partly covered pixels against the covered area (px)"),
        &series,
        None,
    )?;
    Ok(format_table(&header, &rows))
}
