//! `conformance`'s arguments.

use std::path::PathBuf;

use clap::Args;

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
