//! Generated scenes, read from no file: the tensor-field demo (after Gumhold 2003's test
//! scene), a random cloud of overlapping ellipsoids, a densely packed block and a snapshot of
//! a liquid of rods and spheres ([`md_liquid`]), for tests, benches and demos. All are
//! deterministic.

mod contact;
mod md_liquid;

pub use md_liquid::{md_liquid, md_liquid_side, PACKING_FRACTION, ROD_COLOR, SPHERE_COLOR};

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use glam::{DQuat, DVec3, EulerRot};

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::Scene;

/// Smallest share of the spherical Westin measure anywhere in the field, so that even the
/// purest cigars and pancakes keep a visible thickness.
const SPHERICAL_FLOOR: f64 = 0.2;

/// An `n x n x n` lattice of glyphs, spacing 1, centred on the origin, from a smooth symmetric
/// positive-definite tensor field (`n = 40` gives the 64,000-glyph demo).
///
/// With `u` the lattice position scaled to `[-1, 1]^3`:
/// - shape: `a = 0.8 u_x + 0.2 sin(pi u_y) sin(pi u_z)`, `t = (1 + sin(pi a / 2)) / 2`, and the
///   quadratic Bernstein weights `(1-t)^2, 2t(1-t), t^2` become the Westin measures
///   linear, spherical, planar (the spherical one lifted to at least 0.2), so
///   cigars, balls and pancakes each fill a large slab that bends with `y` and `z`;
/// - eigenvalues from the measures (`l3 = cs/3`, `l2 = l3 + cp/2`, `l1 = l2 + cl`), scaled so the
///   largest semi-axis is `0.5 + 0.1 cos(pi u_y) cos(pi u_z)`: neighbours nearly touch and
///   sometimes overlap;
/// - orientation: Euler angles `(pi (0.5 u_y + 0.25 u_z), pi/3 u_z + pi/4 sin(pi u_x), pi/2 u_x)`
///   about z, y, x, so the axes turn smoothly across the lattice.
///
/// Glyphs are coloured by shape.
pub fn tensor_field(n: usize) -> Scene {
    let half = (n as f64 - 1.0) / 2.0;
    let scale = half.max(1.0);
    let mut ellipsoids = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let center = DVec3::new(i as f64, j as f64, k as f64) - DVec3::splat(half);
                let u = center / scale;
                let (radii, rotation) = glyph(u);
                let glyph = Ellipsoid::new(center, radii, rotation, None)
                    .expect("tensor field glyphs have positive radii and unit rotations");
                ellipsoids.push(glyph);
            }
        }
    }
    Scene::new(ellipsoids)
}

/// Semi-axes (local x longest) and rotation of the glyph at normalised position `u`.
fn glyph(u: DVec3) -> (DVec3, DQuat) {
    let a = 0.8 * u.x + 0.2 * (PI * u.y).sin() * (PI * u.z).sin();
    let t = 0.5 * (1.0 + (FRAC_PI_2 * a).sin());
    let keep = 1.0 - SPHERICAL_FLOOR;
    let linear = keep * (1.0 - t) * (1.0 - t);
    let planar = keep * t * t;
    let spherical = SPHERICAL_FLOOR + keep * 2.0 * t * (1.0 - t);

    // Eigenvalues with trace 1 whose Westin measures are exactly the three above.
    let l3 = spherical / 3.0;
    let l2 = l3 + planar / 2.0;
    let l1 = l2 + linear;
    let largest = 0.5 + 0.1 * (PI * u.y).cos() * (PI * u.z).cos();
    let radii = DVec3::new(l1, l2, l3) * (largest / l1);

    let rotation = DQuat::from_euler(
        EulerRot::ZYX,
        PI * (0.5 * u.y + 0.25 * u.z),
        PI / 3.0 * u.z + PI / 4.0 * (PI * u.x).sin(),
        FRAC_PI_2 * u.x,
    );
    (radii, rotation)
}

/// `count` random, overlapping ellipsoids: centres uniform in the cube `[-extent, extent]^3`,
/// uniformly random orientations, semi-axes `radius * [0.25, 1]` each (aspect up to 4) and
/// random colours. The same `seed` gives the same scene.
///
/// # Panics
/// If `radius` is not finite and > 0, or `extent` is not finite and >= 0.
pub fn random_cloud(count: usize, seed: u64, extent: f64, radius: f64) -> Scene {
    assert!(
        radius.is_finite() && radius > 0.0,
        "random_cloud radius must be finite and > 0, got {radius}"
    );
    assert!(
        extent.is_finite() && extent >= 0.0,
        "random_cloud extent must be finite and >= 0, got {extent}"
    );
    let mut rng = SplitMix64(seed);
    let ellipsoids = (0..count)
        .map(|_| {
            let center = DVec3::new(rng.signed(), rng.signed(), rng.signed()) * extent;
            let radii = DVec3::new(
                rng.range(0.25, 1.0),
                rng.range(0.25, 1.0),
                rng.range(0.25, 1.0),
            ) * radius;
            let rotation = rng.rotation();
            // Not too dark, so shading stays visible.
            let color = [0; 3].map(|_| rng.range(0.15, 1.0) as f32);
            Ellipsoid::new(center, radii, rotation, Some(color))
                .expect("random_cloud inputs were checked above")
        })
        .collect();
    Scene::new(ellipsoids)
}

/// A dense block of `n`^3 ellipsoids on a unit grid centred on the origin, semi-axes in
/// `[0.5, 0.75]` (neighbours touch or overlap, so from outside only the shell is visible), with
/// random orientations and colours. The same `seed` gives the same scene.
pub fn packed_block(n: usize, seed: u64) -> Scene {
    let mut rng = SplitMix64(seed);
    let offset = 0.5 * (n as f64 - 1.0);
    let mut ellipsoids = Vec::with_capacity(n * n * n);
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let center = DVec3::new(i as f64, j as f64, k as f64) - offset;
                let radii = DVec3::new(
                    rng.range(0.5, 0.75),
                    rng.range(0.5, 0.75),
                    rng.range(0.5, 0.75),
                );
                let rotation = rng.rotation();
                let color = [0; 3].map(|_| rng.range(0.15, 1.0) as f32);
                ellipsoids.push(
                    Ellipsoid::new(center, radii, rotation, Some(color))
                        .expect("packed_block builds valid ellipsoids"),
                );
            }
        }
    }
    Scene::new(ellipsoids)
}

/// Gumhold's lattice as a CPU ray tracer is benchmarked on: an `n x n x n` lattice, spacing 1,
/// centred on the origin, of uniformly randomly rotated ellipsoids whose three semi-axes are
/// each uniform in `[0.1, 0.45]` (neighbours never touch), coloured by shape. The same `seed`
/// gives the same scene.
pub fn lattice(n: usize, seed: u64) -> Scene {
    let mut rng = SplitMix64(seed);
    let offset = 0.5 * (n as f64 - 1.0);
    let mut ellipsoids = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let center = DVec3::new(i as f64, j as f64, k as f64) - offset;
                let radii = DVec3::new(
                    rng.range(0.1, 0.45),
                    rng.range(0.1, 0.45),
                    rng.range(0.1, 0.45),
                );
                let rotation = rng.rotation();
                ellipsoids.push(
                    Ellipsoid::new(center, radii, rotation, None)
                        .expect("lattice builds valid ellipsoids"),
                );
            }
        }
    }
    Scene::new(ellipsoids)
}

/// Steele, Lea and Flood's SplitMix64: tiny, fast and good enough for test scenes.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` from the top 53 bits.
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[-1, 1)`.
    fn signed(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// A uniformly distributed rotation: a unit quaternion made from three uniform numbers.
    fn rotation(&mut self) -> DQuat {
        let (u1, u2, u3) = (self.unit(), TAU * self.unit(), TAU * self.unit());
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        DQuat::from_xyzw(a * u2.sin(), a * u2.cos(), b * u3.sin(), b * u3.cos())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Index of the dominant Westin measure: 0 linear, 1 planar, 2 spherical.
    fn dominant_shape(radii: DVec3) -> usize {
        let mut l = radii.to_array();
        l.sort_by(|a, b| b.total_cmp(a));
        let sum = l[0] + l[1] + l[2];
        let measures = [
            (l[0] - l[1]) / sum,
            2.0 * (l[1] - l[2]) / sum,
            3.0 * l[2] / sum,
        ];
        (0..3)
            .max_by(|&a, &b| measures[a].total_cmp(&measures[b]))
            .unwrap()
    }

    #[test]
    fn field_has_all_three_shape_classes() {
        let scene = tensor_field(40);
        assert_eq!(scene.len(), 64_000);
        let mut counts = [0usize; 3];
        for e in &scene.ellipsoids {
            counts[dominant_shape(e.radii)] += 1;
        }
        for (name, count) in ["linear", "planar", "spherical"].iter().zip(counts) {
            let share = count as f64 / scene.len() as f64;
            assert!(
                share > 0.15,
                "{name} share {share:.3} too small ({counts:?})"
            );
        }
    }

    #[test]
    fn field_radii_positive_finite_and_sized_for_spacing_one() {
        let scene = tensor_field(40);
        for e in &scene.ellipsoids {
            assert!(e.radii.is_finite() && e.radii.min_element() > 0.0, "{e:?}");
            assert!(e.radii.max_element() <= 0.6 + 1e-12, "{e:?}");
            assert!(e.radii.min_element() > 0.02, "too thin to see: {e:?}");
            assert!((e.rotation.length() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn field_lattice_is_centred_with_unit_spacing() {
        let scene = tensor_field(3);
        assert_eq!(scene.len(), 27);
        assert_eq!(scene.ellipsoids[0].center, DVec3::splat(-1.0));
        assert_eq!(scene.ellipsoids[1].center, DVec3::new(0.0, -1.0, -1.0));
        assert_eq!(scene.ellipsoids[26].center, DVec3::splat(1.0));
        assert_eq!(tensor_field(1).ellipsoids[0].center, DVec3::ZERO);
        assert!(tensor_field(0).is_empty());
    }

    #[test]
    fn field_is_deterministic_and_smooth() {
        let n = 12;
        let scene = tensor_field(n);
        assert_eq!(scene, tensor_field(n));
        // Neighbouring glyphs along x differ only a little in size.
        for pair in scene.ellipsoids.windows(2) {
            if pair[1].center.x > pair[0].center.x {
                let d = (pair[1].radii - pair[0].radii).abs().max_element();
                assert!(d < 0.15, "jump {d} between {:?} and {:?}", pair[0], pair[1]);
            }
        }
    }

    #[test]
    fn lattice_is_deterministic_centred_and_within_its_radii() {
        let a = lattice(4, 3);
        assert_eq!(a, lattice(4, 3));
        assert_ne!(a, lattice(4, 4));
        assert_eq!(a.len(), 64);
        assert_eq!(a.ellipsoids[0].center, DVec3::splat(-1.5));
        assert_eq!(a.ellipsoids[1].center, DVec3::new(-0.5, -1.5, -1.5));
        assert_eq!(a.ellipsoids[63].center, DVec3::splat(1.5));
        for e in &a.ellipsoids {
            assert!(
                e.radii.min_element() >= 0.1 && e.radii.max_element() < 0.45,
                "{e:?}"
            );
            assert!((e.rotation.length() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn random_cloud_is_deterministic_and_within_bounds() {
        let a = random_cloud(500, 7, 10.0, 2.0);
        assert_eq!(a, random_cloud(500, 7, 10.0, 2.0));
        assert_ne!(a, random_cloud(500, 8, 10.0, 2.0));
        assert_eq!(a.len(), 500);
        for e in &a.ellipsoids {
            assert!(e.center.abs().max_element() <= 10.0);
            assert!(e.radii.min_element() >= 0.5 && e.radii.max_element() <= 2.0);
            assert!((e.rotation.length() - 1.0).abs() < 1e-12);
            assert!(e.color.iter().all(|c| (0.15..=1.0).contains(c)));
        }
    }
}
