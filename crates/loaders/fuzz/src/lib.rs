//! What each fuzz target feeds its input to. Shared by the libFuzzer targets in
//! `fuzz_targets/` (nightly, `cargo +nightly fuzz run <target>`) and by the stable replay test
//! `tests/fuzz_corpus.rs` of the loaders crate, which includes this file with `#[path]`, so the
//! corpus is replayed through exactly the calls the fuzzers made.
//!
//! Every input goes through its parser twice, with `skip_invalid` off and on (the default
//! `LoadOptions` otherwise): the two paths differ. "No crash" means each call returns `Ok` or
//! `Err`; the result is not checked.

use std::path::{Path, PathBuf};

use ellipsoid_splat_loaders::csv::{load_csv_with, parse_csv};
use ellipsoid_splat_loaders::load::{Format, LoadOptions};
use ellipsoid_splat_loaders::nifti::parse_nifti;
use ellipsoid_splat_loaders::pdb::parse_structure;
use ellipsoid_splat_loaders::ply::parse_ply;
use ellipsoid_splat_loaders::Trajectory;

/// One fuzz target per parser (PDB and mmCIF are two dialects of one parser, picked by the
/// file name's extension, so two targets).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// `csv::parse_csv` (UTF-8 inputs only), and `csv::load_csv_with` on a
    /// temporary file for `skip_invalid` (there is no in-memory entry point taking options).
    Csv,
    /// `ply::parse_ply`.
    Ply,
    /// `nifti::parse_nifti` (plain or gzipped NIfTI-1).
    Nifti,
    /// `pdb::parse_structure` with a `.pdb` file name.
    Pdb,
    /// `pdb::parse_structure` with a `.cif` file name.
    Mmcif,
    /// `Trajectory::from_bytes` as a LAMMPS dump (plain or gzipped), then every frame
    /// (at most [`MAX_FRAMES`]).
    Lammps,
    /// `Trajectory::from_bytes` as extended XYZ (plain or gzipped), then every frame (at most
    /// [`MAX_FRAMES`]).
    Xyz,
}

/// The frames of a trajectory target parsed per input: enough for every code path, few enough
/// that an input of many tiny frames stays fast.
pub const MAX_FRAMES: usize = 64;

impl Target {
    /// Every target.
    pub const ALL: [Target; 7] = [
        Target::Csv,
        Target::Ply,
        Target::Nifti,
        Target::Pdb,
        Target::Mmcif,
        Target::Lammps,
        Target::Xyz,
    ];

    /// The target's name: its `cargo fuzz` binary and its `corpus/` and `regressions/`
    /// subdirectory.
    pub fn name(self) -> &'static str {
        match self {
            Target::Csv => "csv",
            Target::Ply => "ply",
            Target::Nifti => "nifti",
            Target::Pdb => "pdb",
            Target::Mmcif => "mmcif",
            Target::Lammps => "lammps",
            Target::Xyz => "xyz",
        }
    }

    /// The file name the parser is told (only named in errors, except that `parse_structure`
    /// picks the dialect by its extension).
    pub fn file_name(self) -> &'static str {
        match self {
            Target::Csv => "fuzz.csv",
            Target::Ply => "fuzz.ply",
            Target::Nifti => "fuzz.nii",
            Target::Pdb => "fuzz.pdb",
            Target::Mmcif => "fuzz.cif",
            Target::Lammps => "fuzz.lammpstrj",
            Target::Xyz => "fuzz.extxyz",
        }
    }

    /// Feeds `data` to the target's parser with `skip_invalid` off, then on.
    pub fn run(self, data: &[u8]) {
        for skip_invalid in [false, true] {
            let _ = self.run_with(data, skip_invalid);
        }
    }

    /// Feeds `data` to the target's parser once: the number of ellipsoids, or the error.
    pub fn run_with(self, data: &[u8], skip_invalid: bool) -> Result<usize, String> {
        let options = LoadOptions {
            skip_invalid,
            ..LoadOptions::default()
        };
        let file = Path::new(self.file_name());
        match self {
            Target::Csv if !skip_invalid => match std::str::from_utf8(data) {
                Ok(text) => parse_csv(text, file).map(|scene| scene.len()),
                Err(e) => return Err(format!("not UTF-8: {e}")),
            },
            Target::Csv => csv_skip_invalid(data, &options),
            Target::Ply => parse_ply(data, file, &options).map(|l| l.scene.len()),
            Target::Nifti => parse_nifti(data, file, &options).map(|l| l.scene.len()),
            Target::Pdb | Target::Mmcif => {
                parse_structure(data, file, &options).map(|l| l.scene.len())
            }
            Target::Lammps => frames(data, file, Format::LammpsDump, &options),
            Target::Xyz => frames(data, file, Format::ExtendedXyz, &options),
        }
        .map_err(|e| e.to_string())
    }
}

/// Opens `data` as a trajectory and parses its frames (the first [`MAX_FRAMES`]), also past a
/// bad one: the total number of ellipsoids, or the first error.
fn frames(
    data: &[u8],
    file: &Path,
    format: Format,
    options: &LoadOptions,
) -> ellipsoid_splat_loaders::Result<usize> {
    let trajectory = Trajectory::from_bytes(data.to_vec(), file, format, options)?;
    let mut total = Ok(0);
    for i in 0..trajectory.len().min(MAX_FRAMES) {
        let _ = trajectory.timestep(i);
        match (trajectory.frame(i), &mut total) {
            (Ok(loaded), Ok(n)) => *n += loaded.scene.len(),
            (Err(e), Ok(_)) => total = Err(e),
            _ => {}
        }
    }
    // One past the end is a named error, never a panic.
    let _ = trajectory.frame(trajectory.len());
    total
}

/// `parse_csv` has no options and the row parser behind `load_csv_with` is private, so the
/// `skip_invalid` path is reached through a file: one per process and thread, in the temporary
/// directory, removed afterwards. (Any bytes: the UTF-8 check is part of `load_csv_with`.)
fn csv_skip_invalid(data: &[u8], options: &LoadOptions) -> ellipsoid_splat_loaders::Result<usize> {
    thread_local! {
        static PATH: PathBuf = std::env::temp_dir().join(format!(
            "ellipsoid-splat-fuzz-{}-{:?}.csv",
            std::process::id(),
            std::thread::current().id()
        ).replace(['(', ')'], ""));
    }
    PATH.with(|path| {
        std::fs::write(path, data).expect("cannot write the temporary CSV file");
        let loaded = load_csv_with(path, options);
        let _ = std::fs::remove_file(path);
        loaded.map(|l| l.scene.len())
    })
}
