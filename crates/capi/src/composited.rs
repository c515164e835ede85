//! In situ over MPI (feature `mpi`): each process of an application's communicator hands its
//! own glyphs to `es_offscreen_render_composited`, and the root gets the frame of all of them,
//! exactly the frame one process drawing every glyph reads back (`ellipsoid-splat-mpi`,
//! design §6.3).

use std::ffi::c_int;
use std::panic::{catch_unwind, AssertUnwindSafe};

use ellipsoid_splat::{Outputs, Scene};
use ellipsoid_splat_mpi::{render_share, Error, HostCommunicator, Share, ShareError};
use mpi::traits::Communicator;

use crate::camera::{read_camera, EsCamera};
use crate::frame::{EsFrameBuffers, FRAME_BUFFERS_V1};
use crate::glyphs::{ellipsoids, glyph_slice, EsGlyph};
use crate::offscreen::{offscreen, own_image, poison_on_panic, EsOffscreenRenderer};
use crate::status::{guard, versioned, EsStatus, Failure};

/// The C ABI's failure of a compositing error.
fn failure(error: Error) -> Failure {
    let status = match error {
        Error::Renderer(inner) => return Failure::from(inner),
        Error::OtherRank { .. } => EsStatus::ErrorOtherRank,
        Error::NotComposited(_) => EsStatus::ErrorUnsupported,
        Error::Invalid(_) | Error::Communicator(_) => EsStatus::ErrorInvalidArgument,
        _ => EsStatus::ErrorOther,
    };
    Failure {
        status,
        message: error.to_string(),
    }
}

/// The global indices behind `global_ids`, checked.
///
/// # Safety
/// A non-null `global_ids` points at `count` readable `uint32_t`s.
unsafe fn id_slice<'a>(global_ids: *const u32, count: usize) -> Result<&'a [u32], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    if global_ids.is_null() {
        return Err(Failure::invalid(
            "global_ids",
            format!("is null with count {count}"),
        ));
    }
    // SAFETY: caller contract; `count` was bounded by `glyph_slice` (below 2^32).
    Ok(unsafe { std::slice::from_raw_parts(global_ids, count) })
}

/// Draws this process's `count` glyphs (`glyphs`; glyph `i` is glyph `global_ids[i]` of the
/// whole scene, the indices strictly increasing) with `camera`, and composites the frames of
/// every process of the communicator at rank `root`: there the outputs `buffers` asks for are
/// written (each array `camera->width * camera->height` pixels), exactly what one process
/// drawing every glyph with `es_offscreen_render` writes (`id` holds global indices).
///
/// The rules of this layer:
/// - `communicator` is the communicator's Fortran handle, `MPI_Comm_c2f(comm)`, so this
///   header needs no `mpi.h`. It is borrowed: never freed; MPI is never initialised or
///   finalised here (the application does both, around every call). The exchange runs on a
///   duplicate, so the application's own messages are never taken.
/// - Collective: every process of the communicator calls it, with the same root, camera and
///   image size, and renderers of the same settings.
/// - `buffers` is read at the root only (elsewhere it may be null).
/// - A process whose arguments or drawing fail makes every process return an error: that
///   one its own, the others `ES_STATUS_ERROR_OTHER_RANK` naming the lowest failing rank.
///   None waits for an image that will not come.
///
/// Only in a library built with the `mpi` feature; declared when `ELLIPSOID_SPLAT_MPI` is
/// defined before the header is included. Thread: the renderer's, one the application's MPI
/// threading level allows to call MPI.
///
/// # Safety
/// `communicator` is the Fortran handle of a live communicator of this process (or
/// `MPI_COMM_NULL`'s, refused); `renderer` is live; `glyphs` and `global_ids` point at
/// `count` values each; `camera` at a valid `EsCamera`; at the root, `buffers` at a valid
/// `EsFrameBuffers` whose arrays are writable, large enough and apart.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn es_offscreen_render_composited(
    renderer: *mut EsOffscreenRenderer,
    communicator: c_int,
    root: c_int,
    glyphs: *const EsGlyph,
    global_ids: *const u32,
    count: usize,
    camera: *const EsCamera,
    buffers: *const EsFrameBuffers,
) -> EsStatus {
    let status = guard("es_offscreen_render_composited", || {
        // SAFETY: caller contract: the handle of a live communicator.
        let host = unsafe { HostCommunicator::from_fortran(communicator) }.map_err(failure)?;
        let comm = host.communicator();
        let at_root = comm.rank() == root;
        // What may fail on this process alone, a panic included, fails here, before anything
        // waits on another process: `render_share` tells the others.
        let made = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: caller contract.
            let r = unsafe { offscreen(renderer)? };
            // SAFETY: caller contract.
            let part = Scene::new(ellipsoids(unsafe { glyph_slice(glyphs, count)? }, 0)?);
            // SAFETY: caller contract.
            let global_ids = unsafe { id_slice(global_ids, count)? }.to_vec();
            // SAFETY: caller contract.
            let camera = own_image(unsafe { read_camera(camera)? })?;
            let buffers = if at_root {
                // SAFETY: caller contract: valid at the root.
                Some(*unsafe { versioned(buffers, "buffers", FRAME_BUFFERS_V1)? })
            } else {
                None
            };
            let share = Share {
                renderer: &mut r.renderer,
                part,
                global_ids,
                camera,
            };
            Ok((share, buffers))
        }))
        .unwrap_or_else(|_| {
            Err(Failure {
                status: EsStatus::ErrorPanic,
                message: "internal error (panic) making this process's share".into(),
            })
        });
        let (share, buffers) = match made {
            Ok((share, buffers)) => (Ok(share), buffers),
            Err(failed) => (Err(failed), None),
        };
        let done = render_share(comm, root, share, Outputs::ALL).map_err(|e| match e {
            ShareError::Arguments(failed) => failed,
            ShareError::Composite(error) => failure(error),
        })?;
        // SAFETY: caller contract; the share's borrow of it has ended.
        unsafe { offscreen(renderer)? }.check_validation()?;
        if let (Some(frame), Some(buffers)) = (done.frame, buffers) {
            // SAFETY: caller contract: at the root the arrays hold the camera's pixels.
            unsafe { buffers.write(&frame)? };
        }
        Ok(())
    });
    // SAFETY: caller contract; the call's references are gone.
    unsafe { poison_on_panic(renderer, status) }
}
