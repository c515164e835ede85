//! What can go wrong drawing a frame across processes.

use mpi::topology::Rank;

/// An error of [`render_composited`](crate::render_composited).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// This process's renderer failed.
    #[error(transparent)]
    Renderer(#[from] ellipsoid_splat::Error),
    /// Another process failed (its own error is reported there); nothing was composited.
    #[error("rank {rank} failed drawing its share (its error is reported there): nothing was composited")]
    OtherRank {
        /// The lowest failing rank.
        rank: Rank,
    },
    /// The frame is of a kind compositing cannot combine exactly.
    #[error("not composited: {0}")]
    NotComposited(String),
    /// An argument is inconsistent.
    #[error("invalid compositing input: {0}")]
    Invalid(String),
    /// The host's communicator cannot be used ([`HostCommunicator`](crate::HostCommunicator)).
    #[error("communicator refused: {0}")]
    Communicator(String),
}

/// Shorthand for `Result<T, ellipsoid_splat_mpi::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;
