//! Device selection and validation, as `render`, `stress`, `bench` and `info` take them.

use clap::Args;

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
