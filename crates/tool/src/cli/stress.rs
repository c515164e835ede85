//! `stress`'s arguments.

use std::path::PathBuf;

use clap::Args;

use super::device::DeviceArgs;

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
