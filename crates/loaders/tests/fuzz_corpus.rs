//! Replays the fuzz corpus on stable Rust: every file under `fuzz/corpus/<target>/` and
//! `fuzz/regressions/<target>/` goes to the parser its fuzz target calls, with `skip_invalid`
//! off and on, and must come back as `Ok` or `Err`, never as a panic. The calls are the fuzz
//! targets' own (`fuzz/src/lib.rs`, included below), so a crash found by `cargo fuzz` and saved
//! under `fuzz/regressions/` stays fixed. With `FUZZ_CORPUS_VERBOSE` set (and `--nocapture`),
//! every file's outcome is printed.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

#[path = "../fuzz/src/lib.rs"]
#[allow(dead_code)]
mod fuzz_targets;

use fuzz_targets::Target;

/// The files of `dir` (not recursive), sorted; none when it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.expect("readable directory entry").path())
        .filter(|p| p.is_file())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n != ".gitkeep" && n != "README.md")
        })
        .collect();
    files.sort();
    files
}

/// Replays `target`'s corpus and regressions; returns how many files it fed.
fn replay(target: Target) -> usize {
    let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let corpus = files(&fuzz.join("corpus").join(target.name()));
    assert!(
        !corpus.is_empty(),
        "no seed corpus for fuzz target `{}` in fuzz/corpus/{}/",
        target.name(),
        target.name()
    );
    let regressions = files(&fuzz.join("regressions").join(target.name()));
    let verbose = std::env::var_os("FUZZ_CORPUS_VERBOSE").is_some();
    let mut failures = Vec::new();
    for path in corpus.iter().chain(&regressions) {
        let data = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        for skip_invalid in [false, true] {
            let outcome = catch_unwind(AssertUnwindSafe(|| target.run_with(&data, skip_invalid)));
            if verbose {
                // `FUZZ_CORPUS_VERBOSE=1 cargo test --test fuzz_corpus -- --nocapture`
                let shown = match &outcome {
                    Ok(Ok(n)) => format!("Ok: {n} ellipsoids"),
                    Ok(Err(e)) => format!("Err: {e}"),
                    Err(_) => "PANIC".to_owned(),
                };
                println!("{} [skip_invalid: {skip_invalid}] {shown}", path.display());
            }
            if let Err(payload) = outcome {
                let message = payload
                    .downcast_ref::<String>()
                    .map(String::as_str)
                    .or_else(|| payload.downcast_ref::<&str>().copied())
                    .unwrap_or("(non-string panic payload)");
                failures.push(format!(
                    "{} (skip_invalid: {skip_invalid}): panicked: {message}",
                    path.display()
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "fuzz target `{}`: {} of {} inputs made the parser panic:\n  {}",
        target.name(),
        failures.len(),
        corpus.len() + regressions.len(),
        failures.join("\n  ")
    );
    corpus.len() + regressions.len()
}

#[test]
fn csv_corpus_returns() {
    replay(Target::Csv);
}

#[test]
fn ply_corpus_returns() {
    replay(Target::Ply);
}

#[test]
fn nifti_corpus_returns() {
    replay(Target::Nifti);
}

#[test]
fn pdb_corpus_returns() {
    replay(Target::Pdb);
}

#[test]
fn mmcif_corpus_returns() {
    replay(Target::Mmcif);
}

#[test]
fn lammps_corpus_returns() {
    replay(Target::Lammps);
}

#[test]
fn xyz_corpus_returns() {
    replay(Target::Xyz);
}

/// Every target has its test above, and every corpus directory belongs to a target.
#[test]
fn corpus_directories_match_targets() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    let mut names: Vec<String> = std::fs::read_dir(&corpus)
        .unwrap_or_else(|e| panic!("{}: {e}", corpus.display()))
        .map(|e| e.expect("readable directory entry"))
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut expected: Vec<String> = Target::ALL.iter().map(|t| t.name().to_owned()).collect();
    expected.sort();
    assert_eq!(
        names, expected,
        "fuzz/corpus/ subdirectories vs fuzz targets"
    );
}
