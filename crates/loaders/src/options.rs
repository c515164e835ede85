//! What the loaders may be told: [`LoadOptions`], shared by every format.

use std::path::PathBuf;

/// The order of the six components of a symmetric tensor stored per voxel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TensorOrder {
    /// FSL (`dtifit --save_tensor`): `xx, xy, xz, yy, yz, zz`.
    #[default]
    Fsl,
    /// The NIfTI standard (`NIFTI_INTENT_SYMMATRIX`, lower triangle row by row), also DIPY's:
    /// `xx, yx, yy, zx, zy, zz`.
    Nifti,
}

/// What the loaders may be told.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadOptions {
    /// Drop invalid records (counted in [`Loaded::skipped`](crate::Loaded::skipped)) instead of failing on the first.
    pub skip_invalid: bool,
    /// 3D Gaussian Splatting: radii are `sigma * exp(scale)` (the iso-level in standard
    /// deviations).
    pub sigma: f64,
    /// 3D Gaussian Splatting: splats whose opacity (after the sigmoid) is below this are left
    /// out (not counted as invalid).
    pub min_opacity: f64,
    /// Tensor volumes: the component order of the stored tensors.
    pub tensor_order: TensorOrder,
    /// Tensor volumes: voxels with fractional anisotropy below this are left out.
    pub min_fa: f64,
    /// Tensor volumes: a mask volume of the same grid; voxels where it is 0 are left out.
    pub mask: Option<PathBuf>,
    /// Tensor volumes: glyph semi-axes are the tensor's eigenvalues scaled so that the
    /// largest in the volume is `glyph_scale` voxels (the smallest voxel edge).
    pub glyph_scale: f64,
    /// Show a progress bar on stderr while reading large files (only when it is a terminal).
    pub progress: bool,
    /// Particle files (LAMMPS dumps, extended XYZ): `(our standard name, the file's column
    /// name)` pairs, e.g. `("shapex", "c_shape[1]")` for a dump of
    /// a compute's output. A standard name not mapped is looked for under its own name; a
    /// mapping to a column the file lacks is an error. The standard names are listed in the
    /// [`lammps`](crate::lammps) and [`xyz`](crate::xyz) modules.
    pub columns: Vec<(String, String)>,
    /// Particle files: the colours of types 1, 2, 3, ... (cycling), each component in [0, 1];
    /// empty means [`TYPE_PALETTE`](crate::TYPE_PALETTE).
    pub type_colors: Vec<[f32; 3]>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self {
            skip_invalid: false,
            sigma: 2.0,
            min_opacity: 0.0,
            tensor_order: TensorOrder::Fsl,
            min_fa: 0.0,
            mask: None,
            glyph_scale: 0.5,
            progress: false,
            columns: Vec::new(),
            type_colors: Vec::new(),
        }
    }
}
