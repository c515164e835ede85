//! Command-line arguments of the `ellipsoid-splat` binary: clap's definitions, one file per
//! command (and per flag group commands share), each checked and turned into typed options.
//! What the commands do with them lives beside: the camera in `camera_setup`, the scene in
//! `scene_io`, the host memory check in `host_memory`, the renderer in `render_device`.

use clap::{Parser, Subcommand};

mod bench;
mod camera;
mod conformance;
mod device;
mod load;
mod render;
mod render_check;
mod scene;
mod stress;
pub(crate) mod values;
mod view;

pub use bench::BenchArgs;
pub use camera::{CameraArgs, DEFAULT_FOV_Y};
pub use conformance::ConformanceArgs;
pub use device::DeviceArgs;
pub use load::{ColorArg, LoadArgs, TensorOrderArg};
pub use render::{IntersectionArg, RenderArgs, MAX_IMAGE_SIDE};
pub use render_check::RenderPlan;
pub use scene::{SceneSpec, MAX_ELLIPSOIDS, MAX_TENSOR_FIELD_SIDE, MD_LIQUID_COUNT};
pub use stress::StressArgs;
pub use view::ViewArgs;

/// Exact ray-cast ellipsoid impostors on Vulkan.
#[derive(Debug, Parser)]
#[command(name = "ellipsoid-splat", version, about)]
pub struct Cli {
    /// What to do; with none, renders the default demo.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene to PNG (and optionally depth, normal and ID images).
    Render(Box<RenderArgs>),
    /// Numerical-stability sweep: every point rendered on the GPU and by the float64
    /// reference; writes a CSV table and plots, exits non-zero if a bound breaks.
    Stress(StressArgs),
    /// Run time against error: every drawing method on the same scenes, timed and compared
    /// with the float64 reference; writes results.csv and plots.
    Bench(Box<BenchArgs>),
    /// Print the Vulkan device, driver and features used.
    Info(DeviceArgs),
    /// Check this device's driver against the float64 reference: the accuracy cases under the
    /// validation layer, a report per case, exit status 1 on any failure.
    Conformance(ConformanceArgs),
    /// Open a window on a scene: turn it, zoom, pick glyphs (the same scene, camera and
    /// loading flags as `render`).
    #[command(
        after_help = crate::view::controls::KEYS,
        mut_arg("width", |a| a.default_value("1280").help("Window width in pixels, 1 to 16384.")),
        mut_arg("height", |a| a.default_value("720").help("Window height in pixels, 1 to 16384.")),
        mut_arg("output", |a| a.help("Screenshots (P) go to this name with -001, -002, ... added."))
    )]
    View(Box<ViewArgs>),
}

impl Default for RenderArgs {
    fn default() -> Self {
        // The demo: exactly what `render` does with no flags.
        Cli::parse_from(["ellipsoid-splat", "render"])
            .command
            .and_then(|c| match c {
                Command::Render(r) => Some(*r),
                _ => None,
            })
            .expect("`render` with no flags parses")
    }
}

/// `render`'s arguments from `extra` flags, for the tests of the modules that take them.
#[cfg(test)]
pub(crate) fn render_args(extra: &[&str]) -> RenderArgs {
    let args = ["ellipsoid-splat", "render"].iter().chain(extra);
    match Cli::try_parse_from(args).expect("parses").command {
        Some(Command::Render(r)) => *r,
        _ => unreachable!(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plan_values_parse_and_flags_left_at_their_defaults_count_as_not_given() {
        use ellipsoid_splat::{PathKind, PlanMode};
        let args = render_args(&[]);
        assert_eq!(args.plan.mode(), PlanMode::Measure);
        assert_eq!(args.camera.given(), None);
        assert_eq!(
            args.load.given(),
            None,
            "the flags' defaults are the loaders'"
        );
        let fixed = render_args(&["--plan", "visible-first"]);
        assert_eq!(fixed.plan.mode(), PlanMode::Fixed(PathKind::VisibleFirst));
        assert_eq!(render_args(&["--up", "0,0,1"]).camera.given(), Some("--up"));
        assert_eq!(
            render_args(&["--fov-y", "30"]).camera.given(),
            Some("--fov-y")
        );
        assert_eq!(render_args(&["--sigma", "3"]).load.given(), Some("--sigma"));
    }
}
