//! The tool's error: the renderer's and the loaders' errors, a bad argument, a file that
//! cannot be read or written. `main` maps each to an exit status.

use std::path::PathBuf;

/// Everything that can go wrong in a command of the tool.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The renderer (or the viewer's Vulkan plumbing) failed.
    #[error(transparent)]
    Renderer(#[from] ellipsoid_splat::Error),
    /// A scene could not be loaded.
    #[error(transparent)]
    Load(#[from] ellipsoid_splat_loaders::Error),
    /// An argument or value is outside what the tool accepts.
    #[error("invalid {what}: {reason}")]
    Invalid {
        /// What was invalid (a flag, e.g. `--width`).
        what: String,
        /// Why.
        reason: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A frame of a trajectory failed (`render --frames`).
    #[error("frame {number}: {source}")]
    Frame {
        /// The frame's number in the file, from 1.
        number: usize,
        /// What went wrong.
        source: Box<Error>,
    },
    /// Encoding an output image failed.
    #[error("cannot write {}: {reason}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// The encoder's message.
        reason: String,
    },
}

/// Shorthand for `Result<T, ellipsoid_splat_tool::error::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An invalid `what`, because `reason`.
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            what: what.into(),
            reason: reason.into(),
        }
    }

    /// This error, said of frame `number` of a trajectory.
    pub fn in_frame(self, number: usize) -> Self {
        Error::Frame {
            number,
            source: Box::new(self),
        }
    }

    /// The error of a failed Vulkan call (the viewer's own).
    pub fn vulkan(call: &'static str, result: ash::vk::Result) -> Self {
        Error::Renderer(ellipsoid_splat::Error::vulkan(call, result))
    }
}
