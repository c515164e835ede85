//! Exact screen-space bounds of an ellipsoid on the CPU (float64), for a host's tile or light
//! binning: the axis-aligned rectangle of its projected silhouette and a convex polygon around
//! it, both for the part of the ellipsoid beyond the near plane.
//!
//! Work is in view coordinates relative to the eye, with the ellipsoid as
//! `{c + d : d^T S^-1 d <= 1}`, `S = A A^T` and `A = R diag(radii)` in view axes, so the
//! support function along a direction `n` is `sqrt(n^T S n)`.
//!
//! The projected part is `B = E ∩ {z >= near}`. A screen-plane coordinate (slope `x/z` in
//! perspective, `x` in orthographic) is extreme over `B` either where a plane of constant
//! coordinate touches `E` at a point with `z >= near`, or on the rim `E ∩ {z = near}`. So the
//! bounds are the extremes over those candidates, whatever the ellipsoid's position: wholly
//! in front, cut by the near plane, straddling the eye plane, or around the eye (after Mara and
//! McGuire). The polygon is the n-gon the renderer draws for ellipsoids wholly beyond the near
//! plane, the rectangle otherwise. Pixel coordinates are `x` right, `y` down, pixel `(i, j)`
//! covering `[i, i+1] x [j, j+1]`.

use glam::{DMat3, DVec2, DVec3};

use crate::camera::Camera;
use crate::ellipsoid::Ellipsoid;

/// Screen-space bounds in the camera's pixel coordinates: x to the right and y down from the
/// camera image's top-left corner, pixel `(i, j)` covering `[i, i+1] x [j, j+1]` (its centre
/// at `+0.5`), intrinsics and jitter applied. Not moved by `Camera::viewport_origin` (add it
/// for attachment pixels) and not clipped to the image: a host clips to its own viewport or
/// tiles.
#[derive(Clone, Debug, PartialEq)]
pub struct ScreenBounds {
    /// `[x0, y0, x1, y1]`, the tight axis-aligned rectangle of the projected silhouette.
    pub rect: [f64; 4],
    /// A convex polygon holding the silhouette, counter-clockwise as seen on screen (negative
    /// signed area in these y-down coordinates). For an
    /// ellipsoid wholly beyond the near plane it circumscribes the projected ellipse with the
    /// requested number of corners (the footprint the renderer draws); otherwise it is `rect`.
    pub polygon: Vec<DVec2>,
}

impl Ellipsoid {
    /// The exact bounds of this ellipsoid seen by `camera` (float64), for a host's tile or
    /// light binning: the axis-aligned rectangle of its projected silhouette and a polygon of
    /// `corners` (at least 3) corners around it, both for the part beyond the near plane;
    /// `None` when nothing of it lies beyond the near plane.
    pub fn screen_bounds(&self, camera: &Camera, corners: usize) -> Option<ScreenBounds> {
        let view = ViewEllipsoid::new(self, camera);
        let near = camera.near;
        if view.c.z + view.s.z_axis.z.sqrt() < near {
            return None;
        }
        let orthographic = camera.is_orthographic();
        let x = view.range(0, near, orthographic)?;
        let y = view.range(1, near, orthographic)?;
        let to_pixel = |p: DVec2| camera.screen_to_pixel(p);
        let lo = to_pixel(DVec2::new(x.0, y.1));
        let hi = to_pixel(DVec2::new(x.1, y.0));
        let rect = [lo.x, lo.y, hi.x, hi.y];
        let polygon = match view.projected_ellipse(near, orthographic) {
            Some((centre, axes)) => circumscribed_polygon(centre, axes, corners.max(3))
                .into_iter()
                .map(to_pixel)
                .collect(),
            None => vec![
                DVec2::new(rect[0], rect[1]),
                DVec2::new(rect[0], rect[3]),
                DVec2::new(rect[2], rect[3]),
                DVec2::new(rect[2], rect[1]),
            ],
        };
        Some(ScreenBounds { rect, polygon })
    }
}

/// The ellipsoid in view coordinates relative to the eye.
struct ViewEllipsoid {
    /// Centre: (right, up, forward) components.
    c: DVec3,
    /// `S = A A^T`, symmetric positive definite.
    s: DMat3,
}

impl ViewEllipsoid {
    fn new(e: &Ellipsoid, camera: &Camera) -> Self {
        let b = camera.basis();
        let to_view = DMat3::from_cols(b.right, b.up, b.forward).transpose();
        let offset = e.center - camera.eye;
        let a = to_view * DMat3::from_quat(e.rotation) * DMat3::from_diagonal(e.radii);
        ViewEllipsoid {
            c: to_view * offset,
            s: a * a.transpose(),
        }
    }

    /// The range of screen-plane coordinate `axis` (0: x, 1: y) over the part beyond `near`.
    fn range(&self, axis: usize, near: f64, orthographic: bool) -> Option<(f64, f64)> {
        let mut candidates: Vec<f64> = Vec::with_capacity(4);
        // Planes of constant coordinate touching the ellipsoid, where the touching point lies
        // beyond the near plane. Their normals n: (1, 0, -k) for slope k (perspective), the
        // axis itself (orthographic); the touching points are c +- S n / sqrt(n^T S n).
        let e = if axis == 0 { DVec3::X } else { DVec3::Y };
        let (ci, cz) = (self.c[axis], self.c.z);
        let (s_ii, s_iz, s_zz) = (self.s.col(axis)[axis], self.s.col(axis).z, self.s.z_axis.z);
        let touch = |n: DVec3| {
            let sn = self.s * n;
            let h = n.dot(sn).sqrt();
            [self.c + sn / h, self.c - sn / h]
        };
        if orthographic {
            for p in touch(e) {
                if p.z >= near {
                    candidates.push(p[axis]);
                }
            }
        } else {
            // (ci - k cz)^2 = n^T S n with n = e - k z: lead k^2 - 2 half_b k + c0 = 0.
            let lead = s_zz - cz * cz;
            let half_b = s_iz - ci * cz;
            let c0 = s_ii - ci * ci;
            // half_b^2 - lead c0 expanded so the large c_i^2 cz^2 terms cancel exactly.
            let disc = s_zz * ci * ci - 2.0 * s_iz * ci * cz + s_ii * cz * cz
                - (s_ii * s_zz - s_iz * s_iz);
            if disc >= 0.0 {
                let q = half_b + disc.sqrt().copysign(half_b);
                for k in [q / lead, c0 / q] {
                    if !k.is_finite() {
                        continue;
                    }
                    // The touching point on the plane through the eye.
                    let n = e - DVec3::Z * k;
                    let [p, m] = touch(n);
                    let p = if n.dot(p).abs() <= n.dot(m).abs() {
                        p
                    } else {
                        m
                    };
                    if p.z >= near && p.z > 0.0 {
                        candidates.push(k);
                    }
                }
            }
        }
        // The rim: the section at z = near is an ellipse with centre c + t S e_z / S_zz and
        // shape rho^2 (S - S e_z e_z^T S / S_zz) restricted to the plane, t = near - cz.
        let t = near - cz;
        let rho2 = 1.0 - t * t / s_zz;
        if rho2 > 0.0 {
            let centre = ci + t * s_iz / s_zz;
            let half = (rho2 * (s_ii - s_iz * s_iz / s_zz)).max(0.0).sqrt();
            for v in [centre - half, centre + half] {
                candidates.push(if orthographic { v } else { v / near });
            }
        }
        let lo = candidates.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = candidates.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo <= hi).then_some((lo, hi))
    }

    /// The projected ellipse (centre and the 2x2 shape matrix's semi-axis vectors, in
    /// screen-plane units) of an ellipsoid wholly beyond `near`; `None` otherwise.
    fn projected_ellipse(&self, near: f64, orthographic: bool) -> Option<(DVec2, [DVec2; 2])> {
        let s = &self.s;
        let s_zz = s.z_axis.z;
        if self.c.z - s_zz.sqrt() <= near {
            return None;
        }
        let (centre, m00, m01, m11) = if orthographic {
            (
                DVec2::new(self.c.x, self.c.y),
                s.x_axis.x,
                s.y_axis.x,
                s.y_axis.y,
            )
        } else {
            // The silhouette conic's tangent lines n.x = k (planes (n, -k) through the eye)
            // satisfy lead k^2 - 2 (n.beta) k + n^T C n = 0, the quadratic of `range` for any
            // direction n: its centre is beta / lead, its half-width along n
            // sqrt((n.beta)^2 - lead n^T C n) / |lead|.
            let c = self.c;
            let lead = s_zz - c.z * c.z;
            let beta = DVec2::new(s.x_axis.z - c.x * c.z, s.y_axis.z - c.y * c.z);
            let c0 = |i: usize, j: usize| s.col(i)[j] - c[i] * c[j];
            // Support function squared h(n)^2 = n^T M n with M lead^2 = beta beta^T - lead C.
            let inv = 1.0 / (lead * lead);
            (
                beta / lead,
                (beta.x * beta.x - lead * c0(0, 0)) * inv,
                (beta.x * beta.y - lead * c0(0, 1)) * inv,
                (beta.y * beta.y - lead * c0(1, 1)) * inv,
            )
        };
        // Eigen-decomposition of [[m00, m01], [m01, m11]].
        let mean = 0.5 * (m00 + m11);
        let h = (0.25 * (m00 - m11) * (m00 - m11) + m01 * m01).sqrt();
        let (l1, l2) = (mean + h, (mean - h).max(0.0));
        let d = if m00 >= m11 {
            DVec2::new(0.5 * (m00 - m11) + h, m01)
        } else {
            DVec2::new(m01, 0.5 * (m11 - m00) + h)
        };
        let d = if d.length() > 0.0 {
            d.normalize()
        } else {
            DVec2::X
        };
        Some((centre, [d * l1.sqrt(), d.perp() * l2.sqrt()]))
    }
}

/// The regular `n`-gon circumscribing the unit circle, mapped onto the ellipse
/// `centre + axes[0] cos t + axes[1] sin t`, counter-clockwise in screen-plane units.
fn circumscribed_polygon(centre: DVec2, axes: [DVec2; 2], n: usize) -> Vec<DVec2> {
    let step = std::f64::consts::TAU / n as f64;
    let radius = 1.0 / (0.5 * step).cos();
    (0..n)
        .map(|k| {
            let angle = (k as f64 + 0.5) * step;
            centre + (axes[0] * angle.cos() + axes[1] * angle.sin()) * radius
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn near_plane_cut_shows_the_rim() {
        // A unit sphere centred on the near plane (distance 2): the part beyond it is a
        // hemisphere whose widest visible extent is the rim, slope 1 / 2 -- not the tangent
        // cone's 1 / sqrt(3), whose touching points lie before the plane.
        let camera = Camera::look_at(DVec3::ZERO, DVec3::NEG_Z, 90.0, 2.0, 200, 200).unwrap();
        let e = Ellipsoid::new(
            DVec3::new(0.0, 0.0, -2.0),
            DVec3::ONE,
            DQuat::IDENTITY,
            None,
        )
        .unwrap();
        let b = e.screen_bounds(&camera, 4).unwrap();
        let want = [50.0, 50.0, 150.0, 150.0];
        for (got, want) in b.rect.iter().zip(want) {
            assert!((got - want).abs() < 1e-9, "{:?}", b.rect);
        }
        assert_eq!(
            b.polygon.len(),
            4,
            "a cut ellipsoid's polygon is its rectangle"
        );
    }

    #[test]
    fn sphere_on_axis_has_the_analytic_rectangle() {
        // A sphere of radius r at distance d on the axis subtends half-angle asin(r / d): its
        // silhouette is a circle of slope radius r / sqrt(d^2 - r^2).
        let camera = Camera::look_at(DVec3::ZERO, DVec3::NEG_Z, 90.0, 0.1, 200, 200).unwrap();
        let e = Ellipsoid::new(
            DVec3::new(0.0, 0.0, -10.0),
            DVec3::splat(3.0),
            DQuat::IDENTITY,
            None,
        )
        .unwrap();
        let b = e.screen_bounds(&camera, 8).unwrap();
        let slope = 3.0 / (100.0f64 - 9.0).sqrt();
        let half_px = slope * 100.0; // tan(45 deg) = 1: one slope unit is 100 pixels
        for (got, want) in b.rect.iter().zip([
            100.0 - half_px,
            100.0 - half_px,
            100.0 + half_px,
            100.0 + half_px,
        ]) {
            assert!((got - want).abs() < 1e-9, "{:?}", b.rect);
        }
    }
}
