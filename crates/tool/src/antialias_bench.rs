//! `ellipsoid-splat bench --antialias`: what antialiasing costs. The tensor field and a cloud
//! of 16-pixel glyphs at 1920x1080, drawn with one sample, with 4x MSAA shaded once per pixel
//! and once per sample, and supersampled 2 x 2, interleaved round by round; medians of the
//! submit-to-fence times and their ratio to one sample. The coverage error of each mode is
//! `stress`'s (`stress_aa.csv`): exact in every mode.

use std::path::Path;

use ash::vk;

use ellipsoid_splat::error::Result;
use ellipsoid_splat::gpu::ContextOptions;
use ellipsoid_splat::offscreen::OffscreenRenderer;
use ellipsoid_splat::{Outputs, Settings};

use crate::antialias_stress::AntialiasMode;
use crate::bench::{frustum_cloud, median, tensor_field_scene, BenchScene, RoundOrder};
use crate::report::{format_table, write_csv};
use crate::supersample::supersampled_camera;

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
}

/// The variants timed: one sample (shipped, and drawn without the compute splat, which
/// multisampled frames cannot use), 4x MSAA per pixel and per sample, 2 x 2 supersampling
/// (4 x 4 draws 16 times the pixels: its cost is that of a 16 times larger frame).
const VARIANTS: [Variant; 5] = [
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
];

/// Times every variant on each scene, `frames` interleaved rounds after one warm-up round.
/// Each variant has a renderer of its own, made with `options`, so no frame pays for
/// re-making another variant's targets.
pub fn run(options: &ContextOptions, frames: usize) -> Result<Vec<AntialiasTiming>> {
    let scenes: Vec<BenchScene> = vec![tensor_field_scene(), frustum_cloud(10_000, 16.0, 7)];
    let mut renderers = Vec::new();
    for variant in VARIANTS {
        let mut renderer = OffscreenRenderer::new(options)?;
        let samples = match variant.mode {
            Some(AntialiasMode::Msaa4 | AntialiasMode::Msaa4PerSample) => {
                vk::SampleCountFlags::TYPE_4
            }
            _ => vk::SampleCountFlags::TYPE_1,
        };
        renderer.set_samples(samples)?;
        renderer.set_settings(Settings {
            per_sample_shading: variant.mode == Some(AntialiasMode::Msaa4PerSample),
            compute_splat: variant.compute_splat,
            ..Settings::default()
        });
        renderers.push(renderer);
    }
    let mut out = Vec::new();
    for bench in &scenes {
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
        for (variant, wall_ms) in VARIANTS.iter().zip(&medians) {
            out.push(AntialiasTiming {
                scene: bench.name.clone(),
                variant: *variant,
                wall_ms: *wall_ms,
                ratio: wall_ms / medians[0],
            });
        }
    }
    for renderer in renderers {
        renderer.context().check_validation()?;
        renderer.finish()?;
    }
    Ok(out)
}

/// Writes `antialias.csv` into `dir` and returns the table.
pub fn write_report(results: &[AntialiasTiming], dir: &Path) -> Result<String> {
    let header = ["scene", "variant", "wall_ms", "ratio_to_1_sample"];
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            vec![
                r.scene.clone(),
                r.variant.name(),
                format!("{:.2}", r.wall_ms),
                format!("{:.2}", r.ratio),
            ]
        })
        .collect();
    write_csv(&dir.join("antialias.csv"), &header, &rows)?;
    Ok(format_table(&header, &rows))
}
