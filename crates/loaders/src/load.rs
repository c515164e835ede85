//! Reads a scene file of any supported format: the format is chosen by extension, or by
//! content when the extension says nothing. Also the options every loader shares, the report of
//! what it did, and the small helpers the loaders have in common (reading a file, building a
//! parse error).

use std::path::{Path, PathBuf};

use crate::{Error, Result};
use ellipsoid_splat::Scene;

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
    /// Drop invalid records (counted in [`Loaded::skipped`]) instead of failing on the first.
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
    /// name)` pairs, as OVITO's column mapping, e.g. `("shapex", "c_shape[1]")` for a dump of
    /// a compute's output. A standard name not mapped is looked for under its own name; a
    /// mapping to a column the file lacks is an error. The standard names are listed in the
    /// [`lammps`](crate::lammps) and [`xyz`](crate::xyz) modules.
    pub columns: Vec<(String, String)>,
    /// Particle files: the colours of types 1, 2, 3, ... (cycling), each component in [0, 1];
    /// empty means [`TYPE_PALETTE`](crate::trajectory::TYPE_PALETTE).
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

/// A loaded scene and what the loader has to say about it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Loaded {
    /// The ellipsoids.
    pub scene: Scene,
    /// Records dropped as invalid (only with `skip_invalid`).
    pub skipped: usize,
    /// Lines for the user: parameters in effect, records filtered out and why.
    pub notes: Vec<String>,
    /// Where each glyph came from in the file (a viewer's pick reports it).
    pub origins: Origins,
}

/// Where each glyph of a loaded file came from, one entry per glyph in scene order (a few
/// bytes each: kept for every glyph so that a pick can name its record).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Origins {
    /// Not recorded (generated scenes: the index says it all).
    #[default]
    None,
    /// The 1-based line of each glyph's row (Ellipsoid CSV).
    Lines(Vec<u32>),
    /// The 0-based vertex index of each splat (3D Gaussian Splatting PLY); described 1-based,
    /// as the PLY loader's errors number vertices.
    Vertices(Vec<u32>),
    /// The voxel `(i, j, k)` of each glyph (NIfTI tensor volumes).
    Voxels(Vec<[u16; 3]>),
    /// The line and label (`atom 5 CA (ALA A 1)`) of each atom (PDB, mmCIF).
    Atoms(Vec<(u32, String)>),
    /// The 1-based line and the atom id of each particle (LAMMPS dumps, extended XYZ); where
    /// the file has no `id` column, the id is the particle's 1-based place in its frame.
    Particles(Vec<(u32, i64)>),
}

impl Origins {
    /// What glyph `index` came from, in words, if recorded.
    pub fn describe(&self, index: usize) -> Option<String> {
        match self {
            Origins::None => None,
            Origins::Lines(lines) => lines.get(index).map(|l| format!("line {l}")),
            // 1-based like the loader's "vertex N" errors; u64 so u32::MAX cannot overflow.
            Origins::Vertices(v) => v
                .get(index)
                .map(|&v| format!("splat (vertex) {}", u64::from(v) + 1)),
            Origins::Voxels(v) => v
                .get(index)
                .map(|[i, j, k]| format!("voxel (i, j, k) = ({i}, {j}, {k})")),
            Origins::Atoms(a) => a
                .get(index)
                .map(|(line, label)| format!("{label}, line {line}")),
            Origins::Particles(p) => p
                .get(index)
                .map(|(line, id)| format!("atom id {id}, line {line}")),
        }
    }
}

/// The file formats `load` reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The Ellipsoid CSV of the contract (`x,y,z` and radii+quaternion or a tensor).
    Csv,
    /// A 3D Gaussian Splatting PLY.
    GaussianPly,
    /// A NIfTI-1 diffusion tensor volume (`.nii`, `.nii.gz`).
    Nifti,
    /// A PDB file with ANISOU records.
    Pdb,
    /// An mmCIF file with anisotropic displacement parameters.
    MmCif,
    /// A LAMMPS `dump custom` text file, one or more frames (`.lammpstrj`, `.dump`,
    /// `.lammpsdump`, plain or gzipped).
    LammpsDump,
    /// An extended XYZ file (ASE, OVITO, GPUMD), one or more frames (`.xyz`, `.extxyz`, plain
    /// or gzipped).
    ExtendedXyz,
}

/// The format of `path`: by extension, else by the first bytes of the file.
pub fn detect_format(path: &Path) -> Result<Format> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let by_extension = [
        (".csv", Format::Csv),
        (".ply", Format::GaussianPly),
        (".nii", Format::Nifti),
        (".nii.gz", Format::Nifti),
        (".pdb", Format::Pdb),
        (".ent", Format::Pdb),
        (".cif", Format::MmCif),
        (".mmcif", Format::MmCif),
        (".lammpstrj", Format::LammpsDump),
        (".dump", Format::LammpsDump),
        (".lammpsdump", Format::LammpsDump),
        (".xyz", Format::ExtendedXyz),
        (".extxyz", Format::ExtendedXyz),
    ];
    // A gzipped particle file keeps its format's extension before `.gz` (the other loaders,
    // but NIfTI's `.nii.gz`, read no gzip).
    let particles = [".lammpstrj", ".dump", ".lammpsdump", ".xyz", ".extxyz"];
    let name = match name.strip_suffix(".gz") {
        Some(inner) if particles.iter().any(|ext| inner.ends_with(ext)) => inner.to_string(),
        _ => name,
    };
    if let Some((_, format)) = by_extension.iter().find(|(ext, _)| name.ends_with(ext)) {
        return Ok(*format);
    }
    // 352 bytes hold a NIfTI header; an extended XYZ comment line can be long.
    let mut head = vec![0u8; 4096];
    let read = {
        use std::io::Read;
        let mut file = std::fs::File::open(path).map_err(io_error(path))?;
        file.read(&mut head).map_err(io_error(path))?
    };
    let head = &head[..read];
    // gzip is NIfTI unless the stream inside is a particle file: look at its first bytes.
    if head.starts_with(&[0x1f, 0x8b]) {
        let inner = crate::trajectory::gzip_head(path, 4096)?;
        let format = particle_format(&inner).unwrap_or(Format::Nifti);
        log::debug!(
            "{}: gzip, read as {format:?} by its content",
            path.display()
        );
        return Ok(format);
    }
    if let Some(format) = particle_format(head) {
        log::debug!("{}: read as {format:?} by its first lines", path.display());
        return Ok(format);
    }
    let text = String::from_utf8_lossy(head);
    // mmCIF may open with a byte-order mark, blank lines or `#` comments before `data_`.
    let cif_start = text
        .trim_start_matches('\u{feff}')
        .lines()
        .map(str::trim)
        .find(|line| !line.is_empty() && !line.starts_with('#'))
        .unwrap_or("");
    let format = if head.starts_with(b"ply") {
        Format::GaussianPly
    } else if (head.len() >= 348 && matches!(&head[344..348], b"n+1\0" | b"ni1\0"))
        // gzip: the only compressed format read
        || head.starts_with(&[0x1f, 0x8b])
    {
        Format::Nifti
    } else if cif_start.starts_with("data_") {
        Format::MmCif
    } else if [
        "HEADER", "CRYST1", "ATOM  ", "HETATM", "REMARK", "TITLE ", "COMPND", "EXPDTA", "MODEL ",
        "AUTHOR", "KEYWDS", "SOURCE",
    ]
    .iter()
    .any(|tag| text.starts_with(tag))
    {
        Format::Pdb
    } else {
        Format::Csv
    };
    log::debug!(
        "{}: no known extension, read as {format:?} by its first {read} bytes",
        path.display()
    );
    Ok(format)
}

/// A LAMMPS dump (`ITEM:` at the start) or an extended XYZ file (an integer line, then a
/// line with `Properties=`), by the first bytes of its text.
fn particle_format(head: &[u8]) -> Option<Format> {
    let text = String::from_utf8_lossy(head);
    let mut lines = text.trim_start_matches('\u{feff}').lines();
    let first = lines.next()?.trim();
    if first.starts_with("ITEM:") {
        return Some(Format::LammpsDump);
    }
    let second = lines.next()?;
    (first.parse::<u64>().is_ok() && second.contains("Properties=")).then_some(Format::ExtendedXyz)
}

/// Loads the scene in `path`, in the format `detect_format` finds; of a file with several
/// frames (a LAMMPS dump or extended XYZ trajectory), frame 1, with a note giving the number
/// of frames ([`Trajectory`](crate::Trajectory) reads the others).
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let format = detect_format(path)?;
    let started = std::time::Instant::now();
    let loaded = load_format(path, format, options)?;
    log::debug!(
        "{}: {} ellipsoids from {format:?} in {:.1} ms ({} skipped as invalid)",
        path.display(),
        loaded.scene.len(),
        started.elapsed().as_secs_f64() * 1e3,
        loaded.skipped
    );
    Ok(loaded)
}

/// Loads `path` as `format`.
pub(crate) fn load_format(path: &Path, format: Format, options: &LoadOptions) -> Result<Loaded> {
    match format {
        Format::Csv => crate::csv::load_csv_with(path, options),
        Format::GaussianPly => crate::ply::load_ply(path, options),
        Format::Nifti => crate::nifti::load_nifti(path, options),
        Format::Pdb | Format::MmCif => crate::pdb::load_structure(path, options),
        Format::LammpsDump | Format::ExtendedXyz => {
            crate::trajectory::load_first(path, format, options)
        }
    }
}

/// Maps an I/O error on `path` to [`Error::Io`].
pub(crate) fn io_error(path: &Path) -> impl Fn(std::io::Error) -> Error + Copy + '_ {
    move |source| Error::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The whole content of `path`, or an [`Error::Io`] naming it.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(io_error(path))
}

/// An [`Error::Parse`]: `line` is 1-based, 0 when the problem is not tied to a line.
pub(crate) fn parse_error(
    file: &Path,
    line: usize,
    column: impl Into<String>,
    reason: impl Into<String>,
) -> Error {
    Error::Parse {
        file: file.to_path_buf(),
        line,
        column: column.into(),
        reason: reason.into(),
    }
}

/// The 1-based line of byte `offset` in `bytes`.
pub(crate) fn line_at(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count()
}
