//! A [`Camera`] from a host engine's view and projection matrices, so ellipsoids land exactly
//! where the host's meshes do.
//!
//! The matrices map world points to Vulkan clip space as the host's own vertex shaders do:
//! `clip = projection * view * (p, 1)`, NDC `x` to the right, `y` down, `z` in [0, 1], `w > 0`
//! in front of the eye, drawn with a viewport covering the whole `width x height` image
//! (`minDepth` 0, `maxDepth` 1). Any right-handed rigid view and any symmetric perspective or
//! orthographic projection are accepted, in reversed or standard Z with a finite or infinite
//! far plane. Off-centre (jittered or stereo) frusta and mirroring matrices are refused with
//! an error: the camera contract has a centred principal point and a right-handed frame.

use glam::{DMat3, DMat4, DVec3, DVec4};

use crate::camera::{Camera, Projection};
use crate::depth::DepthConvention;
use crate::error::{Error, Result};

/// How far from exact (relative) the matrices' structure may be: rounding in a host's float32
/// or float64 matrix code stays far below it, a real skew or offset does not.
const TOLERANCE: f64 = 1e-6;

impl Camera {
    /// The camera that `projection * view` describes for a `width x height` image (see the
    /// module documentation for the conventions). Errors say which part of the matrices the
    /// camera contract cannot express.
    pub fn from_view_projection(
        view: DMat4,
        projection: DMat4,
        width: u32,
        height: u32,
    ) -> Result<Self> {
        let m = projection * view;
        if !m.is_finite() {
            return Err(invalid("are not finite"));
        }
        let rows = [m.row(0), m.row(1), m.row(2), m.row(3)];
        let xyz = |r: DVec4| r.truncate();
        let w_axis = xyz(rows[3]);
        let scale = rows.iter().map(|r| xyz(*r).length()).fold(0.0, f64::max);
        if scale == 0.0 {
            return Err(invalid("map every point to the same clip position"));
        }
        let perspective = w_axis.length() > TOLERANCE * scale;
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
            // Right-handed: forward = up x right, from the screen axes below.
            let (ax, ay) = (xyz(rows[0]), xyz(rows[1]));
            ((-ay).cross(ax).normalize_or_zero(), k)
        };
        let (ax, ay, az) = (xyz(rows[0]), xyz(rows[1]), xyz(rows[2]));
        if ax.length() == 0.0 || ay.length() == 0.0 {
            return Err(invalid("flatten the image's x or y axis"));
        }
        let right = ax.normalize();
        let up = -ay.normalize(); // Vulkan NDC y points down; the contract's up points up.
        for (name, axis) in [("x", ax), ("y", ay)] {
            if axis.normalize().dot(forward).abs() > TOLERANCE {
                return Err(invalid(format!(
                    "have an off-centre (jittered or asymmetric) {name} axis, which the camera contract cannot express"
                )));
            }
        }
        if right.dot(up).abs() > TOLERANCE {
            return Err(invalid("skew the image axes"));
        }
        if (forward.cross(up) - right).length() > TOLERANCE {
            return Err(invalid(
                "mirror the image (a left-handed frame or a y-up projection): flip the projection's y or the view's handedness",
            ));
        }
        let (sx, sy) = (k / ax.length(), k / ay.length());
        let aspect = width as f64 / height.max(1) as f64;
        if ((sx / sy) / aspect - 1.0).abs() > TOLERANCE {
            return Err(invalid(format!(
                "have aspect ratio {:.6} but the image is {width}x{height} ({aspect:.6}): pixels must be square",
                sx / sy
            )));
        }
        // Depth: clip z = alpha (forward . p) + z_w, parallel to forward.
        let alpha = az.dot(forward);
        if (az - alpha * forward).length() > TOLERANCE * scale.max(az.length()) {
            return Err(invalid("tilt the depth axis away from the view direction"));
        }
        if perspective {
            perspective_camera(&rows, forward, up, k, alpha, sy, width, height)
        } else {
            orthographic_camera(&rows, forward, up, k, alpha, sy, width, height)
        }
    }
}

/// The perspective case: the eye is where clip x, y and w all vanish.
#[allow(clippy::too_many_arguments)]
fn perspective_camera(
    rows: &[DVec4; 4],
    forward: DVec3,
    up: DVec3,
    k: f64,
    alpha: f64,
    sy: f64,
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
    let camera = Camera::new(
        eye,
        eye + forward,
        up,
        Projection::Perspective {
            fov_y_deg: 2.0 * sy.atan().to_degrees(),
        },
        near,
        width,
        height,
    )?;
    camera.with_depth(DepthConvention { reversed, far })
}

/// The orthographic case: the eye sits on the view axis, one near-to-far span in front of
/// the near plane (any point of the axis gives the same rays and depths).
#[allow(clippy::too_many_arguments)]
fn orthographic_camera(
    rows: &[DVec4; 4],
    forward: DVec3,
    up: DVec3,
    k: f64,
    alpha: f64,
    sy: f64,
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
    let camera = Camera::new(
        axis,
        axis + forward,
        up,
        Projection::Orthographic { height: 2.0 * sy },
        span,
        width,
        height,
    )?;
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

    /// Vulkan-style perspective (y down) for a right-handed view looking down -Z: clip w = d,
    /// depth `n / d` (reversed, infinite) or `f (d - n) / (d (f - n))` (standard, finite).
    fn perspective(fov_y: f64, aspect: f64, near: f64, far: Option<f64>) -> DMat4 {
        let g = 1.0 / (fov_y * 0.5).tan();
        let (z_z, z_w) = match far {
            None => (0.0, near),
            Some(f) => (-f / (f - near), -near * f / (f - near)),
        };
        DMat4::from_cols(
            DVec4::new(g / aspect, 0.0, 0.0, 0.0),
            DVec4::new(0.0, -g, 0.0, 0.0),
            DVec4::new(0.0, 0.0, z_z, -1.0),
            DVec4::new(0.0, 0.0, z_w, 0.0),
        )
    }

    /// Every world point lands on the same pixel and depth through the matrices and through
    /// the camera they give.
    #[test]
    fn camera_reproduces_the_matrices() {
        let eye = DVec3::new(3.0, 2.0, 7.0);
        let view = DMat4::look_at_rh(eye, DVec3::new(0.5, 0.0, -1.0), DVec3::Y);
        let (w, h) = (320, 200);
        let cases = [
            perspective(0.9, 1.6, 0.25, None),
            perspective(0.9, 1.6, 0.25, Some(40.0)),
            DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0))
                * DMat4::orthographic_rh(-8.0, 8.0, -5.0, 5.0, 0.5, 60.0),
        ];
        for projection in cases {
            let camera = Camera::from_view_projection(view, projection, w, h).unwrap();
            let map = camera.depth_map();
            let b = camera.basis();
            let (sx, sy) = camera.ndc_scale();
            for p in [
                DVec3::new(0.0, 0.0, 0.0),
                DVec3::new(1.5, -0.7, -3.0),
                DVec3::new(-2.0, 1.0, 2.5),
            ] {
                let clip = projection * view * p.extend(1.0);
                let want = clip.truncate() / clip.w;
                let d = camera.view_depth(p);
                let rel = p - camera.eye;
                let (x, y) = (rel.dot(b.right), rel.dot(b.up));
                let (nx, ny) = if camera.is_orthographic() {
                    (x / sx, y / sy)
                } else {
                    (x / (sx * d), y / (sy * d))
                };
                let got = DVec3::new(nx, -ny, map.depth(d));
                assert!((got - want).length() < 1e-9, "{camera:?}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn refuses_what_the_contract_cannot_express() {
        let view = DMat4::look_at_rh(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y);
        let good = perspective(0.9, 2.0, 0.1, None);
        assert!(Camera::from_view_projection(view, good, 200, 100).is_ok());
        let mut jittered = good;
        jittered.z_axis.x = 0.01;
        let mirrored = DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0)) * good;
        for (projection, size, word) in [
            (jittered, (200, 100), "off-centre"),
            (mirrored, (200, 100), "mirror"),
            (good, (100, 100), "aspect"),
        ] {
            let err = Camera::from_view_projection(view, projection, size.0, size.1).unwrap_err();
            assert!(err.to_string().contains(word), "{err}");
        }
    }
}
