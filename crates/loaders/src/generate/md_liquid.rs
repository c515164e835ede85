//! A snapshot of a molecular-dynamics liquid of Gay-Berne-like particles: rods and spheres at
//! liquid density, as a simulation of a mixture would write one frame.

use std::f64::consts::PI;

use glam::{DQuat, DVec3};

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::Scene;

use super::contact::{contact, Body};
use super::SplitMix64;

/// Semi-axes of a rod: the 3:1:1 shape of the Gay-Berne model's standard parametrisation.
pub const ROD_RADII: [f64; 3] = [1.5, 0.5, 0.5];
/// Radius of a sphere (the rods' width).
pub const SPHERE_RADIUS: f64 = 0.5;
/// The share of the box the particles fill: a dense liquid (hard ellipsoids of aspect 3 stay
/// isotropic to about 0.5).
pub const PACKING_FRACTION: f64 = 0.47;
/// Colour of the rods (sRGB).
pub const ROD_COLOR: [f32; 3] = [0.92, 0.52, 0.18];
/// Colour of the spheres (sRGB).
pub const SPHERE_COLOR: [f32; 3] = [0.25, 0.52, 0.9];

/// The relaxation stops once at most this share of the particles overlaps another.
const OVERLAPPING_TARGET: f64 = 0.01;
/// The most relaxation rounds.
const MAX_ROUNDS: usize = 300;
/// Added to each overlap's length when pushing a pair apart (rod widths).
const MARGIN: f64 = 0.01;
/// The farthest a particle moves in one round (rod widths).
const MAX_STEP: f64 = 0.2;
/// The most a rod turns in one round (radians).
const MAX_TURN: f64 = 0.15;

/// The side of the cubic box holding `count` particles of `md_liquid` (half of them rods,
/// rounded down, the rest spheres) at [`PACKING_FRACTION`].
pub fn md_liquid_side(count: usize) -> f64 {
    let (rods, spheres) = kinds(count);
    let volume = rods as f64 * rod_volume() + spheres as f64 * sphere_volume();
    (volume / PACKING_FRACTION).cbrt()
}

/// `count` particles of a liquid mixture, as a molecular-dynamics snapshot: `count / 2` rods
/// (semi-axes 1.5 x 0.5 x 0.5) and the rest spheres (radius 0.5), in uniformly random
/// orientations, in a cube centred on the origin whose side makes the particles fill
/// [`PACKING_FRACTION`] (0.47) of it ([`md_liquid_side`]; about 26.1 for 8,000). Rods are
/// orange, spheres blue.
///
/// Placement: the centres start on a cubic lattice of at least `count` sites (kinds and sites
/// shuffled, each centre jittered by up to a tenth of the spacing), where most rods overlap a
/// neighbour. Then rounds of a soft repulsion push them apart, as an energy minimisation
/// before a simulation does: every overlapping pair (Perram and Wertheim's contact function,
/// exact for ellipsoids) moves apart along its contact normal by its overlap there and the
/// rods turn by the push's torque, centres kept inside the box. The rounds stop once at most
/// 1 % of the particles overlap another (about 40 rounds for 8,000), or after 300; the
/// overlaps left are shallow (both would have to shrink by about 1 % to part). About a second
/// for 8,000 particles. The same `seed` gives the same scene.
pub fn md_liquid(count: usize, seed: u64) -> Scene {
    let mut rng = SplitMix64(seed);
    let side = md_liquid_side(count);
    let (rods, _) = kinds(count);
    let mut is_rod: Vec<bool> = (0..count).map(|k| k < rods).collect();
    shuffle(&mut is_rod, &mut rng);

    let per_side = (1..).find(|&m: &usize| m.pow(3) >= count).unwrap_or(1);
    let spacing = side / per_side as f64;
    let mut sites: Vec<usize> = (0..per_side.pow(3)).collect();
    shuffle(&mut sites, &mut rng);
    let half = 0.5 * side;
    let mut particles: Vec<Particle> = is_rod
        .iter()
        .zip(&sites)
        .map(|(&rod, &site)| {
            let cell = DVec3::new(
                (site % per_side) as f64,
                (site / per_side % per_side) as f64,
                (site / (per_side * per_side)) as f64,
            );
            let jitter = DVec3::new(rng.signed(), rng.signed(), rng.signed()) * 0.1 * spacing;
            let center = (cell + 0.5) * spacing - half + jitter;
            Particle::new(rod, center, rng.rotation())
        })
        .collect();

    relax(&mut particles, side);

    let ellipsoids = particles
        .iter()
        .map(|p| {
            let color = if p.rod { ROD_COLOR } else { SPHERE_COLOR };
            Ellipsoid::new(p.body.center, p.radii(), p.rotation, Some(color))
                .expect("md_liquid builds finite centres, positive radii and unit rotations")
        })
        .collect();
    Scene::new(ellipsoids)
}

/// Rods and spheres among `count` particles.
fn kinds(count: usize) -> (usize, usize) {
    (count / 2, count - count / 2)
}

fn rod_volume() -> f64 {
    4.0 / 3.0 * PI * ROD_RADII[0] * ROD_RADII[1] * ROD_RADII[2]
}

fn sphere_volume() -> f64 {
    4.0 / 3.0 * PI * SPHERE_RADIUS.powi(3)
}

/// Fisher-Yates.
fn shuffle<T>(items: &mut [T], rng: &mut SplitMix64) {
    for i in (1..items.len()).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        items.swap(i, j);
    }
}

/// One particle while it is placed.
#[derive(Clone, Copy, Debug)]
struct Particle {
    rod: bool,
    rotation: DQuat,
    body: Body,
}

impl Particle {
    fn new(rod: bool, center: DVec3, rotation: DQuat) -> Self {
        Self {
            rod,
            rotation,
            body: Body::new(center, radii(rod), rotation),
        }
    }

    fn radii(&self) -> DVec3 {
        radii(self.rod)
    }
}

/// The semi-axes of a rod or a sphere.
fn radii(rod: bool) -> DVec3 {
    if rod {
        DVec3::from_array(ROD_RADII)
    } else {
        DVec3::splat(SPHERE_RADIUS)
    }
}

/// A uniform grid of cells at least as wide as two rods' reach, so that only the 27 cells
/// around a particle's can hold particles it may touch.
struct Cells {
    per_side: usize,
    width: f64,
    half: f64,
    members: Vec<Vec<usize>>,
}

impl Cells {
    fn new(particles: &[Particle], side: f64) -> Self {
        let reach = 2.0 * ROD_RADII[0];
        let per_side = ((side / reach).floor() as usize).max(1);
        let mut cells = Self {
            per_side,
            width: side / per_side as f64,
            half: 0.5 * side,
            members: vec![Vec::new(); per_side.pow(3)],
        };
        for (k, p) in particles.iter().enumerate() {
            let cell = cells.index(cells.coords(p.body.center));
            cells.members[cell].push(k);
        }
        cells
    }

    fn coords(&self, p: DVec3) -> [usize; 3] {
        let last = self.per_side - 1;
        ((p + self.half) / self.width)
            .to_array()
            .map(|x| (x.max(0.0) as usize).min(last))
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        x + self.per_side * (y + self.per_side * z)
    }

    /// The particles in the cells around `p`'s.
    fn around(&self, p: DVec3) -> impl Iterator<Item = usize> + '_ {
        let [x, y, z] = self.coords(p);
        let range = |c: usize| c.saturating_sub(1)..=(c + 1).min(self.per_side - 1);
        range(z).flat_map(move |z| {
            range(y).flat_map(move |y| {
                range(x).flat_map(move |x| self.members[self.index([x, y, z])].iter().copied())
            })
        })
    }
}

/// Pushes overlapping particles apart until few overlap (see [`md_liquid`]): each round
/// finds every overlapping pair, moves both along their contact normal by half the
/// overlap's length there and turns rods by the torque of that push about their centres, all
/// particles at once.
fn relax(particles: &mut [Particle], side: f64) {
    let limit = 0.5 * side;
    let count = particles.len();
    for _ in 0..MAX_ROUNDS {
        let cells = Cells::new(particles, side);
        let mut shift = vec![DVec3::ZERO; count];
        let mut torque = vec![DVec3::ZERO; count];
        let mut touching = vec![false; count];
        for i in 0..count {
            let a = particles[i].body;
            for j in cells.around(a.center).filter(|&j| j > i) {
                let b = particles[j].body;
                let Some(c) = contact(&a, &b) else {
                    continue;
                };
                touching[i] = true;
                touching[j] = true;
                // The overlap's length along the normal, and a little more so that pairs
                // part rather than creep towards touching.
                let length = c.depth * (b.center - a.center).dot(c.normal).max(0.0) + MARGIN;
                let push = 0.5 * length * c.normal;
                shift[i] -= push;
                shift[j] += push;
                torque[i] += (c.point - a.center).cross(-push);
                torque[j] += (c.point - b.center).cross(push);
            }
        }
        let overlapping = touching.iter().filter(|&&t| t).count();
        if overlapping as f64 <= OVERLAPPING_TARGET * count as f64 {
            break;
        }
        for (k, p) in particles.iter_mut().enumerate() {
            if !touching[k] {
                continue;
            }
            let step = shift[k].clamp_length_max(MAX_STEP);
            let center = (p.body.center + step).clamp(DVec3::splat(-limit), DVec3::splat(limit));
            let mut rotation = p.rotation;
            if p.rod {
                // A turn that moves the contact point about as far as the push.
                let reach = p.body.reach;
                let angle = (torque[k].length() / (reach * reach)).min(MAX_TURN);
                if let Some(axis) = torque[k].try_normalize() {
                    rotation = (DQuat::from_axis_angle(axis, angle) * rotation).normalize();
                }
            }
            *p = Particle::new(p.rod, center, rotation);
        }
    }
}

/// The share of `scene`'s glyphs that overlap another, and the deepest overlap (exact, every
/// pair within reach; for tests).
#[cfg(test)]
pub(crate) fn overlaps(scene: &Scene) -> (f64, f64) {
    let bodies: Vec<Body> = scene
        .ellipsoids
        .iter()
        .map(|e| Body::new(e.center, e.radii, e.rotation))
        .collect();
    let mut touched = vec![false; bodies.len()];
    let mut deepest: f64 = 0.0;
    for i in 0..bodies.len() {
        for j in i + 1..bodies.len() {
            let depth = super::contact::overlap_depth(&bodies[i], &bodies[j]);
            if depth > 0.0 {
                touched[i] = true;
                touched[j] = true;
                deepest = deepest.max(depth);
            }
        }
    }
    let share = touched.iter().filter(|&&t| t).count() as f64 / bodies.len().max(1) as f64;
    (share, deepest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_shapes_and_colours() {
        let scene = md_liquid(1001, 7);
        assert_eq!(scene.len(), 1001);
        let rods: Vec<&Ellipsoid> = scene
            .ellipsoids
            .iter()
            .filter(|e| e.color == ROD_COLOR)
            .collect();
        assert_eq!(rods.len(), 500);
        for e in &scene.ellipsoids {
            let mut r = e.radii.to_array();
            r.sort_by(f64::total_cmp);
            if e.color == ROD_COLOR {
                assert!(
                    (r[2] - 1.5).abs() < 1e-12 && (r[0] - 0.5).abs() < 1e-12,
                    "{e:?}"
                );
                assert!((r[1] - 0.5).abs() < 1e-12, "{e:?}");
            } else {
                assert_eq!(e.color, SPHERE_COLOR);
                assert!(r.iter().all(|&x| (x - 0.5).abs() < 1e-12), "{e:?}");
            }
            assert!((e.rotation.length() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn fills_its_box_at_liquid_density() {
        let count = 2000;
        let scene = md_liquid(count, 1);
        let side = md_liquid_side(count);
        let volume: f64 = scene
            .ellipsoids
            .iter()
            .map(|e| 4.0 / 3.0 * PI * e.radii.x * e.radii.y * e.radii.z)
            .sum();
        let fraction = volume / side.powi(3);
        assert!((0.45..=0.5).contains(&fraction), "packing {fraction}");
        for e in &scene.ellipsoids {
            assert!(e.center.abs().max_element() <= 0.5 * side + 1e-9, "{e:?}");
        }
        // The centres spread over the whole box, not a corner of it.
        let (lo, hi) = scene.bounds().expect("not empty");
        assert!(
            (hi - lo).min_element() > side,
            "{lo} {hi} in a box of {side}"
        );
    }

    #[test]
    fn particles_barely_overlap() {
        let scene = md_liquid(2000, 3);
        let (share, deepest) = overlaps(&scene);
        assert!(
            share <= 0.05,
            "{:.1} % of the particles overlap",
            share * 100.0
        );
        assert!(deepest < 0.1, "deepest overlap {deepest}");
    }

    #[test]
    fn rods_point_every_way() {
        // An isotropic liquid: each axis gets a third of the rods' squared direction cosines
        // (a nematic would give one axis far more).
        let scene = md_liquid(2000, 2);
        let axes: Vec<DVec3> = scene
            .ellipsoids
            .iter()
            .filter(|e| e.color == ROD_COLOR)
            .map(|e| e.rotation * DVec3::X)
            .collect();
        let mean = axes.iter().map(|u| *u * *u).sum::<DVec3>() / axes.len() as f64;
        assert!(
            mean.min_element() > 0.28 && mean.max_element() < 0.39,
            "squared direction cosines {mean}"
        );
    }

    #[test]
    fn the_seed_fixes_the_scene() {
        assert_eq!(md_liquid(300, 5), md_liquid(300, 5));
        assert_ne!(md_liquid(300, 5), md_liquid(300, 6));
        assert!(md_liquid(0, 1).is_empty());
        assert_eq!(md_liquid(1, 1).len(), 1);
    }
}
