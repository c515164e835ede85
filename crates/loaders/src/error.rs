//! The loaders' error: which file, line and field is bad and why, what could not be read, or
//! what the renderer's types refused; and the helpers that build one (a parse error, an I/O
//! error naming its file, the line of a byte).

use std::path::{Path, PathBuf};

/// Everything that can go wrong loading or generating a scene.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A scene file has a bad row, field or header.
    #[error("{}:{line}:{column}: {reason}", file.display())]
    Parse {
        /// The file being read.
        file: PathBuf,
        /// 1-based line number (0 when the problem is not tied to a line).
        line: usize,
        /// The column name, or a description of the place in the line.
        column: String,
        /// Why it is rejected.
        reason: String,
    },
    /// Reading a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// An option or value is outside what the loaders accept.
    #[error("invalid {what}: {reason}")]
    Invalid {
        /// What was invalid (e.g. `--sigma`, `tensor field side`).
        what: String,
        /// Why.
        reason: String,
    },
    /// The renderer's types refused a value (an ellipsoid, a scene).
    #[error(transparent)]
    Renderer(#[from] ellipsoid_splat::Error),
    /// Another process reading its share of a file failed ([`load_share`](crate::load_share));
    /// its own error is reported there.
    #[error(
        "rank {rank} failed reading its share of {} (its error is reported there)",
        file.display()
    )]
    OtherRank {
        /// The lowest failing rank.
        rank: usize,
        /// The file being read.
        file: PathBuf,
    },
}

/// Shorthand for `Result<T, ellipsoid_splat_loaders::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An invalid `what`, because `reason`.
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            what: what.into(),
            reason: reason.into(),
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

/// The whole content of `path`, or an [`Error::Io`] naming it.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(io_error(path))
}

/// The 1-based line of byte `offset` in `bytes`.
pub(crate) fn line_at(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset].iter().filter(|&&b| b == b'\n').count()
}
