//! What can stop `ellipsoid-splat-mpi`: the tool's errors (arguments, loading, the device,
//! writing), the compositing's, or another process's failure (reported by that process).

/// An error of one process.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// As one-process `render` would fail.
    #[error(transparent)]
    Tool(#[from] ellipsoid_splat_tool::error::Error),
    /// Combining the processes' frames failed.
    #[error(transparent)]
    Composite(#[from] ellipsoid_splat_mpi::Error),
    /// Another process failed; its error is printed there.
    #[error("rank {rank} failed (its error is reported there): nothing was written")]
    OtherRank {
        /// The lowest failing rank.
        rank: i32,
    },
}

impl From<ellipsoid_splat_loaders::Error> for Error {
    fn from(e: ellipsoid_splat_loaders::Error) -> Self {
        Error::Tool(e.into())
    }
}

impl From<ellipsoid_splat::Error> for Error {
    fn from(e: ellipsoid_splat::Error) -> Self {
        Error::Tool(e.into())
    }
}

/// Shorthand for `Result<T, Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;
