//! `render`'s arguments, and what they name: the files of each image, the instance format,
//! the camera's image size. They are checked in `render_check`.

use std::path::{Path, PathBuf};

use clap::Args;
use glam::DVec2;

use super::camera::CameraArgs;
use super::device::DeviceArgs;
use super::load::LoadArgs;
use super::values::{
    parse_number, parse_pixels, parse_sample_count, parse_samples, parse_vec2, parse_viewport,
};
use crate::frame_range::FrameRange;
use crate::output::Image;
use crate::plan::PlanArg;
use ellipsoid_splat::{InstanceFormat, Outputs};

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

/// The largest image side `render` accepts, in pixels (the renderer's own limit, and the
/// largest 2D image lavapipe and most GPUs allocate).
pub const MAX_IMAGE_SIDE: u32 = 16384;

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

    /// The camera's image size: the --viewport rectangle's, or the whole output's.
    pub fn camera_size(&self) -> (u32, u32) {
        match self.viewport {
            Some([_, _, w, h]) => (w, h),
            None => (self.width, self.height),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::render_args;

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
}
