//! The offscreen renderer: the library's own Vulkan instance and device (no host engine),
//! drawing a camera's image and reading it back into the host's arrays -- for C and C++ codes
//! that want pictures, not a pass in their own frame (a simulation, a batch job; with the
//! `mpi` feature, each process of an MPI job: `es_offscreen_render_composited`).
//!
//! Threads: like `EsRenderer`, one thread at a time.

use std::ffi::{c_char, CStr};

use ellipsoid_splat::{ContextOptions, OffscreenRenderer, Scene};

use crate::camera::{read_camera, EsCamera};
use crate::frame::{EsFrameBuffers, FRAME_BUFFERS_V1};
use crate::glyphs::{ellipsoids, glyph_slice, EsGlyph};
use crate::settings::{read_settings, EsSettings};
use crate::status::{guard, output, versioned, EsStatus, Failure};

/// An offscreen renderer: opaque to the host.
pub struct EsOffscreenRenderer {
    pub(crate) renderer: OffscreenRenderer,
    /// Set when a call panicked: only destruction is allowed then.
    poisoned: bool,
}

/// What an offscreen renderer is made with.
#[repr(C)]
pub struct EsOffscreenCreateInfo {
    /// `sizeof(EsOffscreenCreateInfo)`.
    pub struct_size: u32,
    /// Non-zero: the Khronos validation layer (with synchronization checks) is on, and any
    /// message it reports makes the call that caused it fail with `ES_STATUS_ERROR_VULKAN`.
    pub validation: u32,
    /// The device: its index or a part of its name (a NUL-terminated string), or null for
    /// the environment's `ELLIPSOID_SPLAT_DEVICE`, else a real GPU, else lavapipe.
    pub device: *const c_char,
    /// The settings, or null for `es_settings_default`'s.
    pub settings: *const EsSettings,
}

/// The size of the first version of [`EsOffscreenCreateInfo`] (64-bit targets), frozen.
const OFFSCREEN_CREATE_INFO_V1: usize = 24;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsOffscreenCreateInfo>() == OFFSCREEN_CREATE_INFO_V1);

impl EsOffscreenRenderer {
    /// Fails with the validation layer's first message if it reported any.
    pub(crate) fn check_validation(&self) -> Result<(), Failure> {
        Ok(self.renderer.context().check_validation()?)
    }
}

/// The offscreen renderer behind `renderer`, for the entry point `function`: a null or
/// poisoned renderer is an error. The caller runs the call in `guard` and poisons the
/// renderer if it panicked ([`poison_on_panic`]).
///
/// # Safety
/// A non-null `renderer` is a live renderer from `es_offscreen_create`, used by no other
/// thread during the call.
pub(crate) unsafe fn offscreen<'a>(
    renderer: *mut EsOffscreenRenderer,
) -> Result<&'a mut EsOffscreenRenderer, Failure> {
    // SAFETY: caller contract.
    let r = unsafe { renderer.as_mut() }.ok_or_else(|| Failure::invalid("renderer", "is null"))?;
    if r.poisoned {
        return Err(Failure {
            status: EsStatus::ErrorPanic,
            message: "an earlier call on this renderer panicked: destroy it".into(),
        });
    }
    Ok(r)
}

/// Poisons `renderer` (if any) when a call on it panicked.
///
/// # Safety
/// As for [`offscreen`]; no reference from it is alive.
pub(crate) unsafe fn poison_on_panic(
    renderer: *mut EsOffscreenRenderer,
    status: EsStatus,
) -> EsStatus {
    if status == EsStatus::ErrorPanic {
        // SAFETY: caller contract.
        if let Some(r) = unsafe { renderer.as_mut() } {
            r.poisoned = true;
        }
    }
    status
}

/// Makes an offscreen renderer (its own Vulkan instance and device) and writes its handle to
/// `out_renderer` (null on failure). Any thread.
///
/// # Safety
/// `info` points at a valid `EsOffscreenCreateInfo` (its `device` null or a NUL-terminated
/// string, its `settings` null or a valid `EsSettings`); `out_renderer` at a writable
/// pointer.
#[no_mangle]
pub unsafe extern "C" fn es_offscreen_create(
    info: *const EsOffscreenCreateInfo,
    out_renderer: *mut *mut EsOffscreenRenderer,
) -> EsStatus {
    guard("es_offscreen_create", || {
        // SAFETY: caller contract.
        let out = unsafe { output(out_renderer, "out_renderer")? };
        *out = std::ptr::null_mut();
        // SAFETY: caller contract.
        let info = unsafe { versioned(info, "create info", OFFSCREEN_CREATE_INFO_V1)? };
        let mut options = if info.validation != 0 {
            ContextOptions::validated()
        } else {
            ContextOptions::default()
        };
        if !info.device.is_null() {
            // SAFETY: caller contract: a NUL-terminated string.
            let name = unsafe { CStr::from_ptr(info.device) };
            let name = name
                .to_str()
                .map_err(|e| Failure::invalid("create info's device", e))?;
            options.device = Some(name.to_owned());
        }
        let mut renderer = OffscreenRenderer::new(&options)?;
        if !info.settings.is_null() {
            // SAFETY: caller contract.
            let settings = unsafe { read_settings(info.settings, renderer.settings())? };
            renderer.set_settings(settings);
        }
        let made = EsOffscreenRenderer {
            renderer,
            poisoned: false,
        };
        made.check_validation()?;
        *out = Box::into_raw(Box::new(made));
        Ok(())
    })
}

/// Destroys `renderer` with its device and instance (a null `renderer` is fine). The handle
/// is gone after the call whatever the status: a failure reports what a clean shutdown must
/// not have (validation messages, memory still allocated). Thread: the renderer's.
///
/// # Safety
/// A non-null `renderer` came from `es_offscreen_create` and is not used again.
#[no_mangle]
pub unsafe extern "C" fn es_offscreen_destroy(renderer: *mut EsOffscreenRenderer) -> EsStatus {
    if renderer.is_null() {
        return EsStatus::Success;
    }
    guard("es_offscreen_destroy", || {
        // SAFETY: caller contract: made by `es_offscreen_create` with `Box::into_raw`.
        let owned = unsafe { Box::from_raw(renderer) };
        owned.renderer.finish()?;
        Ok(())
    })
}

/// Uploads the `count` glyphs of `glyphs` (read during the call only), draws them with
/// `camera` and writes the outputs `buffers` asks for (each array `camera->width *
/// camera->height` pixels). The camera draws its own image: its `viewport_origin` is
/// (0, 0). Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `glyphs` points at `count` glyphs; `camera` at a valid `EsCamera`;
/// `buffers` at a valid `EsFrameBuffers` whose arrays are writable and large enough, and do
/// not overlap.
#[no_mangle]
pub unsafe extern "C" fn es_offscreen_render(
    renderer: *mut EsOffscreenRenderer,
    glyphs: *const EsGlyph,
    count: usize,
    camera: *const EsCamera,
    buffers: *const EsFrameBuffers,
) -> EsStatus {
    let status = guard("es_offscreen_render", || {
        // SAFETY: caller contract.
        let r = unsafe { offscreen(renderer)? };
        // SAFETY: caller contract.
        let scene = Scene::new(ellipsoids(unsafe { glyph_slice(glyphs, count)? }, 0)?);
        // SAFETY: caller contract.
        let camera = unsafe { own_image(read_camera(camera)?)? };
        // SAFETY: caller contract.
        let buffers = unsafe { versioned(buffers, "buffers", FRAME_BUFFERS_V1)? };
        r.renderer.upload(&scene)?;
        let (frame, _) =
            r.renderer
                .render_views(camera.width, camera.height, &[camera], buffers.outputs())?;
        r.check_validation()?;
        // SAFETY: caller contract: the arrays hold the camera's pixels.
        unsafe { buffers.write(&frame) }
    });
    // SAFETY: caller contract; the call's references are gone.
    unsafe { poison_on_panic(renderer, status) }
}

/// `camera`, refused if it draws into a viewport of a larger image: the offscreen frame is
/// the camera's own image.
pub(crate) fn own_image(
    camera: ellipsoid_splat::Camera,
) -> Result<ellipsoid_splat::Camera, Failure> {
    if camera.viewport_origin != [0, 0] {
        return Err(Failure::invalid(
            "camera",
            format!(
                "viewport_origin is {:?}: the offscreen frame is the camera's own image, drawn \
                 from (0, 0)",
                camera.viewport_origin
            ),
        ));
    }
    Ok(camera)
}
