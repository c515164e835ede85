//! Command-line arguments of the `ellipsoid-splat` binary and how they become a scene and a
//! camera.

use std::num::IntErrorKind;
use std::path::{Path, PathBuf};

use clap::{Args, Parser, Subcommand};
use glam::{DVec2, DVec3};

use crate::error::{Error, Result};
use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::InstanceFormat;
use ellipsoid_splat::{Camera, Intrinsics, Projection};
use ellipsoid_splat::{Scene, NO_INSTANCE};
use ellipsoid_splat_loaders as scene;

use crate::frame_range::FrameRange;
use crate::output::{self, Image};
use crate::plan::PlanArg;
use ellipsoid_splat::Outputs;

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

/// Arguments of `view`: `render`'s (scene, loading, camera, device) and the window's own.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// The scene, as `--scene` takes it (a file, `tensor-field[:N]`, `lattice[:N]`,
    /// `md-liquid[:N]` or `random:COUNT`).
    #[arg(value_name = "SCENE")]
    pub scene_name: Option<String>,
    /// Everything `render` takes; the depth, normal and ID image flags do not apply.
    #[command(flatten)]
    pub render: RenderArgs,
    /// Present without waiting for the display: mailbox, else immediate, where the window
    /// system offers them (default: FIFO, synchronised to the display).
    #[arg(long)]
    pub no_vsync: bool,
    /// Input events to play, one `FRAME COMMAND ARGS` a line (see `view/script.rs`).
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Close after this many turns of the render loop (drawn or skipped).
    #[arg(long)]
    pub exit_after: Option<u64>,
    /// While the camera moves, scenes with more glyphs draw a uniform sample of about this
    /// many; the first frame after it stops draws all. 0 turns sampling off.
    #[arg(long, default_value_t = crate::view::subset::DEFAULT_MOVING_GLYPHS)]
    pub moving_glyphs: usize,
}

impl ViewArgs {
    /// The `render` arguments the viewer starts from: the positional scene in `--scene`, and
    /// no flag that only `render` can honour.
    pub fn render_args(&self) -> Result<RenderArgs> {
        let mut render = self.render.clone();
        for (flag, given) in [
            ("--depth", render.depth.is_some()),
            ("--normal", render.normal.is_some()),
            ("--id", render.id.is_some()),
        ] {
            if given {
                return Err(Error::invalid(
                    flag,
                    "does not apply to `view`, which writes only screenshots (P); use `render`",
                ));
            }
        }
        if render.samples != 1 || render.per_sample_shading {
            return Err(Error::invalid(
                "--samples",
                "does not apply to `view`, which draws one sample per pixel; use `render`",
            ));
        }
        if render.supersample != 1 {
            return Err(Error::invalid(
                "--supersample",
                "does not apply to `view`, which shows the swapchain's pixels; use `render`",
            ));
        }
        for (flag, given, why) in [
            (
                "--jitter",
                render.jitter.is_some(),
                "does not apply to `view`, whose frames follow the mouse; use `render`",
            ),
            (
                "--viewport",
                render.viewport.is_some(),
                "does not apply to `view`, which draws the whole window; use `render`",
            ),
        ] {
            if given {
                return Err(Error::invalid(flag, why));
            }
        }
        if render.intersection != IntersectionArg::Stable {
            return Err(Error::invalid(
                "--intersection",
                "the textbook baseline is for `render` and `bench`; `view` draws the shipped \
                 (stable) intersection",
            ));
        }
        if let Some(name) = &self.scene_name {
            if render.scene != RenderArgs::default().scene && render.scene != *name {
                return Err(Error::invalid(
                    "--scene",
                    format!(
                        "'{}' and the scene '{name}' both name a scene; give one",
                        render.scene
                    ),
                ));
            }
            render.scene = name.clone();
        }
        Ok(render)
    }
}

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

/// Ray/ellipsoid intersection formulation (`--intersection`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, Default)]
pub enum IntersectionArg {
    /// Gumhold's closed form in the silhouette frame (the shipped renderer).
    #[default]
    Stable,
    /// The textbook quadratic in float32: a baseline that breaks at large distance/radius.
    Textbook,
}

impl From<IntersectionArg> for ellipsoid_splat::research::Intersection {
    fn from(value: IntersectionArg) -> Self {
        match value {
            IntersectionArg::Stable => Self::Stable,
            IntersectionArg::Textbook => Self::Textbook,
        }
    }
}

/// Arguments of `conformance`.
#[derive(Debug, Clone, Args)]
pub struct ConformanceArgs {
    /// Device index or name substring (default: prefer a real GPU, fall back to lavapipe).
    #[arg(long)]
    pub device: Option<String>,
    /// Also write the outcomes as JUnit XML to this file.
    #[arg(long)]
    pub junit: Option<PathBuf>,
    /// Smaller scenes and images (seconds rather than a minute on a CPU driver).
    #[arg(long)]
    pub quick: bool,
    /// Draw every case with this benchmark method instead of the shipped renderer (the
    /// command's own test breaks it on purpose with `impostor-textbook`).
    #[arg(long, hide = true)]
    pub method: Option<String>,
}

/// Arguments of `stress`.
#[derive(Debug, Clone, Args)]
pub struct StressArgs {
    /// Directory for `stress.csv` and the plots.
    #[arg(long, default_value = "stress-out")]
    pub out: PathBuf,
    /// The reduced sweep the tests run: each parameter's extremes and a middle value, small
    /// images.
    #[arg(long)]
    pub quick: bool,
    /// Skip the textbook baseline rows.
    #[arg(long)]
    pub no_baseline: bool,
    /// Device and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
}

/// Device selection and validation.
#[derive(Debug, Clone, Args, Default)]
pub struct DeviceArgs {
    /// Device index or name substring (default: prefer a real GPU, fall back to lavapipe).
    #[arg(long)]
    pub device: Option<String>,
    /// Run with the Khronos validation layer (and synchronization validation); any message
    /// makes the command fail.
    #[arg(long)]
    pub validation: bool,
}

/// How scenes are read (see `scene::LoadOptions`) and coloured: what `render` and any other
/// command that shows a scene share.
#[derive(Debug, Clone, Args)]
pub struct LoadArgs {
    /// Glyph colours: the scene's own, or computed from each glyph's shape or orientation.
    #[arg(long, value_enum, value_name = "MODE", default_value_t = ColorArg::File)]
    pub color: ColorArg,
    /// Drop invalid records, report how many, and render the rest (default: fail on the
    /// first, naming where and why).
    #[arg(long)]
    pub skip_invalid: bool,
    /// Gaussian splats: radii are SIGMA standard deviations (`SIGMA * exp(scale)`).
    #[arg(long, default_value_t = 2.0, value_parser = parse_number, allow_hyphen_values = true)]
    pub sigma: f64,
    /// Gaussian splats: leave out splats whose opacity (after the sigmoid) is below this.
    #[arg(long, default_value_t = 0.0, value_parser = parse_number, allow_hyphen_values = true)]
    pub min_opacity: f64,
    /// Tensor volumes: component order of the six stored values.
    #[arg(long, value_enum, default_value_t = TensorOrderArg::Fsl)]
    pub tensor_order: TensorOrderArg,
    /// Tensor volumes: leave out voxels with fractional anisotropy below this.
    #[arg(long, default_value_t = 0.0, value_parser = parse_number, allow_hyphen_values = true)]
    pub min_fa: f64,
    /// Tensor volumes: a mask NIfTI on the same grid; voxels where it is 0 are left out.
    #[arg(long)]
    pub mask: Option<PathBuf>,
    /// Tensor volumes: the largest eigenvalue in the volume becomes a semi-axis of this many
    /// voxels.
    #[arg(long, default_value_t = 0.5, value_parser = parse_number, allow_hyphen_values = true)]
    pub glyph_scale: f64,
    /// Particle files (LAMMPS dumps, extended XYZ): read a standard column from a column of
    /// another name, `NAME=COLUMN,...` (as OVITO's column mapping), e.g.
    /// `shapex=c_shape[1],shapey=c_shape[2],shapez=c_shape[3]`.
    #[arg(long, value_name = "NAME=COLUMN,...", value_parser = parse_columns)]
    pub columns: Option<Vec<(String, String)>>,
    /// Particle files: the colours of types 1, 2, 3, ... (cycling), `r,g,b;r,g,b;...` with
    /// components in [0, 1] (default: a palette of ten).
    #[arg(long, value_name = "R,G,B;...", value_parser = parse_type_colors)]
    pub type_colors: Option<Vec<[f32; 3]>>,
}

impl LoadArgs {
    /// The first of these flags given a value other than its default, if any.
    pub fn given(&self) -> Option<&'static str> {
        let defaults = scene::LoadOptions::default();
        [
            ("--color", self.color != ColorArg::File),
            ("--skip-invalid", self.skip_invalid),
            ("--sigma", self.sigma != defaults.sigma),
            ("--min-opacity", self.min_opacity != defaults.min_opacity),
            ("--tensor-order", self.tensor_order != TensorOrderArg::Fsl),
            ("--min-fa", self.min_fa != defaults.min_fa),
            ("--mask", self.mask.is_some()),
            ("--glyph-scale", self.glyph_scale != defaults.glyph_scale),
            ("--columns", self.columns.is_some()),
            ("--type-colors", self.type_colors.is_some()),
        ]
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
    }

    /// The loader options these flags ask for.
    pub fn options(&self) -> scene::LoadOptions {
        scene::LoadOptions {
            skip_invalid: self.skip_invalid,
            sigma: self.sigma,
            min_opacity: self.min_opacity,
            tensor_order: match self.tensor_order {
                TensorOrderArg::Fsl => scene::TensorOrder::Fsl,
                TensorOrderArg::Nifti => scene::TensorOrder::Nifti,
            },
            min_fa: self.min_fa,
            mask: self.mask.clone(),
            glyph_scale: self.glyph_scale,
            progress: true,
            columns: self.columns.clone().unwrap_or_default(),
            type_colors: self.type_colors.clone().unwrap_or_default(),
        }
    }

    /// The colour mode `--color` asks for.
    pub fn color_mode(&self) -> scene::ColorMode {
        self.color.into()
    }

    /// Loads or generates `spec` with these options, then colours it in `--color`'s mode.
    pub fn load(&self, spec: &SceneSpec) -> Result<scene::Loaded> {
        let mut loaded = spec.load(&self.options())?;
        self.color_mode().apply(&mut loaded.scene.ellipsoids);
        Ok(loaded)
    }
}

/// Glyph colouring (`--color`); see `scene::ColorMode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorArg {
    /// The scene's colours: the file's (CSV r,g,b, splat f_dc, atom elements), else shape
    /// colours (tensor volumes, the tensor field, CSV without colours) or the random cloud's.
    File,
    /// Shape after Westin: linear red, planar green, spherical blue.
    Shape,
    /// RGB = |x|,|y|,|z| of the longest semi-axis's world direction (as diffusion-MRI viewers).
    Principal,
    /// `principal` times the fractional anisotropy of the semi-axes (spheres go black).
    PrincipalFa,
    /// One neutral grey for all.
    Uniform,
}

impl From<ColorArg> for scene::ColorMode {
    fn from(value: ColorArg) -> Self {
        match value {
            ColorArg::File => Self::File,
            ColorArg::Shape => Self::Shape,
            ColorArg::Principal => Self::Principal,
            ColorArg::PrincipalFa => Self::PrincipalFa,
            ColorArg::Uniform => Self::Uniform,
        }
    }
}

/// Component order of stored tensors (`--tensor-order`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TensorOrderArg {
    /// FSL (dtifit --save_tensor): xx, xy, xz, yy, yz, zz.
    Fsl,
    /// The NIfTI standard and DIPY (lower triangle by rows): xx, yx, yy, zx, zy, zz.
    Nifti,
}

/// The camera flags `render`, `view` and `bench --scene` share: where the camera is, where it
/// looks and its projection (the defaults frame the scene, see [`camera_for`]).
#[derive(Debug, Clone, Args)]
pub struct CameraArgs {
    /// Eye position `x,y,z` (default: frames the scene).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub eye: Option<DVec3>,
    /// Point looked at `x,y,z` (default: the scene's centre).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub target: Option<DVec3>,
    /// Up direction `x,y,z`.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    pub up: DVec3,
    /// Vertical field of view in degrees (perspective).
    #[arg(
        long,
        default_value_t = DEFAULT_FOV_Y,
        conflicts_with = "ortho",
        value_parser = parse_number,
        allow_hyphen_values = true
    )]
    pub fov_y: f64,
    /// Orthographic projection with this view height.
    #[arg(long, value_parser = parse_number, allow_hyphen_values = true)]
    pub ortho: Option<f64>,
    /// A pinhole camera's intrinsics `fx,fy,cx,cy` in pixels (OpenCV's; instead of --fov-y):
    /// the ray through pixel centre (i + 0.5, j + 0.5), row 0 at the top, has the camera-frame
    /// direction ((i + 0.5 - cx) / fx, (j + 0.5 - cy) / fy, 1), x right, y down, z forward.
    /// Off-centre principal points, asymmetric frusta and non-square pixels. In the camera's
    /// pixels (--viewport's size when given).
    #[arg(
        long,
        value_parser = parse_intrinsics,
        allow_hyphen_values = true,
        conflicts_with_all = ["ortho", "fov_y"]
    )]
    pub intrinsics: Option<Intrinsics>,
}

impl CameraArgs {
    /// The first of these flags given a value other than its default, if any.
    pub fn given(&self) -> Option<&'static str> {
        [
            ("--eye", self.eye.is_some()),
            ("--target", self.target.is_some()),
            ("--up", self.up != DVec3::Y),
            ("--fov-y", self.fov_y != DEFAULT_FOV_Y),
            ("--ortho", self.ortho.is_some()),
            ("--intrinsics", self.intrinsics.is_some()),
        ]
        .into_iter()
        .find_map(|(flag, given)| given.then_some(flag))
    }
}

/// The vertical field of view `--fov-y` defaults to, degrees.
pub const DEFAULT_FOV_Y: f64 = 45.0;

/// Arguments of `render`.
#[derive(Debug, Clone, Args)]
pub struct RenderArgs {
    /// A scene file -- Ellipsoid CSV (`.csv`), 3D Gaussian Splatting (`.ply`), diffusion tensor
    /// NIfTI (`.nii`, `.nii.gz`), PDB (`.pdb`, `.ent`) or mmCIF (`.cif`) with anisotropic
    /// displacements; other names are recognised by content -- or `tensor-field[:N]` (N^3
    /// glyphs, default 40), `lattice[:N]` (N^3 randomly rotated ellipsoids, default 40),
    /// `md-liquid[:N]` (a liquid of N rods and spheres, default 8000) or `random:COUNT`. At
    /// most 4294967295 ellipsoids (u32 instance indices), and no more than the machine's
    /// memory can hold.
    #[arg(long, default_value = "tensor-field")]
    pub scene: String,
    /// How the scene is read and coloured.
    #[command(flatten)]
    pub load: LoadArgs,
    /// Image width in pixels, 1 to 16384.
    #[arg(long, default_value_t = 1920, value_parser = parse_pixels, allow_negative_numbers = true)]
    pub width: u32,
    /// Image height in pixels, 1 to 16384.
    #[arg(long, default_value_t = 1080, value_parser = parse_pixels, allow_negative_numbers = true)]
    pub height: u32,
    /// Antialias with K x K samples per pixel (1 to 8): the frame is drawn K times larger and
    /// each K x K block averaged in linear light, an exact box filter. Depth, normal and ID
    /// hold one sample per pixel, at (K/2 + 0.5)/K of it (integer K/2). K x width and K x
    /// height must stay within 16384.
    #[arg(long, default_value_t = 1, value_parser = parse_samples, allow_negative_numbers = true)]
    pub supersample: u32,
    /// Multisample antialiasing: samples per pixel (1, or a power of two the device offers
    /// for colour, depth and integer attachments; lavapipe: 4). Shaded once per pixel with
    /// each sample's coverage exact, unless --per-sample-shading. The depth and ID images hold
    /// sample 0's (shaded once per pixel, the depth written there is the pixel's nearest
    /// covered sample's), the normal image the mean of the samples' normals.
    #[arg(long, default_value_t = 1, value_parser = parse_sample_count, allow_negative_numbers = true)]
    pub samples: u32,
    /// With --samples: run the shading at every sample (exact depth per sample; about the
    /// sample count times the cost) instead of once per pixel.
    #[arg(long)]
    pub per_sample_shading: bool,
    /// Also write the scene, as loaded and coloured, as Ellipsoid CSV to this file, its first
    /// line a comment with the camera as `render` flags (for other tools to draw the same
    /// frame); with --frames, the first frame drawn.
    #[arg(long, value_name = "FILE")]
    pub save_scene: Option<PathBuf>,
    /// The camera: where it is, where it looks, its projection.
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Sub-pixel jitter `dx,dy` in pixels (x right, y down): pixel (i, j) samples the
    /// unjittered image plane at (i + 0.5 + dx, j + 0.5 + dy), as a temporal antialiasing
    /// sequence does.
    #[arg(long, value_parser = parse_vec2, allow_hyphen_values = true)]
    pub jitter: Option<DVec2>,
    /// Draw the camera's w x h image into the rectangle `x,y,w,h` of the --width x --height
    /// output (camera pixel (i, j) is output pixel (x + i, y + j)); the rest stays
    /// background. --intrinsics and --jitter are in the camera's pixels.
    #[arg(long, value_parser = parse_viewport)]
    pub viewport: Option<[u32; 4]>,
    /// Draw these frames of a trajectory (LAMMPS dump, extended XYZ): `all`, `N`, `A:B` or
    /// `A:B:STEP`, numbered from 1, both ends included (`A:` runs to the last). Each image
    /// file gets the frame's number: in place of a `%d` or `%04d` in its name, or as `_0001`
    /// before the extension. The camera is framed by the first frame drawn unless given.
    #[arg(long, value_name = "FRAMES", value_parser = FrameRange::parse)]
    pub frames: Option<FrameRange>,
    /// With --frames: also encode the colour frames as a movie (`.mp4`, `.mkv`, `.webm`, ...;
    /// needs `ffmpeg`), in place of the colour image sequence.
    #[arg(long, value_name = "FILE", requires = "frames")]
    pub movie: Option<PathBuf>,
    /// The movie's frames per second, 1 to 240.
    #[arg(long, default_value_t = 24, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub fps: u32,
    /// Near-plane distance (default: half the distance to the scene's bounding sphere).
    #[arg(long, value_parser = parse_number, allow_hyphen_values = true)]
    pub near: Option<f64>,
    /// Colour PNG (`.png`).
    #[arg(long, default_value = "ellipsoids.png")]
    pub output: PathBuf,
    /// Float32 EXR of view depth (`.exr`; background +inf).
    #[arg(long)]
    pub depth: Option<PathBuf>,
    /// Float32 EXR of world-space unit normals (`.exr`; background 0).
    #[arg(long)]
    pub normal: Option<PathBuf>,
    /// Lossless 32-bit instance-ID image (`.exr`: uint channel; `.png`: RGBA8 little-endian).
    #[arg(long)]
    pub id: Option<PathBuf>,
    /// Ray/ellipsoid intersection formulation.
    #[arg(long, value_enum, default_value_t = IntersectionArg::Stable)]
    pub intersection: IntersectionArg,
    /// Store instances in the 32-byte compact format (float16 semi-axes, snorm16 rotation)
    /// instead of 48-byte float32: a third less GPU memory, at the error `bench` reports for
    /// `impostor-compact`.
    #[arg(long)]
    pub compact: bool,
    /// How the frame plan picks the exact path (the paths draw the same picture): `measure`
    /// times those that can serve the frame on frames of the same camera before the one
    /// written (at most 40) and keeps the fastest; `estimate` takes the first guess from the
    /// scene's size on screen; `draw`, `splat` and `visible-first` fix the path wherever it
    /// can serve the frame. Prints the path taken and why.
    #[arg(long, value_enum, value_name = "PLAN", default_value_t = PlanArg::Measure)]
    pub plan: PlanArg,
    /// Device and validation.
    #[command(flatten)]
    pub device: DeviceArgs,
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

/// The largest image side `render` accepts, in pixels (the renderer's own limit, and the
/// largest 2D image lavapipe and most GPUs allocate).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// What `render` was asked for, checked before anything is loaded, allocated or drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderPlan {
    /// The scene to load or generate.
    pub scene: SceneSpec,
    /// The images to produce.
    pub outputs: Outputs,
}

impl RenderArgs {
    /// The file `image` goes to, if it is asked for.
    pub fn file(&self, image: Image) -> Option<&Path> {
        match image {
            Image::Color => Some(&self.output),
            Image::Depth => self.depth.as_deref(),
            Image::Normal => self.normal.as_deref(),
            Image::Id => self.id.as_deref(),
        }
    }

    /// The images these arguments ask for: colour always, the others when their flag is
    /// given.
    pub fn outputs(&self) -> Outputs {
        {
            let mut outputs = Outputs::default();
            outputs.color = self.file(Image::Color).is_some();
            outputs.depth = self.file(Image::Depth).is_some();
            outputs.normal = self.file(Image::Normal).is_some();
            outputs.id = self.file(Image::Id).is_some();
            outputs
        }
    }

    /// The instance format `--compact` selects.
    pub fn instance_format(&self) -> InstanceFormat {
        if self.compact {
            InstanceFormat::Compact
        } else {
            InstanceFormat::Full
        }
    }

    /// Checks every argument that can be checked without the scene -- numbers, the scene's
    /// size, output names and whether the output files can be written -- so that a mistake
    /// is reported before anything is loaded, allocated or drawn. Errors name the flag.
    pub fn check(&self) -> Result<RenderPlan> {
        let scene = self.check_scene()?;
        let outputs = self.outputs();
        let files: Vec<(Image, &Path)> = Image::all_in(outputs)
            .filter_map(|image| Some((image, self.file(image)?)))
            .collect();
        if self.frames.is_some() {
            self.check_sequence_names(&files)?;
        } else {
            for &(image, path) in &files {
                output::check_extension(image, path)?;
            }
            for &(image, path) in &files {
                output::check_writable(image.flag(), path)?;
            }
        }
        let mut inputs: Vec<(&str, &Path)> = Vec::new();
        if let SceneSpec::File(path) = &scene {
            inputs.push(("--scene", path));
        }
        if let Some(path) = &self.save_scene {
            output::check_writable("--save-scene", path)?;
            if let SceneSpec::File(input) = &scene {
                if input
                    .canonicalize()
                    .is_ok_and(|i| i == output::resolved(path))
                {
                    return Err(Error::invalid(
                        "--save-scene",
                        format!("'{}' is the scene being read", path.display()),
                    ));
                }
            }
        }
        if let Some(mask) = &self.load.mask {
            inputs.push(("--mask", mask));
        }
        // A sequence's files are compared as frame 1's names (`x.png` and `x_%04d.png` both
        // number to `x_0001.png`).
        let named: Vec<(Image, PathBuf)> = files
            .iter()
            .map(|&(image, path)| match self.frames {
                Some(_) => output::numbered(image.flag(), path, 1).map(|p| (image, p)),
                None => Ok((image, path.to_path_buf())),
            })
            .collect::<Result<_>>()?;
        for (k, (image, path)) in named.iter().enumerate() {
            let (image, path) = (*image, path.as_path());
            let target = output::resolved(path);
            if let Some((other, _)) = named[..k]
                .iter()
                .find(|(_, p)| output::resolved(p) == target)
            {
                return Err(Error::invalid(
                    image.flag(),
                    format!(
                        "'{}' is also the {} file; each image needs a file of its own",
                        path.display(),
                        other.flag()
                    ),
                ));
            }
            if let Some((flag, _)) = inputs
                .iter()
                .find(|(_, input)| input.canonicalize().is_ok_and(|i| i == target))
            {
                return Err(Error::invalid(
                    image.flag(),
                    format!(
                        "'{}' is the {flag} input file; writing it would overwrite it",
                        path.display()
                    ),
                ));
            }
        }
        Ok(RenderPlan { scene, outputs })
    }

    /// Checks the sequence's file names (as frame 1's) and the movie's name, before anything is
    /// loaded: every name's pattern, every first file writable, the movie's directory there.
    fn check_sequence_names(&self, images: &[(Image, &Path)]) -> Result<()> {
        // With a movie the colour goes there, not to files.
        let files = images
            .iter()
            .filter(|(image, _)| !(*image == Image::Color && self.movie.is_some()));
        for &(image, path) in files {
            let first = output::numbered(image.flag(), path, 1)?;
            output::check_extension(image, &first)?;
            output::check_writable(image.flag(), &first)?;
        }
        if let Some(movie) = &self.movie {
            if movie.extension().is_none() {
                return Err(Error::invalid(
                    "--movie",
                    format!(
                        "'{}' has no extension, which names the movie's container (.mp4, .mkv, \
                         .webm, ...)",
                        movie.display()
                    ),
                ));
            }
            output::check_writable("--movie", movie)?;
        }
        Ok(())
    }

    /// Checks the numbers and the scene's name and size (what [`RenderArgs::check`] checks
    /// but the output files), naming the flag; the scene to load or generate.
    pub fn check_scene(&self) -> Result<SceneSpec> {
        self.check_numbers()?;
        let scene = SceneSpec::parse(&self.scene)?;
        if let Some(count) = scene.generated_count() {
            check_host_memory(&self.scene, count, self.instance_format(), machine_memory())?;
        }
        Ok(scene)
    }

    /// The camera's image size: the --viewport rectangle's, or the whole output's.
    pub fn camera_size(&self) -> (u32, u32) {
        match self.viewport {
            Some([_, _, w, h]) => (w, h),
            None => (self.width, self.height),
        }
    }

    /// Every numeric and vector flag on its own.
    fn check_numbers(&self) -> Result<()> {
        for (flag, value) in [("--width", self.width), ("--height", self.height)] {
            if !(1..=MAX_IMAGE_SIDE).contains(&value) {
                return Err(Error::invalid(
                    flag,
                    format!(
                        "{value} pixels is outside 1..={MAX_IMAGE_SIDE} (the largest image side \
                         the renderer accepts)"
                    ),
                ));
            }
        }
        if let Some([x, y, w, h]) = self.viewport {
            if x as u64 + w as u64 > self.width as u64 || y as u64 + h as u64 > self.height as u64 {
                return Err(Error::invalid(
                    "--viewport",
                    format!(
                        "the {w}x{h} rectangle at ({x}, {y}) reaches beyond the {}x{} output \
                         (--width, --height)",
                        self.width, self.height
                    ),
                ));
            }
        }
        if !self.samples.is_power_of_two() || self.samples > 64 {
            return Err(Error::invalid(
                "--samples",
                format!("{} is not a sample count (1, 2, 4, ... 64)", self.samples),
            ));
        }
        if self.per_sample_shading && self.samples == 1 {
            return Err(Error::invalid(
                "--per-sample-shading",
                "applies to multisampling: give --samples 2 or more",
            ));
        }
        let k = self.supersample;
        if !(1..=ellipsoid_splat::supersample::MAX_SUPERSAMPLE).contains(&k) {
            return Err(Error::invalid(
                "--supersample",
                format!(
                    "{k} is outside 1..={}",
                    ellipsoid_splat::supersample::MAX_SUPERSAMPLE
                ),
            ));
        }
        for (flag, value) in [("--width", self.width), ("--height", self.height)] {
            if value as u64 * k as u64 > MAX_IMAGE_SIDE as u64 {
                return Err(Error::invalid(
                    "--supersample",
                    format!(
                        "{k} x {flag} {value} = {} pixels is more than {MAX_IMAGE_SIDE}, the \
                         largest image side the renderer accepts",
                        value as u64 * k as u64
                    ),
                ));
            }
        }
        let positive = |flag: &str, value: f64| {
            if value.is_finite() && value > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    flag,
                    format!("must be positive (and finite), got {value}"),
                ))
            }
        };
        let number = |flag: &str, value: f64| {
            if value.is_nan() {
                Err(Error::invalid(flag, "must be a number, got NaN"))
            } else {
                Ok(())
            }
        };
        if let Some(near) = self.near {
            positive("--near", near)?;
        }
        match self.camera.ortho {
            Some(height) => positive("--ortho", height)?,
            None => {
                let fov = self.camera.fov_y;
                if !(fov.is_finite() && fov > 0.0 && fov < 180.0) {
                    return Err(Error::invalid(
                        "--fov-y",
                        format!("must be between 0 and 180 degrees (exclusive), got {fov}"),
                    ));
                }
            }
        }
        if self.camera.up == DVec3::ZERO {
            return Err(Error::invalid("--up", "must not be 0,0,0"));
        }
        if let (Some(eye), Some(target)) = (self.camera.eye, self.camera.target) {
            if eye == target {
                return Err(Error::invalid(
                    "--target",
                    format!(
                        "{} is the same point as --eye; the camera needs a direction",
                        xyz(target)
                    ),
                ));
            }
        }
        positive("--sigma", self.load.sigma)?;
        number("--min-opacity", self.load.min_opacity)?;
        number("--min-fa", self.load.min_fa)?;
        positive("--glyph-scale", self.load.glyph_scale)?;
        Ok(())
    }
}

/// `NAME=COLUMN,...` of `--columns`: each standard name once, neither side empty. Column names
/// may hold brackets but no commas (LAMMPS names never do).
fn parse_columns(text: &str) -> std::result::Result<Vec<(String, String)>, String> {
    let mut pairs: Vec<(String, String)> = Vec::new();
    for item in text.split(',') {
        let (name, column) = item
            .split_once('=')
            .map(|(n, c)| (n.trim(), c.trim()))
            .filter(|(n, c)| !n.is_empty() && !c.is_empty())
            .ok_or_else(|| format!("'{item}' is not NAME=COLUMN (e.g. shapex=c_shape[1])"))?;
        if pairs.iter().any(|(n, _)| n == name) {
            return Err(format!("{name} is mapped twice"));
        }
        pairs.push((name.to_string(), column.to_string()));
    }
    Ok(pairs)
}

/// `r,g,b;r,g,b;...` of `--type-colors`, each component a number in [0, 1].
fn parse_type_colors(text: &str) -> std::result::Result<Vec<[f32; 3]>, String> {
    text.split(';')
        .enumerate()
        .map(|(k, item)| {
            let [r, g, b] = parse_numbers::<3>(item, &format!("type {}'s colour as r,g,b", k + 1))?;
            let rgb = [r, g, b];
            if rgb.iter().any(|c| !(0.0..=1.0).contains(c)) {
                return Err(format!(
                    "type {}'s colour {item} has a component outside [0, 1]",
                    k + 1
                ));
            }
            Ok(rgb.map(|c| c as f32))
        })
        .collect()
}

/// A number flag's value. Such flags take values that start with `-`, so a flag given
/// where the value should be is reported as the missing value it is.
fn parse_number(text: &str) -> std::result::Result<f64, String> {
    text.trim().parse::<f64>().map_err(|_| {
        if text.starts_with("--") {
            format!("'{text}' is a flag, not a number: the value is missing")
        } else {
            format!("'{text}' is not a number")
        }
    })
}

/// `count` comma-separated finite numbers, named by `what`.
fn parse_numbers<const N: usize>(text: &str, what: &str) -> std::result::Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("expected {what}, got '{text}'"));
    }
    let mut v = [0.0; N];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse::<f64>()
            .map_err(|_| format!("'{part}' is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("'{part}' is not finite"));
        }
    }
    Ok(v)
}

fn parse_intrinsics(text: &str) -> std::result::Result<Intrinsics, String> {
    let [fx, fy, cx, cy] = parse_numbers(text, "fx,fy,cx,cy")?;
    if !(fx > 0.0 && fy > 0.0) {
        return Err(format!(
            "the focal lengths fx and fy must be positive, got {fx} and {fy}"
        ));
    }
    Ok(Intrinsics { fx, fy, cx, cy })
}

fn parse_vec2(text: &str) -> std::result::Result<DVec2, String> {
    parse_numbers(text, "dx,dy").map(DVec2::from_array)
}

fn parse_viewport(text: &str) -> std::result::Result<[u32; 4], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 4 {
        return Err(format!("expected x,y,w,h in whole pixels, got '{text}'"));
    }
    let mut v = [0u32; 4];
    for (slot, part) in v.iter_mut().zip(&parts) {
        *slot = part
            .parse::<u32>()
            .map_err(|_| format!("'{part}' is not a whole number of pixels"))?;
    }
    if v[2] == 0 || v[3] == 0 {
        return Err(format!("the rectangle {}x{} is empty", v[2], v[3]));
    }
    Ok(v)
}

fn parse_pixels(text: &str) -> std::result::Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{text}' is not a whole number of pixels (1 to {MAX_IMAGE_SIDE})"))
}

/// The `render` flags of `camera`'s view and image (numbers in Rust's shortest round-trip
/// form, so they read back to the same float64).
pub fn camera_flags(camera: &Camera) -> String {
    let v = |v: DVec3| format!("{:?},{:?},{:?}", v.x, v.y, v.z);
    let projection = match camera.projection {
        Projection::Perspective { fov_y_deg } => format!("--fov-y {fov_y_deg:?}"),
        Projection::Orthographic { height } => format!("--ortho {height:?}"),
        Projection::PerspectiveIntrinsics(i) => {
            format!("--intrinsics {:?},{:?},{:?},{:?}", i.fx, i.fy, i.cx, i.cy)
        }
        // No `render` flag makes the others (the library's orthographic intrinsics).
        other => format!("(projection {other:?}: no render flag)"),
    };
    format!(
        "--width {} --height {} --eye {} --target {} --up {} {projection} --near {:?}",
        camera.width,
        camera.height,
        v(camera.eye),
        v(camera.target),
        v(camera.up),
        camera.near
    )
}

fn parse_orbit_degrees(text: &str) -> std::result::Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(degrees) if (0.01..=90.0).contains(&degrees.abs()) => Ok(degrees),
        _ => Err(format!(
            "'{text}' is not an orbit step in degrees per frame (0.01 to 90, either sign)"
        )),
    }
}

fn parse_samples(text: &str) -> std::result::Result<u32, String> {
    text.trim().parse::<u32>().map_err(|_| {
        format!(
            "'{text}' is not a whole number of samples per side (1 to {})",
            ellipsoid_splat::supersample::MAX_SUPERSAMPLE
        )
    })
}

fn parse_sample_count(text: &str) -> std::result::Result<u32, String> {
    text.trim()
        .parse::<u32>()
        .map_err(|_| format!("'{text}' is not a sample count (1, 2, 4, ... 64)"))
}

fn parse_vec3(text: &str) -> std::result::Result<DVec3, String> {
    parse_numbers(text, "x,y,z").map(DVec3::from_array)
}

/// The most ellipsoids a scene can have. Instance indices are u32, and 0xFFFFFFFF
/// ([`NO_INSTANCE`]) marks background pixels in ID images, so indices run up to 0xFFFFFFFE.
pub const MAX_ELLIPSOIDS: u64 = NO_INSTANCE as u64;

/// The seed of `--scene lattice[:N]` (the benchmark's `lattice` scene).
pub const LATTICE_SEED: u64 = 1;

/// The seed of `--scene md-liquid[:N]` (the benchmark's `md-liquid` scene).
pub const MD_LIQUID_SEED: u64 = 1;

/// The particles of `--scene md-liquid` without a count (the benchmark's `md-liquid`).
pub const MD_LIQUID_COUNT: usize = 8000;

/// The side of the largest `tensor-field:N` or `lattice:N`: the largest N with N^3 <=
/// [`MAX_ELLIPSOIDS`].
pub const MAX_TENSOR_FIELD_SIDE: u64 = 1625;

/// Host bytes each ellipsoid surely takes while a scene is uploaded: its record in the scene
/// plus its packed instance. Real use is higher (a staging copy, the culling list, the
/// driver), so a scene refused for this is certainly too large.
pub fn host_bytes_per_ellipsoid(format: InstanceFormat) -> u64 {
    (std::mem::size_of::<Ellipsoid>() + format.bytes()) as u64
}

/// This machine's memory plus swap in bytes (`/proc/meminfo`), a fixed figure rather than
/// what happens to be free; `None` where it cannot be read.
pub fn machine_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib = |key: &str| {
        text.lines().find_map(|line| {
            line.strip_prefix(key)?
                .trim()
                .strip_suffix("kB")?
                .trim()
                .parse::<u64>()
                .ok()
        })
    };
    Some((kib("MemTotal:")? + kib("SwapTotal:").unwrap_or(0)) * 1024)
}

/// Refuses `count` ellipsoids in `format` when even [`host_bytes_per_ellipsoid`] of them
/// exceed `memory` bytes (the machine's memory and swap; no check when unknown).
pub fn check_host_memory(
    spec: &str,
    count: u64,
    format: InstanceFormat,
    memory: Option<u64>,
) -> Result<()> {
    let Some(memory) = memory else {
        return Ok(());
    };
    let per = host_bytes_per_ellipsoid(format);
    let needed = count.saturating_mul(per);
    if needed <= memory {
        return Ok(());
    }
    Err(Error::invalid(
        "--scene",
        format!(
            "{spec} needs at least {} of host memory for {count} ellipsoids ({} bytes each for \
             the scene and {} for its packed instance), more than this machine's {} of memory \
             and swap",
            gib(needed),
            std::mem::size_of::<Ellipsoid>(),
            format.bytes(),
            gib(memory)
        ),
    ))
}

fn gib(bytes: u64) -> String {
    format!("{:.1} GiB", bytes as f64 / (1u64 << 30) as f64)
}

/// A scene as `--scene` names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSpec {
    /// `tensor-field[:N]`: the N x N x N glyph lattice.
    TensorField(usize),
    /// `lattice[:N]`: N x N x N randomly rotated ellipsoids, semi-axes 0.1 to 0.45 (the
    /// benchmark's `lattice`, seed 1).
    Lattice(usize),
    /// `md-liquid[:N]`: a liquid of N rods and spheres (half each), seed [`MD_LIQUID_SEED`].
    MdLiquid(usize),
    /// `random:COUNT`: a random cloud.
    Random(usize),
    /// A scene file.
    File(PathBuf),
}

impl SceneSpec {
    /// Reads `--scene`; generated scenes must stay within [`MAX_ELLIPSOIDS`]. Errors name
    /// `--scene` and say why.
    pub fn parse(spec: &str) -> Result<Self> {
        let invalid = |reason: String| Error::invalid("--scene", reason);
        let side = format!(
            " (tensor-field:N and lattice:N have N^3 glyphs, so N can be at most \
             {MAX_TENSOR_FIELD_SIDE})"
        );
        let too_many = |count: String, note: &str| {
            invalid(format!(
                "{spec} asks for {count} ellipsoids, more than the {MAX_ELLIPSOIDS} the renderer \
                 can address{note}: instance indices are u32 (0xFFFFFFFF marks the background \
                 in ID images), and instances are {} bytes each on the GPU, so \
                 even that many take {}",
                InstanceFormat::Full.bytes(),
                gib(MAX_ELLIPSOIDS * InstanceFormat::Full.bytes() as u64)
            ))
        };
        // `cube`: the count is the number cubed (`tensor-field:N`).
        let count = |text: &str, what: &str, cube: bool| {
            text.trim().parse::<u64>().map_err(|e| match e.kind() {
                IntErrorKind::PosOverflow if cube => too_many(format!("{}^3", text.trim()), &side),
                IntErrorKind::PosOverflow => too_many(text.trim().to_string(), ""),
                _ => invalid(format!("{what} needs a whole number, got '{text}'")),
            })
        };
        // The cubes: `name` alone is 40^3, `name:N` is N^3.
        type Cube = fn(usize) -> SceneSpec;
        let cubes: [(&str, Cube); 2] = [
            ("tensor-field", SceneSpec::TensorField),
            ("lattice", SceneSpec::Lattice),
        ];
        for (name, make) in cubes {
            if spec == name {
                return Ok(make(40));
            }
            if let Some(text) = spec.strip_prefix(name).and_then(|t| t.strip_prefix(':')) {
                let n = count(text, &format!("{name}:N"), true)?;
                if n == 0 {
                    return Err(invalid(format!("{name}:N needs N >= 1")));
                }
                if n > MAX_TENSOR_FIELD_SIDE {
                    let glyphs = u128::from(n)
                        .checked_pow(3)
                        .map_or(format!("{n}^3"), |c| format!("{n}^3 = {c}"));
                    return Err(too_many(glyphs, &side));
                }
                return Ok(make(n as usize));
            }
        }
        if spec == "md-liquid" {
            return Ok(SceneSpec::MdLiquid(MD_LIQUID_COUNT));
        }
        if let Some(text) = spec.strip_prefix("md-liquid:") {
            let n = count(text, "md-liquid:N", false)?;
            if n == 0 {
                return Err(invalid("md-liquid:N needs N >= 1".to_string()));
            }
            if n > MAX_ELLIPSOIDS {
                return Err(too_many(n.to_string(), ""));
            }
            return Ok(SceneSpec::MdLiquid(n as usize));
        }
        if let Some(text) = spec.strip_prefix("random:") {
            let n = count(text, "random:COUNT", false)?;
            if n == 0 {
                return Err(invalid("random:COUNT needs COUNT >= 1".to_string()));
            }
            if n > MAX_ELLIPSOIDS {
                return Err(too_many(n.to_string(), ""));
            }
            return Ok(SceneSpec::Random(n as usize));
        }
        Ok(SceneSpec::File(PathBuf::from(spec)))
    }

    /// How many ellipsoids a generated scene has (`None` for a file).
    pub fn generated_count(&self) -> Option<u64> {
        match *self {
            SceneSpec::TensorField(n) | SceneSpec::Lattice(n) => Some((n as u64).pow(3)),
            SceneSpec::MdLiquid(n) | SceneSpec::Random(n) => Some(n as u64),
            SceneSpec::File(_) => None,
        }
    }

    /// Loads or generates the scene, with what the loader reports.
    pub fn load(&self, options: &scene::LoadOptions) -> Result<scene::Loaded> {
        let generated = |scene: Scene| scene::Loaded {
            scene,
            ..Default::default()
        };
        match self {
            SceneSpec::TensorField(n) => Ok(generated(scene::tensor_field(*n))),
            SceneSpec::Lattice(n) => Ok(generated(scene::lattice(*n, LATTICE_SEED))),
            SceneSpec::MdLiquid(n) => Ok(generated(scene::md_liquid(*n, MD_LIQUID_SEED))),
            SceneSpec::Random(n) => {
                let extent = (*n as f64).cbrt() * 2.0;
                Ok(generated(scene::random_cloud(*n, 1, extent, 1.0)))
            }
            SceneSpec::File(path) => Ok(scene::load(path, options)?),
        }
    }
}

/// Loads or generates the scene named by `--scene` after checking its size (see
/// [`SceneSpec::parse`] and [`check_host_memory`]), with what the loader reports.
pub fn load_scene(spec: &str, options: &scene::LoadOptions) -> Result<scene::Loaded> {
    let parsed = SceneSpec::parse(spec)?;
    if let Some(count) = parsed.generated_count() {
        check_host_memory(spec, count, InstanceFormat::Full, machine_memory())?;
    }
    parsed.load(options)
}

/// Writes `scene` as Ellipsoid CSV where `--save-scene` asks, its first line the camera as
/// `render` flags.
pub fn save_scene(args: &RenderArgs, scene: &Scene, camera: &Camera) -> Result<()> {
    if let Some(path) = &args.save_scene {
        let comment = format!("camera: {}", camera_flags(camera));
        scene::save_csv(scene, &[comment], path)?;
        eprintln!("wrote {} ({} ellipsoids)", path.display(), scene.len());
    }
    Ok(())
}

/// The camera of the render arguments, framing the scene where positions are not given.
/// Errors name the flag to change.
pub fn camera_for(args: &RenderArgs, scene: &Scene) -> Result<Camera> {
    camera_around(args, scene.bounding_sphere())
}

/// The camera of the render arguments, framing a scene of bounding sphere `sphere`
/// ([`Scene::bounding_sphere`]; `None` when empty) where positions are not given.
pub fn camera_around(args: &RenderArgs, sphere: Option<(DVec3, f64)>) -> Result<Camera> {
    let (center, radius) = sphere.ok_or_else(|| Error::invalid("--scene", "has no ellipsoids"))?;
    let projection = match (args.camera.ortho, args.camera.intrinsics) {
        (Some(height), _) => Projection::Orthographic { height },
        (None, Some(intrinsics)) => Projection::PerspectiveIntrinsics(intrinsics),
        (None, None) => Projection::Perspective {
            fov_y_deg: args.camera.fov_y,
        },
    };
    let (width, height) = args.camera_size();
    let mut camera = Camera::framing(center, radius, width, height)?;
    camera.projection = projection;
    camera.jitter = args.jitter.unwrap_or(DVec2::ZERO);
    if let Some([x, y, _, _]) = args.viewport {
        camera.viewport_origin = [x, y];
    }
    camera.up = args.camera.up;
    if let Some(target) = args.camera.target {
        camera.target = target;
    }
    if let Some(eye) = args.camera.eye {
        camera.eye = eye;
        if args.camera.target.is_none() {
            camera.target = center;
        }
    }
    let view = camera.target - camera.eye;
    if view.length() <= 1e-12 * camera.eye.length().max(1.0) {
        let (flag, what) = if args.camera.eye.is_some() && args.camera.target.is_none() {
            (
                "--eye",
                "is the scene's centre, which the camera looks at without --target",
            )
        } else {
            ("--target", "is where the camera is (--eye)")
        };
        return Err(Error::invalid(
            flag,
            format!(
                "{} {what}; give a --target away from --eye",
                xyz(camera.target)
            ),
        ));
    }
    if view.normalize().cross(args.camera.up.normalize()).length() < 1e-9 {
        return Err(Error::invalid(
            "--up",
            format!(
                "{} is parallel to the view direction (from {} to {}); give an --up across it",
                xyz(args.camera.up),
                xyz(camera.eye),
                xyz(camera.target)
            ),
        ));
    }
    camera.near = match args.near {
        Some(near) => near,
        None => {
            // Half way to the bounding sphere, or a small fraction of its size from inside.
            let gap = (center - camera.eye).length() - radius;
            if gap > 0.0 {
                0.5 * gap
            } else {
                radius * 1e-3
            }
        }
    };
    camera.validate().map_err(|e| match e {
        ellipsoid_splat::Error::Invalid { what, reason } if what.starts_with("camera ") => {
            let flag = match what.as_str() {
                "camera intrinsics" | "camera principal point"
                    if args.camera.intrinsics.is_some() =>
                {
                    "--intrinsics"
                }
                "camera principal point" | "camera jitter" => "--jitter",
                "camera viewport" => "--viewport",
                _ => return Error::invalid(what, reason),
            };
            Error::invalid(flag, reason)
        }
        other => Error::from(other),
    })?;
    Ok(camera)
}

/// Why `camera` certainly shows none of `scene`, if it does: the scene is behind the eye,
/// outside the field of view, or nearer than the near plane. Such an image is empty but not
/// an error (a camera path may pass by), so this is a warning to print.
pub fn nothing_in_view(args: &RenderArgs, camera: &Camera, scene: &Scene) -> Option<String> {
    nothing_in_view_around(args, camera, scene.bounding_sphere()?)
}

/// [`nothing_in_view`] of a scene of bounding sphere `(center, radius)`.
pub fn nothing_in_view_around(
    args: &RenderArgs,
    camera: &Camera,
    (center, radius): (DVec3, f64),
) -> Option<String> {
    let basis = camera.basis();
    let offset = center - camera.eye;
    let depth = offset.dot(basis.forward);
    let lateral = (offset - depth * basis.forward).length();
    let looking = format!(
        "looking from {} towards {} (--eye, --target)",
        xyz(camera.eye),
        xyz(camera.target)
    );
    let sphere = format!("centre {}, radius {radius:.4}", xyz(center));
    if depth + radius <= 0.0 {
        return Some(format!(
            "the image is empty: {looking}, the whole scene ({sphere}) is behind the camera"
        ));
    }
    // The screen-plane corner farthest from the view axis.
    let (lo, hi) = camera.screen_window();
    let half_diagonal = lo.x.abs().max(hi.x.abs()).hypot(lo.y.abs().max(hi.y.abs()));
    let outside = if camera.is_orthographic() {
        lateral - radius > half_diagonal
    } else {
        // The frustum lies in the cone of half-angle atan(half_diagonal) around the view
        // direction; the sphere is outside when its angular distance from the axis exceeds
        // that half-angle plus its own angular radius.
        let distance = offset.length();
        distance > radius && {
            let angle = lateral.atan2(depth);
            let angular_radius = (radius / distance).asin();
            angle - angular_radius > half_diagonal.atan()
        }
    };
    if outside {
        return Some(format!(
            "the image is empty: {looking}, the scene ({sphere}) is outside the field of view"
        ));
    }
    if depth + radius <= camera.near {
        let near = match args.near {
            Some(near) => format!("--near {near}"),
            None => format!("the near plane at {:.4}", camera.near),
        };
        return Some(format!(
            "the image is empty: {near} is beyond the farthest point of the scene (view depth \
             {:.4})",
            depth + radius
        ));
    }
    None
}

/// `v` as the flags write it, `x,y,z`, each to four decimals without trailing zeros.
fn xyz(v: DVec3) -> String {
    v.to_array()
        .map(|x| {
            let text = format!("{x:.4}");
            let text = text.trim_end_matches('0').trim_end_matches('.');
            if text == "-0" {
                "0".to_string()
            } else {
                text.to_string()
            }
        })
        .join(",")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn render_args(extra: &[&str]) -> RenderArgs {
        let args = ["ellipsoid-splat", "render"].iter().chain(extra);
        match Cli::try_parse_from(args).expect("parses").command {
            Some(Command::Render(r)) => *r,
            _ => unreachable!(),
        }
    }

    #[test]
    fn outputs_follow_the_flags() {
        let colour_only = render_args(&["--width", "16384", "--height", "16384"]).outputs();
        assert_eq!(colour_only, {
            let mut outputs = Outputs::default();
            outputs.color = true;
            outputs
        });
        assert_eq!(
            Image::all_in(colour_only).collect::<Vec<_>>(),
            vec![Image::Color]
        );
        let all =
            render_args(&["--depth", "d.exr", "--normal", "n.exr", "--id", "i.png"]).outputs();
        assert_eq!(all, {
            let mut outputs = Outputs::default();
            outputs.color = true;
            outputs.depth = true;
            outputs.normal = true;
            outputs.id = true;
            outputs
        });
        let id = render_args(&["--id", "i.exr"]).outputs();
        assert!(id.color && id.id && !id.depth && !id.normal);
    }

    #[test]
    fn color_modes_parse_by_their_names() {
        assert_eq!(
            render_args(&[]).load.color_mode(),
            scene::ColorMode::File,
            "the default keeps today's pictures"
        );
        for mode in scene::ColorMode::ALL {
            let args = render_args(&["--color", mode.name()]);
            assert_eq!(args.load.color_mode(), mode);
        }
        let args = ["ellipsoid-splat", "render", "--color", "rainbow"];
        let e = Cli::try_parse_from(args).unwrap_err().to_string();
        assert!(e.contains("'rainbow'") && e.contains("principal-fa"), "{e}");
    }

    #[test]
    fn scene_counts_are_bounded_by_addressing() {
        assert_eq!(
            SceneSpec::parse("random:4294967295").unwrap(),
            SceneSpec::Random(4294967295)
        );
        for spec in [
            "random:4294967296",
            "random:999999999999",
            "random:99999999999999999999999999",
            "tensor-field:1626",
            "tensor-field:99999999999999999999999999",
            "lattice:1626",
        ] {
            let e = SceneSpec::parse(spec).unwrap_err().to_string();
            assert!(
                e.contains("--scene") && e.contains("4294967295") && e.contains("u32"),
                "{spec}: {e}"
            );
        }
        assert_eq!(
            SceneSpec::parse("tensor-field:1625")
                .unwrap()
                .generated_count(),
            Some(1625u64.pow(3))
        );
        assert!(1625u64.pow(3) <= MAX_ELLIPSOIDS && 1626u64.pow(3) > MAX_ELLIPSOIDS);
        assert_eq!(SceneSpec::parse("lattice").unwrap(), SceneSpec::Lattice(40));
        assert_eq!(
            SceneSpec::parse("lattice:3").unwrap(),
            SceneSpec::Lattice(3)
        );
        let e = SceneSpec::parse("lattice:0").unwrap_err().to_string();
        assert!(e.contains("lattice:N needs N >= 1"), "{e}");
        let e = SceneSpec::parse("random:12x").unwrap_err().to_string();
        assert!(e.contains("needs a whole number, got '12x'"), "{e}");
    }

    #[test]
    fn md_liquid_takes_a_particle_count() {
        assert_eq!(
            SceneSpec::parse("md-liquid").unwrap(),
            SceneSpec::MdLiquid(MD_LIQUID_COUNT)
        );
        let spec = SceneSpec::parse("md-liquid:300").unwrap();
        assert_eq!(spec, SceneSpec::MdLiquid(300));
        assert_eq!(spec.generated_count(), Some(300));
        let scene = spec.load(&scene::LoadOptions::default()).unwrap().scene;
        assert_eq!(scene.len(), 300);
        for (text, reason) in [
            ("md-liquid:0", "md-liquid:N needs N >= 1"),
            ("md-liquid:many", "needs a whole number, got 'many'"),
            ("md-liquid:4294967296", "4294967295"),
        ] {
            let e = SceneSpec::parse(text).unwrap_err().to_string();
            assert!(e.contains("--scene") && e.contains(reason), "{text}: {e}");
        }
    }

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

    #[test]
    fn host_memory_estimate_refuses_what_cannot_fit() {
        let per = host_bytes_per_ellipsoid(InstanceFormat::Full);
        assert_eq!(per, 96 + 48);
        let eight_gib = Some(8u64 << 30);
        assert!(check_host_memory("random:1000", 1000, InstanceFormat::Full, eight_gib).is_ok());
        let fits = (8u64 << 30) / per;
        assert!(check_host_memory("x", fits, InstanceFormat::Full, eight_gib).is_ok());
        let e = check_host_memory("random:N", fits + 1, InstanceFormat::Full, eight_gib)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("--scene") && e.contains("host memory") && e.contains("8.0 GiB"),
            "{e}"
        );
        // Compact instances take less.
        let compact = (8u64 << 30) / host_bytes_per_ellipsoid(InstanceFormat::Compact);
        assert!(check_host_memory("x", compact, InstanceFormat::Compact, eight_gib).is_ok());
        assert!(check_host_memory("x", u64::MAX, InstanceFormat::Full, None).is_ok());
        assert!(machine_memory().is_none_or(|m| m > 0));
    }

    #[test]
    fn empty_views_are_reported() {
        let scene = scene::random_cloud(10, 1, 4.0, 1.0);
        let warn = |extra: &[&str]| {
            let args = render_args(extra);
            let camera = camera_for(&args, &scene).unwrap();
            nothing_in_view(&args, &camera, &scene)
        };
        assert_eq!(warn(&[]), None);
        let behind = warn(&["--eye", "0,0,100", "--target", "0,0,200"]).unwrap();
        assert!(behind.contains("behind the camera"), "{behind}");
        let near = warn(&["--near", "1e6"]).unwrap();
        assert!(near.contains("--near"), "{near}");
        let aside = warn(&["--eye", "0,0,100", "--target", "500,0,100"]).unwrap();
        assert!(aside.contains("outside the field of view"), "{aside}");
        let ortho_aside = warn(&["--eye", "0,0,100", "--target", "500,0,100", "--ortho", "2"]);
        assert!(ortho_aside.is_some());
        assert_eq!(warn(&["--ortho", "2"]), None);
    }
}
