//! One frame drawn for an application in another language (through the C ABI, from Python):
//! each process makes its share of the glyphs and the camera from that language's arguments,
//! which may fail on one process and not on another. A process whose arguments failed still
//! takes part, so that every process learns of the failure before drawing and none waits for
//! an image that will not come.

use mpi::topology::Rank;
use mpi::traits::*;

use ellipsoid_splat::{Camera, OffscreenRenderer, Outputs, Scene};

use crate::distributed::{render_composited, Composited};
use crate::error::Error;
use crate::failure::first_failed;

/// What one process draws: [`render_composited`]'s arguments, made from the host's.
pub struct Share<'a> {
    /// This process's renderer.
    pub renderer: &'a mut OffscreenRenderer,
    /// This process's glyphs.
    pub part: Scene,
    /// The global index of each glyph of `part`, strictly increasing.
    pub global_ids: Vec<u32>,
    /// The camera (the same on every process).
    pub camera: Camera,
}

/// Why a frame of [`render_share`] failed.
#[derive(Debug)]
pub enum ShareError<E> {
    /// This process's own arguments failed: the host layer's error, as that layer made it.
    Arguments(E),
    /// Another process's arguments failed ([`Error::OtherRank`]), or drawing or compositing
    /// did.
    Composite(Error),
}

/// Draws `share` and composites the frame at `root` ([`render_composited`]) once every
/// process of `comm` has made its share; where any could not (`share` is its error), every
/// process returns an error instead: that one its own, the others [`Error::OtherRank`] naming
/// the lowest failing rank. Collective, like [`render_composited`]; the agreement is one
/// blocking all-reduce on `comm` itself, which takes none of the application's messages.
pub fn render_share<C: Communicator, E>(
    comm: &C,
    root: Rank,
    share: Result<Share<'_>, E>,
    outputs: Outputs,
) -> Result<Composited, ShareError<E>> {
    let failed = first_failed(comm, share.is_err());
    let share = share.map_err(ShareError::Arguments)?;
    if let Some(rank) = failed {
        return Err(ShareError::Composite(Error::OtherRank { rank }));
    }
    render_composited(
        comm,
        root,
        share.renderer,
        &share.part,
        &share.global_ids,
        &share.camera,
        outputs,
    )
    .map_err(ShareError::Composite)
}
