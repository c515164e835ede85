//! Cameras: from the host's column-major view and projection matrices and its viewport
//! (jittered, off-centre, asymmetric, flipped), or from a look-at; as a plain struct the host
//! may also fill itself.

use ellipsoid_splat::{Camera, DepthConvention, HostViewport, Intrinsics, Projection};
use glam::{DMat4, DVec2, DVec3};

use crate::status::{guard, output, required, versioned, EsStatus, Failure};

/// How the view volume is shaped.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsProjection {
    /// A pinhole with `fov_y_deg`, centred, square pixels.
    Perspective = 0,
    /// Parallel rays through a centred window `ortho_height` high, square pixels.
    Orthographic = 1,
    /// A pinhole with `intrinsics` (OpenCV's `fx, fy, cx, cy` in pixels).
    PerspectiveIntrinsics = 2,
    /// Parallel rays with `intrinsics` (`fx`, `fy` in pixels per world unit).
    OrthographicIntrinsics = 3,
}

/// A viewport as the host gives `vkCmdSetViewport` (whole pixels, depth range [0, 1]); a
/// negative `height` flips it (`y` is then its bottom edge and the projection's y points up).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsViewport {
    /// Left edge in attachment pixels.
    pub x: u32,
    /// Top edge, or the bottom edge when `height` is negative.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels; negative for a flipped viewport.
    pub height: i32,
}

/// A camera: the contract of `docs/design.md` §3 field by field. Fill it with
/// `es_camera_from_matrices` or `es_camera_look_at`, or directly (set `struct_size`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsCamera {
    /// `sizeof(EsCamera)`.
    pub struct_size: u32,
    /// Which of the projection fields apply: an `EsProjection` value.
    pub projection: u32,
    /// Eye position (perspective centre, or a point of the orthographic view axis).
    pub eye: [f64; 3],
    /// A point on the view axis in front of the eye.
    pub target: [f64; 3],
    /// Approximate up direction.
    pub up: [f64; 3],
    /// `ES_PROJECTION_PERSPECTIVE`: the vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f64,
    /// `ES_PROJECTION_ORTHOGRAPHIC`: the window's height in world units.
    pub ortho_height: f64,
    /// The `*_INTRINSICS` projections: `fx, fy, cx, cy` in pixels.
    pub intrinsics: [f64; 4],
    /// View depth of the near plane (> 0).
    pub near: f64,
    /// Image width in pixels (1 ..= 16384).
    pub width: u32,
    /// Image height in pixels (1 ..= 16384).
    pub height: u32,
    /// Sub-pixel jitter in pixels (x right, y down): pixel `(i, j)` samples the unjittered
    /// image at `(i + 0.5 + dx, j + 0.5 + dy)`.
    pub jitter: [f64; 2],
    /// The attachment pixel of the camera's pixel (0, 0).
    pub viewport_origin: [u32; 2],
    /// Non-zero: reversed Z (near at 1, compare GREATER); zero: standard (near at 0).
    pub depth_reversed: u32,
    /// View depth of the far plane; 0 (or infinity) for an infinite far plane.
    pub depth_far: f64,
}

/// The size of the first version of [`EsCamera`] (64-bit targets), frozen.
pub(crate) const CAMERA_V1: usize = 184;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsCamera>() == CAMERA_V1);

/// The library's camera of `camera`.
pub(crate) fn camera_from(camera: &EsCamera) -> Result<Camera, Failure> {
    let [fx, fy, cx, cy] = camera.intrinsics;
    let intrinsics = Intrinsics { fx, fy, cx, cy };
    let projection = match camera.projection {
        p if p == EsProjection::Perspective as u32 => Projection::Perspective {
            fov_y_deg: camera.fov_y_deg,
        },
        p if p == EsProjection::Orthographic as u32 => Projection::Orthographic {
            height: camera.ortho_height,
        },
        p if p == EsProjection::PerspectiveIntrinsics as u32 => {
            Projection::PerspectiveIntrinsics(intrinsics)
        }
        p if p == EsProjection::OrthographicIntrinsics as u32 => {
            Projection::OrthographicIntrinsics(intrinsics)
        }
        p => {
            return Err(Failure::invalid(
                "EsCamera.projection",
                format!("{p} is not an EsProjection"),
            ))
        }
    };
    let far =
        (camera.depth_far != 0.0 && camera.depth_far != f64::INFINITY).then_some(camera.depth_far);
    let [x, y] = camera.viewport_origin;
    let built = Camera::new(
        DVec3::from_array(camera.eye),
        DVec3::from_array(camera.target),
        DVec3::from_array(camera.up),
        projection,
        camera.near,
        camera.width,
        camera.height,
    )
    .and_then(|c| {
        c.with_depth(DepthConvention {
            reversed: camera.depth_reversed != 0,
            far,
        })
    })
    .and_then(|c| c.with_jitter(DVec2::from_array(camera.jitter)))
    .and_then(|c| c.with_viewport_origin(x, y))?;
    Ok(built)
}

/// The plain struct of a library camera.
pub(crate) fn camera_to(camera: &Camera) -> EsCamera {
    let (projection, fov_y_deg, ortho_height) = match camera.projection {
        Projection::Perspective { fov_y_deg } => (EsProjection::Perspective, fov_y_deg, 0.0),
        Projection::Orthographic { height } => (EsProjection::Orthographic, 0.0, height),
        Projection::PerspectiveIntrinsics(_) => (EsProjection::PerspectiveIntrinsics, 0.0, 0.0),
        _ => (EsProjection::OrthographicIntrinsics, 0.0, 0.0),
    };
    let k = camera.intrinsics();
    EsCamera {
        struct_size: CAMERA_V1 as u32,
        projection: projection as u32,
        eye: camera.eye.to_array(),
        target: camera.target.to_array(),
        up: camera.up.to_array(),
        fov_y_deg,
        ortho_height,
        intrinsics: [k.fx, k.fy, k.cx, k.cy],
        near: camera.near,
        width: camera.width,
        height: camera.height,
        jitter: camera.jitter.to_array(),
        viewport_origin: camera.viewport_origin,
        depth_reversed: camera.depth.reversed as u32,
        depth_far: camera.depth.far.unwrap_or(0.0),
    }
}

/// The camera the host's `view` and `projection` matrices (column-major `float[16]`, world to
/// Vulkan clip space) describe when drawn with `viewport`: any perspective or orthographic
/// frustum -- jittered, off-centre, asymmetric, non-square pixels -- in reversed or standard
/// Z with a finite or infinite far plane, and y-up projections with a flipped viewport.
/// Skewed, oblique and mirroring matrices are refused (the message says why). Any thread.
///
/// # Safety
/// `view` and `projection` point at 16 floats each; `out_camera` at a writable `EsCamera`.
#[no_mangle]
pub unsafe extern "C" fn es_camera_from_matrices(
    view: *const f32,
    projection: *const f32,
    viewport: EsViewport,
    out_camera: *mut EsCamera,
) -> EsStatus {
    guard("es_camera_from_matrices", || {
        // SAFETY: caller contract: 16 floats each.
        let view = unsafe { required(view.cast::<[f32; 16]>(), "view")? };
        // SAFETY: as above.
        let projection = unsafe { required(projection.cast::<[f32; 16]>(), "projection")? };
        // SAFETY: caller contract.
        let out = unsafe { output(out_camera, "out_camera")? };
        let widen = |m: &[f32; 16]| DMat4::from_cols_array(&m.map(f64::from));
        let camera = Camera::from_view_projection_viewport(
            widen(view),
            widen(projection),
            HostViewport {
                x: viewport.x,
                y: viewport.y,
                width: viewport.width,
                height: viewport.height,
            },
        )?;
        *out = camera_to(&camera);
        Ok(())
    })
}

/// A perspective camera at `eye` looking at `target` with `up` roughly up, `fov_y_deg`
/// degrees of vertical field of view, the near plane at `near` and a `width x height` image
/// (reversed Z, infinite far plane). Any thread.
///
/// # Safety
/// `eye`, `target` and `up` point at 3 doubles each; `out_camera` at a writable `EsCamera`.
#[no_mangle]
pub unsafe extern "C" fn es_camera_look_at(
    eye: *const f64,
    target: *const f64,
    up: *const f64,
    fov_y_deg: f64,
    near: f64,
    width: u32,
    height: u32,
    out_camera: *mut EsCamera,
) -> EsStatus {
    guard("es_camera_look_at", || {
        let point = |p: *const f64, what: &str| {
            // SAFETY: caller contract: 3 doubles.
            unsafe { required(p.cast::<[f64; 3]>(), what) }.map(|v| DVec3::from_array(*v))
        };
        let (eye, target, up) = (
            point(eye, "eye")?,
            point(target, "target")?,
            point(up, "up")?,
        );
        // SAFETY: caller contract.
        let out = unsafe { output(out_camera, "out_camera")? };
        let camera = Camera::new(
            eye,
            target,
            up,
            Projection::Perspective { fov_y_deg },
            near,
            width,
            height,
        )?;
        *out = camera_to(&camera);
        Ok(())
    })
}

/// The library's camera behind a host's `EsCamera` pointer.
///
/// # Safety
/// A non-null `camera` points at a valid `EsCamera`.
pub(crate) unsafe fn read_camera(camera: *const EsCamera) -> Result<Camera, Failure> {
    // SAFETY: caller contract.
    camera_from(unsafe { versioned(camera, "camera", CAMERA_V1)? })
}
