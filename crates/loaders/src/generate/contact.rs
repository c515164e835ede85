//! How far two ellipsoids overlap, from Perram and Wertheim's contact function (J. Comput.
//! Phys. 58, 1985): with each ellipsoid `(x - c)^T M^-1 (x - c) <= 1` (`M = R diag(r^2) R^T`),
//! `F(l) = l (1 - l) d^T [(1 - l) M_a + l M_b]^-1 d` for the centres' offset `d` is concave on
//! `[0, 1]`, and its maximum `F*` is the square of the factor by which both must be scaled
//! about their centres to just touch. So they overlap exactly when `F* < 1`.

use glam::{DMat3, DQuat, DVec3};

/// The most steps of the search for `F`'s maximum (it takes about six).
const STEPS: usize = 40;

/// An ellipsoid as the contact function reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Body {
    pub center: DVec3,
    /// `R diag(r^2) R^T`.
    shape: DMat3,
    /// The largest semi-axis (bounding sphere).
    pub reach: f64,
}

impl Body {
    pub fn new(center: DVec3, radii: DVec3, rotation: DQuat) -> Self {
        let r = DMat3::from_quat(rotation);
        let shape = r * DMat3::from_diagonal(radii * radii) * r.transpose();
        Self {
            center,
            shape,
            reach: radii.max_element(),
        }
    }
}

/// Where and how deeply two ellipsoids overlap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Contact {
    /// `1 - sqrt(F*)`: the share by which both would have to shrink to just touch.
    pub depth: f64,
    /// The point where the shrunk ellipsoids would touch.
    pub point: DVec3,
    /// Their common unit normal there, pointing from `a` towards `b`.
    pub normal: DVec3,
}

/// Whether `a` and `b` overlap, and if so where and how deeply.
pub(crate) fn contact(a: &Body, b: &Body) -> Option<Contact> {
    let d = b.center - a.center;
    let reach = a.reach + b.reach;
    if d.length_squared() >= reach * reach {
        return None;
    }
    // With u = C(l)^-1 d: F(l) = l (1 - l) d.u and, C being linear in l,
    // F'(l) = (1 - 2 l) d.u - l (1 - l) u.(M_b - M_a) u, decreasing from d.M_a^-1 d > 0 at 0 to
    // -d.M_b^-1 d < 0 at 1: F's maximum is the root of F', found by regula falsi (Illinois).
    let diff = b.shape - a.shape;
    let at = |l: f64| -> Option<(f64, f64, DVec3)> {
        let c = a.shape * (1.0 - l) + b.shape * l;
        if c.determinant() <= 0.0 {
            return None;
        }
        let u = c.inverse() * d;
        let du = d.dot(u);
        Some((
            l * (1.0 - l) * du,
            (1.0 - 2.0 * l) * du - l * (1.0 - l) * u.dot(diff * u),
            u,
        ))
    };
    // Most pairs within reach are apart: F(1/2) >= 1 proves it at once.
    let (f, _, _) = at(0.5)?;
    if f >= 1.0 {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let (mut g_lo, mut g_hi) = (d.dot(a.shape.inverse() * d), -d.dot(b.shape.inverse() * d));
    let mut side = 0;
    let mut best = (0.5, f);
    for _ in 0..STEPS {
        let l = (lo * g_hi - hi * g_lo) / (g_hi - g_lo);
        let (f, g, _) = at(l)?;
        let settled = (l - best.0).abs() < 1e-10;
        best = (l, f);
        if f >= 1.0 {
            return None;
        }
        if g == 0.0 || settled {
            break;
        }
        // Illinois: halve the stale end's value when the same end moves twice.
        if g > 0.0 {
            lo = l;
            g_lo = g;
            if side == 1 {
                g_hi *= 0.5;
            }
            side = 1;
        } else {
            hi = l;
            g_hi = g;
            if side == -1 {
                g_lo *= 0.5;
            }
            side = -1;
        }
    }
    let (l, f) = best;
    let (_, _, u) = at(l)?;
    Some(Contact {
        depth: 1.0 - f.max(0.0).sqrt(),
        // The minimiser of l (x-a)^T M_a^-1 (x-a) + (1-l) (x-b)^T M_b^-1 (x-b).
        point: a.center + (1.0 - l) * (a.shape * u),
        normal: u.try_normalize().unwrap_or(DVec3::X),
    })
}

/// How deeply `a` and `b` overlap ([`Contact::depth`]); 0 when they do not.
#[cfg(test)]
pub(crate) fn overlap_depth(a: &Body, b: &Body) -> f64 {
    contact(a, b).map_or(0.0, |c| c.depth)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(x: f64, r: f64) -> Body {
        Body::new(DVec3::new(x, 0.0, 0.0), DVec3::splat(r), DQuat::IDENTITY)
    }

    #[test]
    fn spheres_overlap_by_their_gap() {
        // Radii 0.5 and 0.5 at distance 0.8: both shrink by 0.8 to touch.
        let depth = overlap_depth(&sphere(0.0, 0.5), &sphere(0.8, 0.5));
        assert!((depth - 0.2).abs() < 1e-6, "{depth}");
        assert_eq!(overlap_depth(&sphere(0.0, 0.5), &sphere(1.01, 0.5)), 0.0);
        // Unequal spheres touch where the shrunk ones would: 0.3 / (0.3 + 0.6) of the way.
        let c = contact(&sphere(0.0, 0.3), &sphere(0.6, 0.6)).expect("overlapping");
        assert!((c.depth - (1.0 - 0.6 / 0.9)).abs() < 1e-6, "{c:?}");
        assert!(
            (c.point - DVec3::new(0.2, 0.0, 0.0)).length() < 1e-6,
            "{c:?}"
        );
        assert!((c.normal - DVec3::X).length() < 1e-9, "{c:?}");
    }

    #[test]
    fn rods_side_by_side_and_end_to_end() {
        let rod = |c: DVec3, q: DQuat| Body::new(c, DVec3::new(1.5, 0.5, 0.5), q);
        // Parallel along x, 0.9 apart in y: touching at 1.0, so 10 % too close.
        let a = rod(DVec3::ZERO, DQuat::IDENTITY);
        let b = rod(DVec3::new(0.0, 0.9, 0.0), DQuat::IDENTITY);
        assert!((overlap_depth(&a, &b) - 0.1).abs() < 1e-6);
        // End to end, 2.9 apart along x: touching at 3.0.
        let c = rod(DVec3::new(2.9, 0.0, 0.0), DQuat::IDENTITY);
        assert!((overlap_depth(&a, &c) - 0.1 / 3.0).abs() < 1e-6);
        // Crossed: one along x, one along y, 1.2 apart in y -- its tip reaches 1.5 down into
        // the first one's side (surface at 0.5): overlapping.
        let crossed = rod(
            DVec3::new(0.0, 1.2, 0.0),
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        );
        assert!(overlap_depth(&a, &crossed) > 0.0);
        // 2.1 apart: the tip at 0.6, clear of the surface at 0.5.
        let clear = rod(
            DVec3::new(0.0, 2.1, 0.0),
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        );
        assert_eq!(overlap_depth(&a, &clear), 0.0);
    }
}
