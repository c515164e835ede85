//! The offscreen renderer a `render` command asks for: its device and validation, draw
//! configuration, settings and sample count, each refused with the flag to change; and the
//! renderer made ready for the command's frames (scene uploaded, plan warmed up).

use ellipsoid_splat::research::DrawConfig;
use ellipsoid_splat::{
    supersample, Camera, ContextOptions, Frame, OffscreenRenderer, Outputs, Scene, Settings,
};

use crate::cli::{DeviceArgs, RenderArgs};
use crate::error::{Error, Result};
use crate::plan::{self, WarmUp};

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

/// A renderer ready to draw `render`'s frame: made as `args` ask, the scene uploaded, and the
/// plan warmed up on the camera as drawn (supersampled by `--supersample`).
pub struct Prepared {
    /// The renderer, its plan settled as far as the warm-up went.
    pub renderer: OffscreenRenderer,
    /// The camera as drawn: `--supersample` times larger.
    pub drawn: Camera,
    /// The size of the drawn frame.
    pub extent: ash::vk::Extent2D,
    /// How the warm-up went.
    pub warm: WarmUp,
}

/// Makes the renderer (see [`offscreen_renderer`]), uploads `scene` and warms the plan up on
/// `camera` for `outputs`.
pub fn prepare(
    args: &RenderArgs,
    scene: &Scene,
    camera: &Camera,
    outputs: Outputs,
) -> Result<Prepared> {
    let mut renderer = offscreen_renderer(args)?;
    let k = args.supersample;
    let drawn = supersample::supersampled_camera(camera, k)?;
    let extent = ash::vk::Extent2D {
        width: args.width * k,
        height: args.height * k,
    };
    renderer.upload(scene)?;
    // The frame written comes after those the plan needs with its camera: where it measures,
    // it times the candidates first (as FFTW_MEASURE plans).
    let warm = plan::warm_up(&mut renderer, &drawn, extent, outputs, args.plan)?;
    Ok(Prepared {
        renderer,
        drawn,
        extent,
        warm,
    })
}

impl Prepared {
    /// Draws the frame of the uploaded scene and reads back `outputs`, filtered down to the
    /// output size with `--supersample`; and what it took on the device.
    pub fn draw(
        &mut self,
        k: u32,
        outputs: Outputs,
    ) -> Result<(Frame, ellipsoid_splat::FrameTiming)> {
        let (frame, timing) = self.renderer.render_views(
            self.extent.width,
            self.extent.height,
            std::slice::from_ref(&self.drawn),
            outputs,
        )?;
        self.renderer.context().check_validation()?;
        let frame = if k > 1 {
            supersample::box_filter(&frame, k)?
        } else {
            frame
        };
        Ok((frame, timing))
    }
}
