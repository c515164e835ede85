//! A scene: the ellipsoids to draw, in instance order.

use glam::DVec3;

use crate::ellipsoid::Ellipsoid;

/// The ellipsoids to draw, in instance order (the instance ID is the index).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// Every ellipsoid; the index is its instance ID.
    pub ellipsoids: Vec<Ellipsoid>,
}

impl Scene {
    /// A scene from a list of ellipsoids.
    pub fn new(ellipsoids: Vec<Ellipsoid>) -> Self {
        Self { ellipsoids }
    }

    /// Number of ellipsoids.
    pub fn len(&self) -> usize {
        self.ellipsoids.len()
    }

    /// True when there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.ellipsoids.is_empty()
    }

    /// Axis-aligned bounds `(min, max)` of all ellipsoids (exact per-ellipsoid boxes, after
    /// Herbison-Evans' osculating box `b_i = sqrt(sum_j R_ij^2 a_j^2)`); `None` when empty.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut it = self.ellipsoids.iter();
        let first = it.next()?;
        let half = |e: &Ellipsoid| {
            let m = e.to_world();
            DVec3::new(m.row(0).length(), m.row(1).length(), m.row(2).length())
        };
        let mut lo = first.center - half(first);
        let mut hi = first.center + half(first);
        for e in it {
            lo = lo.min(e.center - half(e));
            hi = hi.max(e.center + half(e));
        }
        Some((lo, hi))
    }

    /// Centre and radius of a sphere containing every ellipsoid; `None` when empty.
    pub fn bounding_sphere(&self) -> Option<(DVec3, f64)> {
        self.bounds().map(Self::sphere_around)
    }

    /// The sphere [`Scene::bounding_sphere`] gives a scene of `bounds`: for a scene known by
    /// the union of its parts' [`Scene::bounds`] (processes drawing shares of one scene).
    pub fn sphere_around((lo, hi): (DVec3, DVec3)) -> (DVec3, f64) {
        ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
    }
}
