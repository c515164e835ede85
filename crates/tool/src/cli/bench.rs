//! `bench`'s arguments.

use std::path::PathBuf;

use clap::Args;

use super::camera::CameraArgs;
use super::device::DeviceArgs;
use super::load::LoadArgs;
use super::values::{parse_orbit_degrees, parse_pixels};

/// Arguments of `bench`.
#[derive(Debug, Clone, Args)]
pub struct BenchArgs {
    /// Directory for results.csv and the plots (with the tensor field among the scenes, also
    /// antialias.csv and antialias_vs_error.png: its antialiased ways join its chart).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Fewer and smaller scenes, for a run of minutes rather than hours on 2 cores.
    #[arg(long)]
    pub quick: bool,
    /// Timed frames per method and scene (median reported).
    #[arg(long, default_value_t = 15, allow_negative_numbers = true)]
    pub frames: usize,
    /// Time a moving camera: each frame turned this many degrees (0.01 to 90) further about
    /// the scene's centre than the frame before (default: the camera holds still).
    #[arg(long, value_name = "DEG", value_parser = parse_orbit_degrees, allow_negative_numbers = true)]
    pub orbit: Option<f64>,
    /// Comma-separated method names (default: all).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Only built-in scenes whose name contains one of these comma-separated words (default:
    /// all of them, or none when `--scene` is given).
    #[arg(long, value_delimiter = ',')]
    pub scenes: Vec<String>,
    /// A scene of your own, as `render --scene` takes it: a file in any format `render`
    /// reads, `tensor-field[:N]`, `lattice[:N]`, `md-liquid[:N]` or `random:COUNT`. Repeat it
    /// for several; with `--scenes`, the built-in scenes it picks run too. Each is loaded,
    /// and its camera set up, before the device is opened.
    #[arg(long = "scene", value_name = "SCENE")]
    pub scene: Vec<String>,
    /// The camera of the `--scene` scenes, as `render` takes it (default: framing each).
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Image width of the `--scene` scenes in pixels, 1 to 16384 (default 1920).
    #[arg(long, value_parser = parse_pixels, allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height of the `--scene` scenes in pixels, 1 to 16384 (default 1080).
    #[arg(long, value_parser = parse_pixels, allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// How the `--scene` scenes are read and coloured.
    #[command(flatten)]
    pub load: LoadArgs,
    /// Instead: measure each skippable piece of work on and off (culling, outputs, order);
    /// writes skip.csv and skip.png.
    #[arg(long, conflicts_with = "antialias")]
    pub skip: bool,
    /// With `--skip`: only these comma-separated features (default: all of them).
    #[arg(long, value_delimiter = ',', requires = "skip")]
    pub features: Vec<String>,
    /// Instead: time antialiasing (one sample, 4x MSAA shaded per pixel and per sample, 2 x 2
    /// and 4 x 4 supersampling) on the tensor field and a cloud of 16 px glyphs, and report
    /// each way's area error and its error at its own samples (both measured at a quarter of
    /// the size); writes antialias.csv and antialias_vs_error.png.
    #[arg(long)]
    pub antialias: bool,
    /// Device and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}
