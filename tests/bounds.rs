//! The CPU bounds API against the float64 reference: every pixel centre an ellipsoid covers
//! (its ray hits the part beyond the near plane) lies inside the rectangle and the polygon,
//! and the rectangle is tight to within a pixel and a half -- for ellipsoids wholly in front, cut by
//! the near plane, straddling the eye plane and around the eye, in perspective and
//! orthographic views.

use ellipsoid_splat::bounds::{screen_bounds, ScreenBounds};
use ellipsoid_splat::reference::intersect;
use ellipsoid_splat::scene::random_cloud;
use ellipsoid_splat::{Camera, Ellipsoid, Projection};
use glam::{DQuat, DVec2, DVec3};

/// Pixel centres the ellipsoid covers, by the reference's ray test.
fn covered(e: &Ellipsoid, camera: &Camera) -> Vec<DVec2> {
    let forward = camera.basis().forward;
    let mut out = Vec::new();
    for j in 0..camera.height {
        for i in 0..camera.width {
            if intersect(e, &camera.ray(i, j), camera.near, forward).is_some() {
                out.push(DVec2::new(i as f64 + 0.5, j as f64 + 0.5));
            }
        }
    }
    out
}

/// Whether `p` lies inside the convex polygon (either orientation), with `slack` pixels.
fn inside(polygon: &[DVec2], p: DVec2, slack: f64) -> bool {
    let n = polygon.len();
    let area: f64 = (0..n)
        .map(|k| polygon[k].perp_dot(polygon[(k + 1) % n]))
        .sum();
    (0..n).all(|k| {
        let (a, b) = (polygon[k], polygon[(k + 1) % n]);
        let edge = b - a;
        edge.perp_dot(p - a) * area.signum() >= -slack * edge.length()
    })
}

fn check(e: &Ellipsoid, camera: &Camera, tight: bool, what: &str) -> usize {
    let pixels = covered(e, camera);
    let bounds = screen_bounds(e, camera, 8);
    let Some(ScreenBounds { rect, polygon }) = bounds else {
        assert!(
            pixels.is_empty(),
            "{what}: no bounds but {} pixels",
            pixels.len()
        );
        return 0;
    };
    if pixels.is_empty() {
        return 0;
    }
    // Rounding of the reference's hits at the silhouette: a hair of slack.
    let slack = 1e-6;
    for p in &pixels {
        assert!(
            p.x >= rect[0] - slack
                && p.x <= rect[2] + slack
                && p.y >= rect[1] - slack
                && p.y <= rect[3] + slack,
            "{what}: pixel {p} outside rect {rect:?}"
        );
        assert!(
            inside(&polygon, *p, slack),
            "{what}: pixel {p} outside polygon"
        );
    }
    // Tight: each side within 1.5 pixels of the outermost covered pixel centre, for glyphs
    // wholly inside the image: past its extreme line a round silhouette is narrow for a
    // moment, so the first row of centres it covers can lie just over a pixel inside. (Not
    // for needles: a thin tip can reach far past the last pixel centre it covers.)
    let (w, h) = (camera.width as f64, camera.height as f64);
    if !tight || rect[0] < 0.0 || rect[1] < 0.0 || rect[2] > w || rect[3] > h {
        return pixels.len();
    }
    let min_x = pixels.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let max_x = pixels.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
    let min_y = pixels.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let max_y = pixels.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    let gaps = [
        min_x - rect[0],
        min_y - rect[1],
        rect[2] - max_x,
        rect[3] - max_y,
    ];
    assert!(
        gaps.iter().all(|&g| g <= 1.5),
        "{what}: rect {rect:?} loose against covered pixels {min_x}..{max_x} x {min_y}..{max_y}"
    );
    TIGHT_CHECKED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    pixels.len()
}

/// Glyphs whose rectangle was checked for tightness.
static TIGHT_CHECKED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

/// The first glyphs of the scene are needles and blades.
const NEEDLES: usize = 10;

#[test]
fn bounds_hold_every_covered_pixel_and_are_tight() {
    let mut scene = random_cloud(60, 51, 4.0, 1.2);
    // Needles and blades, and glyphs around the eye and across the near and eye planes.
    for e in scene.ellipsoids.iter_mut().take(NEEDLES) {
        e.radii.y *= 0.05;
    }
    let eye = DVec3::new(1.0, 0.5, 6.0);
    let perspective = Camera::look_at(eye, DVec3::ZERO, 60.0, 0.5, 96, 72).unwrap();
    let basis = perspective.basis();
    for (center, radii) in [
        (eye, DVec3::new(2.0, 1.0, 1.5)), // around the eye
        (eye + basis.right * 1.5, DVec3::new(1.0, 1.2, 2.5)), // across the eye plane
        (eye + basis.forward * 0.8, DVec3::new(0.6, 0.4, 0.5)), // cut by the near plane
        (
            eye + basis.forward * 0.9 - basis.up * 0.7,
            DVec3::new(0.3, 0.9, 0.2),
        ),
    ] {
        scene
            .ellipsoids
            .push(Ellipsoid::new(center, radii, DQuat::from_rotation_x(0.6), None).unwrap());
    }
    let mut orthographic = perspective;
    orthographic.projection = Projection::Orthographic { height: 9.0 };
    let mut total = 0;
    for (name, camera) in [
        ("perspective", &perspective),
        ("orthographic", &orthographic),
    ] {
        for (k, e) in scene.ellipsoids.iter().enumerate() {
            total += check(e, camera, k >= NEEDLES, &format!("{name} ellipsoid {k}"));
        }
    }
    assert!(total > 5_000, "only {total} covered pixels checked");
    let tight = TIGHT_CHECKED.load(std::sync::atomic::Ordering::Relaxed);
    assert!(tight >= 20, "only {tight} rectangles checked for tightness");
}
