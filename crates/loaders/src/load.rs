//! Reads a scene file of any supported format: the format is chosen by extension, or by
//! content when the extension says nothing. The options and the report of a load live in
//! `options` and `loaded` (so that the loaders need not import this module, which imports
//! them) and are re-exported here.

use std::path::Path;

use crate::error::io_error;
pub use crate::loaded::{Loaded, Origins};
pub use crate::options::{LoadOptions, TensorOrder};
use crate::Result;

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
        let inner = crate::gzip::gzip_head(path, 4096)?;
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
        Format::LammpsDump => crate::lammps::load_lammps(path, options),
        Format::ExtendedXyz => crate::xyz::load_xyz(path, options),
    }
}
