//! In situ over MPI (feature `mpi`): each process of a Python application's communicator
//! (mpi4py's, by its Fortran handle `comm.py2f()`) draws its own glyphs, and the root gets the
//! frame of all of them (`ellipsoid-splat-mpi`, design §6.3). The Python half
//! (`Renderer.render_composited`) checks the arguments; a process whose arguments fail there
//! calls `composite_failed` instead, so that every process learns of it and none waits.

use std::ffi::c_int;
use std::time::Instant;

use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::{Frame, Outputs, Scene};
use ellipsoid_splat_mpi::failure::first_failed;
use ellipsoid_splat_mpi::{render_share, Error, HostCommunicator, Share, ShareError};
use glam::DVec3;
use numpy::PyReadonlyArray1;
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::camera::{matrix, CameraArgs};
use crate::errors::{no_panic, poisoned, renderer_error, OtherRankError};
use crate::glyphs::{Floats2, Floats3, GlyphArrays};
use crate::renderer::{frame_arrays, FrameArrays, Renderer};

/// The Python exception of a compositing error.
fn composite_error(error: Error) -> PyErr {
    match error {
        Error::Renderer(inner) => renderer_error(inner),
        Error::OtherRank { .. } => OtherRankError::new_err(error.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// The host's communicator of `handle`.
fn communicator(handle: c_int) -> PyResult<HostCommunicator> {
    // SAFETY: the handle comes from mpi4py's `py2f()` of a live communicator, or from the
    // caller as the same (the Python half's documentation); Open MPI maps an integer that
    // names no communicator to MPI_COMM_NULL, which is refused.
    unsafe { HostCommunicator::from_fortran(handle) }.map_err(composite_error)
}

/// Takes part in a composited frame for a process whose arguments failed in the Python half
/// (which raises that error next): every process of the communicator learns that this one
/// failed, so none waits for its image.
#[pyfunction]
pub fn composite_failed(py: Python<'_>, communicator_handle: c_int) -> PyResult<()> {
    py.allow_threads(|| {
        no_panic(|| {
            let host = communicator(communicator_handle)?;
            first_failed(host.communicator(), true);
            Ok(())
        })
    })
}

/// This process's glyphs, their global indices and the camera, as read from NumPy.
type Made = (Scene, Vec<u32>, CameraArgs);

/// Draws this process's glyphs and composites the frame of every process of the communicator
/// at `root`: the frame's arrays there (global indices as IDs), `None` elsewhere. The camera
/// is given in full (no framing defaults: a process sees only its share).
#[pyfunction]
#[pyo3(signature = (renderer, communicator_handle, root, centers, radii, rotations, colors, tensors, global_ids, eye, target, up, fov_y, intrinsics, world_to_camera, width, height, near, supersample))]
#[allow(clippy::too_many_arguments)]
pub fn render_composited<'py>(
    py: Python<'py>,
    renderer: &Renderer,
    communicator_handle: c_int,
    root: c_int,
    centers: Floats2<'py>,
    radii: Option<Floats2<'py>>,
    rotations: Option<Floats2<'py>>,
    colors: Option<Floats2<'py>>,
    tensors: Option<Floats3<'py>>,
    global_ids: PyReadonlyArray1<'py, u32>,
    eye: Option<[f64; 3]>,
    target: Option<[f64; 3]>,
    up: [f64; 3],
    fov_y: f64,
    intrinsics: Option<PyReadonlyArray2<'py, f64>>,
    world_to_camera: Option<PyReadonlyArray2<'py, f64>>,
    width: u32,
    height: u32,
    near: Option<f64>,
    supersample: u32,
) -> PyResult<Option<FrameArrays<'py>>> {
    // Read with the GIL held (no other Python thread changes the arrays meanwhile). What fails
    // here fails on this process alone: it is reported to the others before any waits.
    let made: PyResult<Made> = no_panic(|| {
        let arrays = GlyphArrays {
            centers,
            radii,
            rotations,
            colors,
            tensors,
        };
        let part = Scene::new(arrays.ellipsoids()?);
        let ids = global_ids.as_slice()?.to_vec();
        let args = CameraArgs {
            eye,
            target,
            up,
            fov_y,
            intrinsics: matrix("intrinsics", intrinsics)?,
            world_to_camera: matrix("world_to_camera", world_to_camera)?,
            width,
            height,
            near,
        };
        Ok((part, ids, args))
    });
    let frame = py.allow_threads(|| {
        no_panic(|| composite(renderer, communicator_handle, root, made, supersample))
    })?;
    frame
        .map(|(frame, ms)| frame_arrays(py, frame, ms))
        .transpose()
}

/// The collective part of [`render_composited`], with the GIL released.
fn composite(
    renderer: &Renderer,
    communicator_handle: c_int,
    root: c_int,
    made: PyResult<Made>,
    supersample: u32,
) -> PyResult<Option<(Frame, f64)>> {
    let host = communicator(communicator_handle)?;
    let start = Instant::now();
    // A renderer an earlier call left broken fails this process like a bad argument.
    let mut state = renderer.state.lock().ok();
    let share = made.and_then(|(part, global_ids, args)| {
        let state = state.as_deref_mut().ok_or_else(poisoned)?;
        let full = (args.eye.is_some() && args.target.is_some() || args.intrinsics.is_some())
            && args.near.is_some();
        if !full {
            return Err(PyValueError::new_err(
                "render_composited takes the camera in full -- eye and target, or intrinsics \
                 and world_to_camera, and near -- as each process sees only its share",
            ));
        }
        // Every framing default is given: the sphere is not used.
        let camera = args.camera((DVec3::ZERO, 1.0))?;
        let camera = match supersample {
            1 => camera,
            k => supersampled_camera(&camera, k).map_err(renderer_error)?,
        };
        Ok(Share {
            renderer: state.renderer_for_own_upload(),
            part,
            global_ids,
            camera,
        })
    });
    let done =
        render_share(host.communicator(), root, share, Outputs::ALL).map_err(|e| match e {
            ShareError::Arguments(error) => error,
            ShareError::Composite(error) => composite_error(error),
        })?;
    state.as_deref().ok_or_else(poisoned)?.check_validation()?;
    let Some(frame) = done.frame else {
        return Ok(None);
    };
    let frame = match supersample {
        1 => frame,
        k => box_filter(&frame, k).map_err(renderer_error)?,
    };
    Ok(Some((frame, start.elapsed().as_secs_f64() * 1e3)))
}
