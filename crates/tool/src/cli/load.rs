//! How scenes are read and coloured: the loading flags `render`, `view` and `bench --scene`
//! share, turned into the loaders' options.

use std::path::PathBuf;

use clap::Args;
use ellipsoid_splat_loaders as scene;

use super::values::{parse_columns, parse_number, parse_type_colors};

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::{render_args, Cli};
    use clap::Parser;

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
}
