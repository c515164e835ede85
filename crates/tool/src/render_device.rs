//! The offscreen renderer a `render` command asks for: its device and validation, draw
//! configuration, settings and sample count, each refused with the flag to change.

use ellipsoid_splat::research::DrawConfig;
use ellipsoid_splat::{ContextOptions, OffscreenRenderer, Settings};

use crate::cli::{DeviceArgs, RenderArgs};
use crate::error::{Error, Result};

/// The context options `--device` and `--validation` ask for (validation brings
/// synchronization validation with it).
pub fn context_options(args: &DeviceArgs) -> ContextOptions {
    let mut context = ContextOptions::default();
    context.validation = args.validation;
    context.synchronization_validation = args.validation;
    context.device = args.device.clone();
    context
}

/// A renderer set up as `args` ask: `--intersection`, `--compact`, `--per-sample-shading`,
/// `--plan` and `--samples` (refused, naming the counts the device offers, where it offers
/// not that one).
pub fn offscreen_renderer(args: &RenderArgs) -> Result<OffscreenRenderer> {
    let mut renderer = OffscreenRenderer::new(&context_options(&args.device))?;
    renderer.set_draw_config(DrawConfig {
        intersection: args.intersection.into(),
        ..DrawConfig::default()
    });
    renderer.set_settings({
        let mut settings = Settings::default();
        settings.instance_format = args.instance_format();
        settings.per_sample_shading = args.per_sample_shading;
        settings.plan = args.plan.mode();
        settings
    });
    let samples = ash::vk::SampleCountFlags::from_raw(args.samples);
    let offered = renderer.context().info().sample_counts;
    if !offered.contains(samples) {
        let counts: Vec<String> = (0..7)
            .map(|bit| 1u32 << bit)
            .filter(|&n| offered.contains(ash::vk::SampleCountFlags::from_raw(n)))
            .map(|n| n.to_string())
            .collect();
        return Err(Error::invalid(
            "--samples",
            format!(
                "{} samples per pixel: this device offers {}",
                args.samples,
                counts.join(", ")
            ),
        ));
    }
    renderer.set_samples(samples)?;
    Ok(renderer)
}
