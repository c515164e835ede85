//! A [`Camera`] from a host engine's view and projection matrices and viewport, so ellipsoids
//! land exactly where the host's meshes do. What is accepted, how it is read and what is
//! refused: [`Camera::from_view_projection_viewport`].

use glam::{DMat3, DMat4, DVec3, DVec4};

use crate::camera::{Camera, Intrinsics, Projection};
use crate::depth::DepthConvention;
use crate::error::{Error, Result};

/// How far from exact (relative) the matrices' structure may be: rounding in a host's float32
/// or float64 matrix code stays far below it, a real skew or tilt does not.
const TOLERANCE: f64 = 1e-6;

/// How near to centred (relative) a projection must be to give a centred [`Projection`]:
/// within float64 rounding, so a jittered projection keeps its jitter.
const CENTRED: f64 = 1e-12;

/// A host's Vulkan viewport, as given to `vkCmdSetViewport` (whole pixels; depth range
/// [0, 1]).
///
/// A negative `height` is a y-up projection drawn with a flipped viewport (the usual way of
/// porting OpenGL-style matrices): `y` is then the viewport's bottom edge, NDC `y` points up
/// the image, and [`Camera::from_view_projection_viewport`] reads the matrix as
/// `diag(1, -1, 1, 1) projection view`, a y-down one. Its image is the rectangle
/// `(x, y - |height|)` .. `(x + width, y)`, which becomes the camera's viewport origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostViewport {
    /// Left edge in attachment pixels.
    pub x: u32,
    /// Top edge, or the bottom edge when `height` is negative.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels; negative for a flipped (y-up) viewport.
    pub height: i32,
}

impl HostViewport {
    /// The whole of a `width x height` attachment, not flipped.
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x: 0,
            y: 0,
            width,
            height: height.min(i32::MAX as u32) as i32,
        }
    }
}

impl Camera {
    /// The camera that `projection * view` describes for a `width x height` image drawn over
    /// the whole attachment, not flipped: [`Camera::from_view_projection_viewport`] with
    /// [`HostViewport::full`], whose documentation says what is accepted and refused. Errors
    /// say which part of the matrices the camera contract cannot express.
    pub fn from_view_projection(
        view: DMat4,
        projection: DMat4,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        Self::from_view_projection_viewport(view, projection, HostViewport::full(width, height))
    }

    /// The camera that `projection * view` describes when drawn with the host's `viewport`
    /// (its image is the viewport's rectangle, at the viewport's top-left corner).
    ///
    /// The matrices map world points to Vulkan clip space as the host's own vertex shaders do:
    /// `clip = projection * view * (p, 1)`, NDC `x` to the right, `z` in [0, 1], `w > 0` in
    /// front of the eye, drawn with the host's viewport (depth range [0, 1]): NDC `y` points
    /// down the viewport, or up it when the viewport is flipped ([`HostViewport`]). Any
    /// right-handed rigid view and any perspective or orthographic projection are accepted --
    /// off-centre, jittered, asymmetric (one eye of a stereo pair), with non-square pixels -- in
    /// reversed or standard Z with a finite or infinite far plane. Skewed, oblique or mirroring
    /// matrices are refused with an error.
    ///
    /// # How the matrices are read
    ///
    /// - `m` is the y-down clip matrix: `projection view`, or its y-negated form for a flipped
    ///   viewport ([`HostViewport`]).
    /// - With `m`'s rows `m0..m3`: perspective when the `xyz` part of `m3` is not zero: `w = k d`
    ///   with `f = normalize(m3.xyz)` and `k = |m3.xyz|`. Orthographic otherwise: `w = k = m3.w`
    ///   (must be > 0), and `f` follows from the screen axes for a right-handed frame.
    /// - Each screen axis splits into its part across the view and its part along it: `r =
    ///   normalize(m0.xyz - (m0.xyz . f) f)`, `u = -normalize(m1.xyz - (m1.xyz . f) f)`. The
    ///   parts across give the focal lengths, `fx = (W/2) |m0 across| / k`, `fy = (H/2) |m1
    ///   across| / k`, the parts along give the principal point, `cx = (W/2)(1 + m0.xyz . f /
    ///   k)`, `cy = (H/2)(1 + m1.xyz . f / k)`. So off-centre, jittered (TAA), asymmetric
    ///   (stereo, OpenXR) frusta and non-square pixels become
    ///   [`Projection::PerspectiveIntrinsics`] (a jitter in the matrix is a shift of the
    ///   principal point); a centred frustum with square pixels (within float64 rounding, 1e-12
    ///   relative) stays [`Projection::Perspective`]. Orthographic windows are centred by
    ///   placing the eye on the window's axis, so they give [`Projection::Orthographic`] or, with
    ///   non-square pixels, [`Projection::OrthographicIntrinsics`].
    /// - Refused with an error naming the cause: non-finite or singular matrices, an empty
    ///   viewport or a flipped one whose bottom edge lies above the attachment's top, skewed
    ///   image axes, a mirrored image (a left-handed frame, or a y-up projection drawn with a
    ///   viewport that is not flipped -- the message says to flip one of them), a depth axis
    ///   tilted away from `f`, an oblique orthographic projection, a principal point beyond
    ///   [`Camera::MAX_PRINCIPAL_SHIFT`] or [`Camera::MAX_PRINCIPAL_SHIFT_PX`] (design §3.2).
    ///   Structure is checked to a relative tolerance of 1e-6.
    /// - Perspective: the eye solves `m0.p = m1.p = m3.p = 0` (with their `w` terms). Depth is
    ///   `a + c/d` with `a = alpha/k`, `c = (m2.w + alpha f.eye)/k` and `alpha = m2.xyz . f`;
    ///   reversed when `c > 0`; `near = c/(1 - a)` (reversed) or `-c/a` (standard); the far
    ///   plane is the other end, and is taken as infinite when it is not finite or lies beyond
    ///   `1e12 near`.
    /// - Orthographic: depth is linear in `t = f.p`; reversed when its slope is negative. The
    ///   eye is placed on the view axis one near-to-far span in front of the host's near plane
    ///   (any point of the axis gives the same rays), so `near = span` and `far = 2 span`.
    ///
    /// A crate `Camera` takes another convention with [`Camera::with_depth`], a jitter with
    /// [`Camera::with_jitter`] and a place in the attachments with
    /// [`Camera::with_viewport_origin`].
    pub fn from_view_projection_viewport(
        view: DMat4,
        projection: DMat4,
        viewport: HostViewport,
    ) -> Result<Self> {
        let (width, height) = (viewport.width, viewport.height.unsigned_abs());
        let flipped = viewport.height < 0;
        let top = if flipped {
            viewport.y.checked_sub(height).ok_or_else(|| {
                Error::invalid(
                    "host viewport",
                    format!(
                        "a flipped viewport of height {} must have its bottom edge y >= {height}, got {}",
                        viewport.height, viewport.y
                    ),
                )
            })?
        } else {
            viewport.y
        };
        // A flipped viewport turns NDC y up the image: negate it, and the rest reads as a
        // y-down projection.
        let flip = if flipped { -1.0 } else { 1.0 };
        let m = DMat4::from_scale(DVec3::new(1.0, flip, 1.0)) * projection * view;
        let camera = from_y_down(m, width, height)?;
        camera.with_viewport_origin(viewport.x, top)
    }
}

/// The camera of a y-down clip matrix `m` over a whole `width x height` image.
fn from_y_down(m: DMat4, width: u32, height: u32) -> Result<Camera> {
    if !m.is_finite() {
        return Err(invalid("are not finite"));
    }
    if width == 0 || height == 0 {
        return Err(Error::invalid(
            "host viewport",
            format!("{width}x{height} is empty"),
        ));
    }
    let rows = [m.row(0), m.row(1), m.row(2), m.row(3)];
    let xyz = |r: DVec4| r.truncate();
    let w_axis = xyz(rows[3]);
    let scale = rows.iter().map(|r| xyz(*r).length()).fold(0.0, f64::max);
    if scale == 0.0 {
        return Err(invalid("map every point to the same clip position"));
    }
    let perspective = w_axis.length() > TOLERANCE * scale;
    let (ax, ay, az) = (xyz(rows[0]), xyz(rows[1]), xyz(rows[2]));
    if ax.length() == 0.0 || ay.length() == 0.0 {
        return Err(invalid("flatten the image's x or y axis"));
    }
    // `k` scales clip w to view depth: w = k d (perspective) or w = k (orthographic).
    let (forward, k) = if perspective {
        (w_axis.normalize(), w_axis.length())
    } else {
        let k = rows[3].w;
        if k <= 0.0 {
            return Err(invalid(
                "give clip w <= 0 (orthographic w must be positive)",
            ));
        }
        // Right-handed: forward = up x right, from the screen axes (NDC y points down).
        ((-ay).cross(ax).normalize_or_zero(), k)
    };
    // Each screen axis splits into its part across the view (the focal length) and its part
    // along it (the principal point's offset, perspective only).
    let across = |axis: DVec3| axis - axis.dot(forward) * forward;
    let (ax_across, ay_across) = (across(ax), across(ay));
    if ax_across.length() <= TOLERANCE * ax.length()
        || ay_across.length() <= TOLERANCE * ay.length()
    {
        return Err(invalid(
            "put the image's x or y axis along the view direction",
        ));
    }
    if !perspective {
        for (name, axis) in [("x", ax), ("y", ay)] {
            if axis.normalize().dot(forward).abs() > TOLERANCE {
                return Err(invalid(format!(
                    "tilt the {name} axis along the view direction (an oblique projection)"
                )));
            }
        }
    }
    let right = ax_across.normalize();
    let up = -ay_across.normalize(); // NDC y points down; the contract's up points up.
    if right.dot(up).abs() > TOLERANCE {
        return Err(invalid("skew the image axes"));
    }
    if (forward.cross(up) - right).length() > TOLERANCE {
        return Err(invalid(
            "mirror the image (a left-handed frame, or a y-up projection drawn with a viewport \
             that is not flipped): flip the projection's y, give the viewport a negative \
             height, or flip the view's handedness",
        ));
    }
    let (w, h) = (width as f64, height as f64);
    // NDC x = (|ax_across| X + (ax . f) d) / (k d): pixel x = W/2 (NDC x + 1).
    let intrinsics = Intrinsics {
        fx: 0.5 * w * ax_across.length() / k,
        fy: 0.5 * h * ay_across.length() / k,
        cx: 0.5 * w * (1.0 + ax.dot(forward) / k),
        cy: 0.5 * h * (1.0 + ay.dot(forward) / k),
    };
    // Depth: clip z = alpha (forward . p) + z_w, parallel to forward.
    let alpha = az.dot(forward);
    if (az - alpha * forward).length() > TOLERANCE * scale.max(az.length()) {
        return Err(invalid("tilt the depth axis away from the view direction"));
    }
    if perspective {
        perspective_camera(&rows, forward, up, k, alpha, intrinsics, width, height)
    } else {
        orthographic_camera(&rows, forward, up, k, alpha, intrinsics, width, height)
    }
}

/// The centred projection `intrinsics` describe, when they are centred with square pixels.
fn centred(intrinsics: Intrinsics, width: u32, height: u32) -> Option<f64> {
    let (w, h) = (width as f64, height as f64);
    let Intrinsics { fx, fy, cx, cy } = intrinsics;
    let square = (fx / fy - 1.0).abs() <= CENTRED;
    let on_centre =
        (cx / (0.5 * w) - 1.0).abs() <= CENTRED && (cy / (0.5 * h) - 1.0).abs() <= CENTRED;
    (square && on_centre).then_some(fy)
}

/// The perspective case: the eye is where clip x, y and w all vanish.
#[allow(clippy::too_many_arguments)]
fn perspective_camera(
    rows: &[DVec4; 4],
    forward: DVec3,
    up: DVec3,
    k: f64,
    alpha: f64,
    intrinsics: Intrinsics,
    width: u32,
    height: u32,
) -> Result<Camera> {
    let eye = solve(
        [rows[0].truncate(), rows[1].truncate(), rows[3].truncate()],
        DVec3::new(-rows[0].w, -rows[1].w, -rows[3].w),
    )?;
    // depth(d) = a + c / d with d the view depth.
    let a = alpha / k;
    let c = (rows[2].w + alpha * forward.dot(eye)) / k;
    let reversed = c > 0.0;
    let near = if reversed { c / (1.0 - a) } else { -c / a };
    let far_depth = if reversed { -c / a } else { c / (1.0 - a) };
    // a = 0 (reversed) or a = 1 (standard) is an infinite far plane; rounding leaves it huge.
    let far = (far_depth.is_finite() && far_depth > near && far_depth < near / 1e-12)
        .then_some(far_depth);
    if !(near.is_finite() && near > 0.0) {
        return Err(invalid(format!(
            "put the near plane at view depth {near}: depth must reach 1 (reversed) or 0 (standard) in front of the eye"
        )));
    }
    let projection = match centred(intrinsics, width, height) {
        Some(fy) => Projection::Perspective {
            fov_y_deg: 2.0 * (0.5 * height as f64 / fy).atan().to_degrees(),
        },
        None => Projection::PerspectiveIntrinsics(intrinsics),
    };
    let camera = Camera::new(eye, eye + forward, up, projection, near, width, height)?;
    camera.with_depth(DepthConvention { reversed, far })
}

/// The orthographic case: the eye sits on the line where clip x and y vanish (the image's
/// centre), one near-to-far span in front of the near plane (any point of that line gives
/// the same rays and depths), so the camera is centred.
#[allow(clippy::too_many_arguments)]
fn orthographic_camera(
    rows: &[DVec4; 4],
    forward: DVec3,
    up: DVec3,
    k: f64,
    alpha: f64,
    intrinsics: Intrinsics,
    width: u32,
    height: u32,
) -> Result<Camera> {
    // depth = (alpha t + z_w) / k with t = forward . p.
    if alpha == 0.0 {
        return Err(invalid("give every point the same depth"));
    }
    let z_w = rows[2].w;
    let reversed = alpha < 0.0;
    let (near_value, far_value) = if reversed { (1.0, 0.0) } else { (0.0, 1.0) };
    let t_near = (near_value * k - z_w) / alpha;
    let t_far = (far_value * k - z_w) / alpha;
    let span = t_far - t_near;
    let axis = solve(
        [rows[0].truncate(), rows[1].truncate(), forward],
        DVec3::new(-rows[0].w, -rows[1].w, t_near - span),
    )?;
    let centred_intrinsics = Intrinsics {
        cx: 0.5 * width as f64,
        cy: 0.5 * height as f64,
        ..intrinsics
    };
    let projection = match centred(centred_intrinsics, width, height) {
        Some(fy) => Projection::Orthographic {
            height: height as f64 / fy,
        },
        None => Projection::OrthographicIntrinsics(centred_intrinsics),
    };
    let camera = Camera::new(axis, axis + forward, up, projection, span, width, height)?;
    camera.with_depth(DepthConvention {
        reversed,
        far: Some(2.0 * span),
    })
}

/// The point `p` with `rows[i] . p = rhs[i]`.
fn solve(rows: [DVec3; 3], rhs: DVec3) -> Result<DVec3> {
    let m = DMat3::from_cols(rows[0], rows[1], rows[2]).transpose();
    if m.determinant().abs() <= f64::MIN_POSITIVE {
        return Err(invalid("are singular: no single eye position"));
    }
    Ok(m.inverse() * rhs)
}

fn invalid(why: impl std::fmt::Display) -> Error {
    Error::invalid("host view and projection matrices", why.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// Vulkan-style perspective (y down) for a right-handed view looking down -Z with the
    /// frustum's tangents `l, r, b, t` at unit depth: clip w = d, depth `n / d` (reversed,
    /// infinite) or `f (d - n) / (d (f - n))` (standard, finite).
    fn frustum(l: f64, r: f64, b: f64, t: f64, near: f64, far: Option<f64>) -> DMat4 {
        let (z_z, z_w) = match far {
            None => (0.0, near),
            Some(f) => (-f / (f - near), -near * f / (f - near)),
        };
        // NDC x = (2 X/d - (r + l)) / (r - l) with X/d = x / -z; y down: NDC y = -(...).
        DMat4::from_cols(
            DVec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
            DVec4::new(0.0, -2.0 / (t - b), 0.0, 0.0),
            DVec4::new((r + l) / (r - l), -(t + b) / (t - b), z_z, -1.0),
            DVec4::new(0.0, 0.0, z_w, 0.0),
        )
    }

    fn perspective(fov_y: f64, aspect: f64, near: f64, far: Option<f64>) -> DMat4 {
        let t = (fov_y * 0.5).tan();
        frustum(-t * aspect, t * aspect, -t, t, near, far)
    }

    /// Where the host's matrices and viewport put a world point: attachment pixel and depth.
    fn host_pixel(view: DMat4, projection: DMat4, viewport: HostViewport, p: DVec3) -> DVec3 {
        let clip = projection * view * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        DVec3::new(
            viewport.x as f64 + 0.5 * (ndc.x + 1.0) * viewport.width as f64,
            viewport.y as f64 + 0.5 * (ndc.y + 1.0) * viewport.height as f64,
            ndc.z,
        )
    }

    /// Where the camera puts it.
    fn camera_pixel(camera: &Camera, p: DVec3) -> DVec3 {
        let b = camera.basis();
        let rel = p - camera.eye;
        let d = camera.view_depth(p);
        let (x, y) = (rel.dot(b.right), rel.dot(b.up));
        let screen = if camera.is_orthographic() {
            DVec2::new(x, y)
        } else {
            DVec2::new(x / d, y / d)
        };
        let px = camera.screen_to_pixel(screen);
        let [ox, oy] = camera.viewport_origin;
        DVec3::new(
            px.x + ox as f64,
            px.y + oy as f64,
            camera.depth_map().depth(d),
        )
    }

    /// Every world point lands on the same attachment pixel and depth through the matrices
    /// and viewport and through the camera they give: centred, jittered, asymmetric,
    /// non-square, off-centre orthographic, y-up with a flipped viewport, in a sub-rectangle.
    #[test]
    fn camera_reproduces_the_matrices() {
        let eye = DVec3::new(3.0, 2.0, 7.0);
        let view = DMat4::look_at_rh(eye, DVec3::new(0.5, 0.0, -1.0), DVec3::Y);
        let (w, h) = (320u32, 200u32);
        let full = HostViewport::full(w, h);
        let inset = HostViewport {
            x: 40,
            y: 30,
            width: w,
            height: h as i32,
        };
        // A y-up (OpenGL-style, depth [0, 1]) projection drawn with a flipped viewport.
        let y_up =
            DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)) * perspective(0.9, 1.6, 0.25, None);
        let flipped = HostViewport {
            x: 40,
            y: 30 + h,
            width: w,
            height: -(h as i32),
        };
        let jitter = DMat4::from_translation(DVec3::new(0.6 / w as f64, -0.3 / h as f64, 0.0));
        let cases = [
            (perspective(0.9, 1.6, 0.25, None), full),
            (perspective(0.9, 1.6, 0.25, Some(40.0)), full),
            (jitter * perspective(0.9, 1.6, 0.25, None), full),
            (frustum(-0.9, 0.4, -0.5, 0.7, 0.25, None), full),
            (frustum(-0.5, 0.5, -0.5, 0.5, 0.25, Some(30.0)), inset),
            (y_up, flipped),
            (
                DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0))
                    * DMat4::orthographic_rh(-8.0, 8.0, -5.0, 5.0, 0.5, 60.0),
                full,
            ),
            (
                DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0))
                    * DMat4::orthographic_rh(-3.0, 9.0, -6.0, 2.0, 0.5, 60.0),
                inset,
            ),
        ];
        for (projection, viewport) in cases {
            let camera = Camera::from_view_projection_viewport(view, projection, viewport).unwrap();
            for p in [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.5, -0.7, -3.0),
                DVec3::new(-2.0, 1.0, 2.5),
            ] {
                let want = host_pixel(view, projection, viewport, p);
                let got = camera_pixel(&camera, p);
                assert!(
                    (got - want).length() < 1e-9 * w as f64,
                    "{camera:?}: {got} vs {want}"
                );
            }
        }
    }

    /// A centred projection gives a centred camera; a jittered one keeps its jitter.
    #[test]
    fn centred_projections_stay_centred() {
        let view = DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y);
        let good = perspective(0.9, 2.0, 0.1, None);
        let camera = Camera::from_view_projection(view, good, 200, 100).unwrap();
        assert!(matches!(camera.projection, Projection::Perspective { .. }));
        let jitter = DMat4::from_translation(DVec3::new(1.0 / 200.0, 0.0, 0.0));
        let camera = Camera::from_view_projection(view, jitter * good, 200, 100).unwrap();
        let Projection::PerspectiveIntrinsics(k) = camera.projection else {
            panic!("{camera:?}");
        };
        // Clip x moved by 2 / W of NDC: half a pixel.
        assert!((k.cx - 100.5).abs() < 1e-9, "{k:?}");
    }

    #[test]
    fn refuses_what_the_contract_cannot_express() {
        let view = DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y);
        let good = perspective(0.9, 2.0, 0.1, None);
        assert!(Camera::from_view_projection(view, good, 200, 100).is_ok());
        let mirrored = DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)) * good;
        let mut skewed = good;
        skewed.y_axis.x = 0.3;
        let mut tilted = good;
        tilted.x_axis.z = 0.2;
        for (projection, word) in [
            (mirrored, "mirror"),
            (skewed, "skew"),
            (tilted, "depth axis"),
        ] {
            let err = Camera::from_view_projection(view, projection, 200, 100).unwrap_err();
            assert!(err.to_string().contains(word), "{err}");
        }
        let flipped_too_high = HostViewport {
            x: 0,
            y: 50,
            width: 200,
            height: -100,
        };
        let err = Camera::from_view_projection_viewport(view, good, flipped_too_high).unwrap_err();
        assert!(err.to_string().contains("bottom edge"), "{err}");
    }
}
