//! The CPU bounds API against the float64 reference: every pixel centre an ellipsoid covers
//! (its ray hits the part beyond the near plane) lies inside the rectangle and the polygon,
//! and the rectangle is tight to within a pixel and a half -- for ellipsoids wholly in front, cut by
//! the near plane, straddling the eye plane and around the eye, in perspective and
//! orthographic views.
//!
//! Beyond that, against the exact region a camera sees (sampled from the ray/ellipsoid geometry
//! in float64 below, and checked pixel by pixel against the reference): the rectangle is that
//! region's extent to float64 sampling accuracy for every glyph -- across the image border, cut
//! by the near plane (silhouette plus near cap) or not; clipped to the image it is within a
//! pixel of the covered pixel centres wherever the region covers centres that close; and the
//! polygon is convex, counter-clockwise on screen, holds the whole region and touches it with
//! every edge, with the least area an n-gon around the projected ellipse can have.

use ellipsoid_splat::{Camera, Ellipsoid, Projection, ScreenBounds};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::reference::intersect;
use glam::{DQuat, DVec2, DVec3};
use std::f64::consts::{PI, TAU};

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
    let bounds = e.screen_bounds(camera, 8);
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

// ---------------------------------------------------------------------------------------------
// The exact region, independently of src/bounds.rs.
//
// What a camera sees of an ellipsoid `E = {c + T q : |q| <= 1}` (`T = R diag(radii)`) is the
// image of `B = E ∩ {depth >= near}`. That image is convex (a central or parallel projection
// of a convex set in front of the eye), so it is the convex hull of its boundary, and every
// boundary point is the image of a point where a ray touches `B`: either on the contour
// generator of `E` (a ray tangent to the surface) at depth >= near, or on the rim
// `E ∩ {depth = near}` -- a ray cannot touch the flat cap anywhere else. In parameter space
// (`q` on the unit sphere) both are circles: the contour is `q . o = 1` with `o = T^-1 (eye -
// c)` in perspective (`q . (q - o) = 0`) and `q . T^-1 f = 0` in orthographic; the rim is
// `q . T^T f = near - depth(c)`. Sampling both densely, plus the points where they meet, and
// projecting with the camera's pixel-ray contract gives the expectation for every test below.
// `region_oracle_matches_the_reference_renderer` checks it pixel by pixel against
// `reference::intersect`.
// ---------------------------------------------------------------------------------------------

/// Pixel coordinates (x right, y down, pixel `(i, j)` centred at `(i + 0.5, j + 0.5)`) of a
/// world point, from the contract of src/camera.rs: view coordinates along `r`, `u`, `f`,
/// divided by depth in perspective, scaled by `ndc_scale`, shifted by `ndc_shift`, mapped
/// from NDC to pixels.
fn to_pixel(camera: &Camera, p: DVec3) -> DVec2 {
    let b = camera.basis();
    let v = p - camera.eye;
    let (x, y, z) = (v.dot(b.right), v.dot(b.up), v.dot(b.forward));
    let (sx, sy) = camera.ndc_scale();
    let (shift_x, shift_y) = camera.ndc_shift();
    let (nx, ny) = if camera.is_orthographic() {
        (x / sx - shift_x, y / sy - shift_y)
    } else {
        (x / (z * sx) - shift_x, y / (z * sy) - shift_y)
    };
    DVec2::new(
        (nx + 1.0) * 0.5 * camera.width as f64,
        (1.0 - ny) * 0.5 * camera.height as f64,
    )
}

/// `n` points, in order, of the circle `{q : |q| = 1, q . a = h}` (`a` a unit vector).
fn sphere_circle(a: DVec3, h: f64, n: usize) -> Vec<DVec3> {
    if h.abs() >= 1.0 {
        return Vec::new();
    }
    let (p1, p2) = a.any_orthonormal_pair();
    let rho = ((1.0 - h) * (1.0 + h)).sqrt();
    (0..n)
        .map(|k| {
            let t = TAU * k as f64 / n as f64;
            a * h + (p1 * t.cos() + p2 * t.sin()) * rho
        })
        .collect()
}

/// The points of the unit sphere on both planes `q . a1 = h1` and `q . a2 = h2`.
fn sphere_two_planes(a1: DVec3, h1: f64, a2: DVec3, h2: f64) -> Vec<DVec3> {
    let w = a1.cross(a2);
    let ww = w.length_squared();
    if ww < 1e-24 {
        return Vec::new();
    }
    // The line where the planes meet: q0 + s w.
    let q0 = (a2.cross(w) * h1 + w.cross(a1) * h2) / ww;
    let s2 = (1.0 - q0.length_squared()) / ww;
    if s2 < 0.0 {
        return Vec::new();
    }
    let s = s2.sqrt();
    vec![q0 + w * s, q0 - w * s]
}

/// The sampled boundary of what `camera` sees of `e`.
struct Outline {
    /// Images of points of `B`, including (densely) every boundary point of its image.
    points: Vec<DVec2>,
    /// The whole projected contour, in order, when `E` lies wholly beyond the near plane.
    silhouette: Option<Vec<DVec2>>,
    /// The near plane cuts `E`.
    cut: bool,
}

/// Samples per circle; the hull's inner gap is about (largest radius in pixels)
/// `(TAU / n)^2 / 8`.
const SAMPLES: usize = 16384;

/// The outline of what `camera` sees of `e`, `None` when nothing lies beyond the near plane.
fn outline(e: &Ellipsoid, camera: &Camera, n: usize) -> Option<Outline> {
    let f = camera.basis().forward;
    let (c, t) = (e.center, e.to_world());
    let near = camera.near;
    let depth = |q: DVec3| (c + t * q - camera.eye).dot(f);
    // The rim: depth(c) + (T^T f) . q = near.
    let g = t.transpose() * f;
    let rim_h = (near - (c - camera.eye).dot(f)) / g.length();
    if rim_h > 1.0 {
        return None; // the farthest point of E is before the near plane
    }
    let rim_a = g.normalize();
    let inv = t.inverse();
    let contour = if camera.is_orthographic() {
        Some(((inv * f).normalize(), 0.0))
    } else {
        let o = inv * (camera.eye - c);
        (o.length() > 1.0).then(|| (o.normalize(), 1.0 / o.length()))
    };
    let mut q: Vec<DVec3> = sphere_circle(rim_a, rim_h, n);
    let cut = !q.is_empty();
    let mut silhouette = None;
    if let Some((a, h)) = contour {
        let ring = sphere_circle(a, h, n);
        if cut {
            q.extend(ring.into_iter().filter(|&p| depth(p) >= near));
            q.extend(sphere_two_planes(a, h, rim_a, rim_h));
        } else {
            let ring: Vec<DVec2> = ring.iter().map(|&p| to_pixel(camera, c + t * p)).collect();
            silhouette = Some(ring);
        }
    }
    let mut points: Vec<DVec2> = q.iter().map(|&p| to_pixel(camera, c + t * p)).collect();
    if let Some(ring) = &silhouette {
        points.extend_from_slice(ring);
    }
    assert!(!points.is_empty(), "B is not empty, so its outline is not");
    Some(Outline {
        points,
        silhouette,
        cut,
    })
}

/// `[x0, y0, x1, y1]` of points.
fn extent(points: &[DVec2]) -> [f64; 4] {
    points.iter().fold(
        [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ],
        |r, p| [r[0].min(p.x), r[1].min(p.y), r[2].max(p.x), r[3].max(p.y)],
    )
}

/// Twice the signed area (shoelace) of a closed polygon, in its own coordinates.
fn twice_area(polygon: &[DVec2]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|k| polygon[k].perp_dot(polygon[(k + 1) % n]))
        .sum()
}

/// Convex hull (Andrew's monotone chain), positive signed area in the points' coordinates.
fn hull(points: &[DVec2]) -> Vec<DVec2> {
    let mut p = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let mut out: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = out.len();
        let it: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in it {
            while out.len() >= start + 2 {
                let (a, b) = (out[out.len() - 2], out[out.len() - 1]);
                if (b - a).perp_dot(q - a) <= 0.0 {
                    out.pop();
                } else {
                    break;
                }
            }
            out.push(q);
        }
        out.pop();
    }
    out
}

/// Signed distance-like value of `p` against a convex polygon with positive signed area: the
/// largest outward distance to an edge line. Inside, minus the distance to the boundary;
/// outside, at most the distance to the polygon.
fn outside_by(polygon: &[DVec2], p: DVec2) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|k| {
            let (a, b) = (polygon[k], polygon[(k + 1) % n]);
            let edge = b - a;
            -edge.perp_dot(p - a) / edge.length()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The scene of the checks below, for one camera: the random cloud (with needles and blades)
/// and the four hand-placed glyphs of the test above, plus glyphs centred on the image border
/// and its corners at several depths, glyphs cut by the near plane inside the image and across
/// its border, and glyphs straddling the eye plane.
fn scene(camera: &Camera) -> Vec<(String, Ellipsoid)> {
    let mut out = Vec::new();
    let mut cloud = random_cloud(60, 51, 4.0, 1.2);
    for e in cloud.ellipsoids.iter_mut().take(NEEDLES) {
        e.radii.y *= 0.05;
    }
    for (k, e) in cloud.ellipsoids.into_iter().enumerate() {
        out.push((format!("cloud {k}"), e));
    }
    let b = camera.basis();
    let eye = camera.eye;
    for (k, (center, radii)) in [
        (eye, DVec3::new(2.0, 1.0, 1.5)),
        (eye + b.right * 1.5, DVec3::new(1.0, 1.2, 2.5)),
        (eye + b.forward * 0.8, DVec3::new(0.6, 0.4, 0.5)),
        (
            eye + b.forward * 0.9 - b.up * 0.7,
            DVec3::new(0.3, 0.9, 0.2),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        let e = Ellipsoid::new(center, radii, DQuat::from_rotation_x(0.6), None).unwrap();
        out.push((format!("special {k}"), e));
    }
    // A point at view depth `d` on the ray through NDC `(x, y)`.
    let at = |x: f64, y: f64, d: f64| {
        // Both kinds of ray have forward component 1: the parameter is the view depth.
        let pixel = DVec2::new(
            (x + 1.0) * 0.5 * camera.width as f64,
            (1.0 - y) * 0.5 * camera.height as f64,
        );
        let ray = camera.ray_at_pixel(pixel);
        ray.origin + ray.direction * d
    };
    let border = [
        (-1.0, -0.6),
        (-1.0, 0.2),
        (1.0, 0.5),
        (1.0, -0.3),
        (-0.4, 1.0),
        (0.3, 1.0),
        (0.6, -1.0),
        (-0.2, -1.0),
        (-1.0, 1.0),
        (1.0, -1.0),
        (1.0, 1.0),
        (-1.0, -1.0),
    ];
    let mut k = 0usize;
    for &(x, y) in &border {
        for d in [2.0, 4.5, 7.0] {
            let s = d / 4.5;
            let mut radii = DVec3::new(
                0.25 + 0.1 * (k % 5) as f64,
                0.2 + 0.15 * (k % 3) as f64,
                0.3 + 0.07 * (k % 7) as f64,
            ) * s;
            if k % 4 == 3 {
                radii.x *= 4.0; // a needle across the border
                radii.y *= 0.1;
            }
            let rotation = DQuat::from_euler(
                glam::EulerRot::YXZ,
                0.7 * k as f64,
                0.4 + 0.3 * k as f64,
                1.1 * k as f64,
            );
            let e = Ellipsoid::new(at(x, y, d), radii, rotation, None).unwrap();
            out.push((format!("border {k} at ndc ({x}, {y}) depth {d}"), e));
            k += 1;
        }
    }
    // Cut by the near plane: centres just before and just beyond it, inside and across the
    // border.
    let near = camera.near;
    for (k, &(x, y, d, r)) in [
        (0.2, -0.3, near + 0.1, 0.3),
        (-0.5, 0.4, near - 0.1, 0.35),
        (0.0, 0.0, near + 0.25, 0.3),
        (0.6, 0.1, near, 0.2),
        (-1.0, 0.3, near + 0.05, 0.3),
        (1.0, -0.5, near - 0.05, 0.25),
        (0.4, 1.0, near + 0.1, 0.3),
        (-0.7, -1.0, near + 0.2, 0.4),
        (1.0, 1.0, near, 0.3),
    ]
    .iter()
    .enumerate()
    {
        let radii = DVec3::new(r, 0.6 * r, 1.3 * r);
        let rotation = DQuat::from_euler(glam::EulerRot::XYZ, 0.5 + k as f64, 0.9 * k as f64, 0.3);
        let e = Ellipsoid::new(at(x, y, d), radii, rotation, None).unwrap();
        out.push((format!("near cut {k}"), e));
    }
    // Straddling the eye plane, beside the eye.
    for (k, (side, radii)) in [
        (DVec3::new(1.2, 0.3, 0.0), DVec3::new(0.8, 0.5, 1.5)),
        (DVec3::new(-0.4, -1.0, 0.2), DVec3::new(0.6, 0.7, 2.0)),
    ]
    .into_iter()
    .enumerate()
    {
        let center = eye + b.right * side.x + b.up * side.y + b.forward * side.z;
        let e = Ellipsoid::new(center, radii, DQuat::from_rotation_y(0.4), None).unwrap();
        out.push((format!("eye plane {k}"), e));
    }
    out
}

/// The perspective camera of the test above and its orthographic twin.
fn cameras() -> [(&'static str, Camera); 2] {
    let eye = DVec3::new(1.0, 0.5, 6.0);
    let perspective = Camera::look_at(eye, DVec3::ZERO, 60.0, 0.5, 96, 72).unwrap();
    let mut orthographic = perspective;
    orthographic.projection = Projection::Orthographic { height: 9.0 };
    [("perspective", perspective), ("orthographic", orthographic)]
}

#[test]
fn region_oracle_matches_the_reference_renderer() {
    // The projection above is the contract: the ray through a projected point passes through
    // the point, and points on a pixel's ray project onto its centre.
    for (name, camera) in cameras() {
        for (i, j) in [(0, 0), (95, 71), (40, 17), (3, 60)] {
            let ray = camera.ray(i, j);
            for t in [0.5, 2.0, 9.0] {
                let p = to_pixel(&camera, ray.origin + ray.direction * t);
                let want = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                assert!((p - want).length() < 1e-9, "{name}: {p} vs {want}");
            }
        }
    }
    // Pixel by pixel: a centre well inside the sampled region is covered by the reference's ray
    // test, one well outside it is not. The hull of 1024 samples a circle lies inside the
    // region by at most (radius in pixels) 5e-6, so 0.05 pixels is ample margin.
    let margin = 0.05;
    let (mut checked, mut skipped) = (0usize, 0usize);
    for (name, camera) in cameras() {
        let forward = camera.basis().forward;
        for (what, e) in scene(&camera) {
            let Some(o) = outline(&e, &camera, 1024) else {
                continue;
            };
            let region = hull(&o.points);
            let r = extent(&region);
            let (i0, i1) = (
                (r[0] - 2.0).max(0.0) as u32,
                (r[2] + 2.0).clamp(0.0, camera.width as f64) as u32,
            );
            let (j0, j1) = (
                (r[1] - 2.0).max(0.0) as u32,
                (r[3] + 2.0).clamp(0.0, camera.height as f64) as u32,
            );
            for j in j0..j1 {
                for i in i0..i1 {
                    let p = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                    let d = outside_by(&region, p);
                    if d.abs() < margin {
                        skipped += 1;
                        continue;
                    }
                    let hit = intersect(&e, &camera.ray(i, j), camera.near, forward).is_some();
                    assert_eq!(
                        hit,
                        d < 0.0,
                        "{name} {what}: pixel ({i}, {j}) {d} from the region"
                    );
                    checked += 1;
                }
            }
        }
    }
    eprintln!("oracle: {checked} pixel centres agree with the reference, {skipped} within {margin} px skipped");
    assert!(
        checked > 50_000 && skipped * 50 < checked,
        "{checked} checked, {skipped} skipped"
    );
}

#[test]
fn rect_is_the_exact_extent_of_silhouette_and_near_cap() {
    let mut worst = 0.0f64;
    let (mut cut, mut border, mut total) = (0, 0, 0);
    for (name, camera) in cameras() {
        let (w, h) = (camera.width as f64, camera.height as f64);
        for (what, e) in scene(&camera) {
            let bounds = e.screen_bounds(&camera, 8);
            let o = outline(&e, &camera, SAMPLES);
            let (b, o) = match (bounds, o) {
                (Some(b), Some(o)) => (b, o),
                (None, None) => continue,
                (b, o) => panic!(
                    "{name} {what}: bounds {b:?} but beyond the near plane: {}",
                    o.is_some()
                ),
            };
            let want = extent(&o.points);
            let size = (want[2] - want[0]).max(want[3] - want[1]);
            let err = (0..4)
                .map(|k| (b.rect[k] - want[k]).abs())
                .fold(0.0, f64::max);
            worst = worst.max(err / size.max(1.0));
            assert!(
                err <= 1e-6 * size.max(1.0),
                "{name} {what}: rect {:?}, exact extent {want:?}",
                b.rect
            );
            total += 1;
            cut += o.cut as usize;
            border += (want[0] < 0.0 || want[1] < 0.0 || want[2] > w || want[3] > h) as usize;
        }
    }
    eprintln!("rect: {total} rects ({cut} cut by the near plane, {border} across the image border), worst error {worst:e} x size");
    assert!(
        total >= 200 && cut >= 20 && border >= 60,
        "{total} {cut} {border}"
    );
}

#[test]
fn rect_clipped_to_the_image_is_tight_to_covered_pixels() {
    // For glyphs across the image border: on each side, the rectangle clipped to the image
    // reaches no further than the first line of pixel centres that the exact region (clipped to
    // the image) covers -- with the 0.05 px margin of the oracle check, so the reference must
    // cover a centre on it. Where that line is the first line of centres inside the clipped
    // exact extent (a region reaching past the border always covers the border row or column
    // of centres unless it is thinner than a pixel there), this is "within one pixel".
    let margin = 0.05;
    let (mut sides, mut one_pixel, mut glyphs, mut cut) = (0, 0, 0, 0);
    let (mut worst_one, mut worst_any) = (0.0f64, 0.0f64);
    let (mut border_sides, mut worst_border) = (0, 0.0f64);
    for (name, camera) in cameras() {
        let (w, h) = (camera.width as f64, camera.height as f64);
        let clip = |r: [f64; 4]| [r[0].max(0.0), r[1].max(0.0), r[2].min(w), r[3].min(h)];
        for (what, e) in scene(&camera) {
            let (Some(b), Some(o)) = (e.screen_bounds(&camera, 8), outline(&e, &camera, 1024))
            else {
                continue;
            };
            let exact = extent(&outline(&e, &camera, SAMPLES).expect("as above").points);
            if exact[0] >= 0.0 && exact[1] >= 0.0 && exact[2] <= w && exact[3] <= h {
                continue;
            }
            let pixels = covered(&e, &camera);
            if pixels.is_empty() {
                continue;
            }
            glyphs += 1;
            cut += o.cut as usize;
            let region = hull(&o.points);
            let seen = extent(&pixels);
            let beyond = [exact[0] < 0.0, exact[1] < 0.0, exact[2] > w, exact[3] > h];
            let (rect, exact) = (clip(b.rect), clip(exact));
            assert!(
                rect[0] <= seen[0]
                    && rect[1] <= seen[1]
                    && rect[2] >= seen[2]
                    && rect[3] >= seen[3],
                "{name} {what}: clipped rect {rect:?} misses covered centres {seen:?}"
            );
            // Does the line of centres at `c` (a column for x sides, a row for y sides) hold a
            // centre well inside the region?
            let holds = |vertical: bool, c: f64| {
                let n = if vertical {
                    camera.height
                } else {
                    camera.width
                };
                (0..n).any(|k| {
                    let s = k as f64 + 0.5;
                    let p = if vertical {
                        DVec2::new(c, s)
                    } else {
                        DVec2::new(s, c)
                    };
                    outside_by(&region, p) < -margin
                })
            };
            for side in 0..4 {
                let vertical = side % 2 == 0;
                let low = side < 2;
                let n = if vertical {
                    camera.width
                } else {
                    camera.height
                };
                // Lines of centres from the clipped exact extent inwards.
                let first = if low {
                    (exact[side] - 0.5).ceil()
                } else {
                    (exact[side] - 0.5).floor()
                };
                let lines =
                    (0..n as i64).map(|k| first + if low { k as f64 } else { -(k as f64) } + 0.5);
                let Some(line) = lines
                    .take_while(|&c| c > 0.0 && c < n as f64)
                    .find(|&c| holds(vertical, c))
                else {
                    continue; // no centre well inside: only the containment checks apply
                };
                let allowed = (line - exact[side]).abs();
                let gap = (seen[side] - rect[side]).abs();
                assert!(
                    gap <= allowed + 1e-3,
                    "{name} {what}: side {side} of clipped rect {rect:?} is {gap} px from the \
                     covered centres {seen:?}; the exact region covers centres {allowed} px in"
                );
                sides += 1;
                worst_any = worst_any.max(gap);
                if allowed < 1.0 {
                    one_pixel += 1;
                    worst_one = worst_one.max(gap);
                }
                if beyond[side] && allowed < 1.0 {
                    border_sides += 1;
                    worst_border = worst_border.max(gap);
                }
            }
        }
    }
    eprintln!(
        "clipped rect: {glyphs} glyphs across the border ({cut} also cut by the near plane), \
         {sides} sides, {one_pixel} within one pixel by geometry (worst gap {worst_one:.3} px), \
         worst gap overall {worst_any:.3} px; {border_sides} of them on the image \
         border (worst gap {worst_border:.3} px)"
    );
    assert!(glyphs >= 60 && cut >= 4, "{glyphs} glyphs, {cut} cut");
    assert!(one_pixel * 5 >= sides * 4, "{one_pixel} of {sides} sides");
}

/// Corner counts for the polygon checks.
const CORNERS: [usize; 7] = [3, 4, 5, 6, 8, 12, 32];

#[test]
fn polygon_is_convex_and_counter_clockwise_on_screen() {
    // The documented convention: counter-clockwise as seen on screen, which in pixel
    // coordinates (y down) is a negative shoelace area (and a positive one in NDC, y up).
    // Every turn has that sign and the turns add up to one full turn: a simple convex polygon.
    let mut polygons = 0;
    for (name, camera) in cameras() {
        for (what, e) in scene(&camera) {
            let Some(o) = outline(&e, &camera, 64) else {
                continue;
            };
            for corners in CORNERS {
                let b = e
                    .screen_bounds(&camera, corners)
                    .expect("something beyond near");
                let p = &b.polygon;
                if o.silhouette.is_some() {
                    assert_eq!(p.len(), corners, "{name} {what}: corners");
                } else {
                    let r = b.rect;
                    let want = [[r[0], r[1]], [r[0], r[3]], [r[2], r[3]], [r[2], r[1]]]
                        .map(|[x, y]| DVec2::new(x, y));
                    assert_eq!(p, &want, "{name} {what}: a cut glyph's polygon is its rect");
                }
                assert!(p.iter().all(|v| v.is_finite()), "{name} {what}: {p:?}");
                assert!(
                    twice_area(p) < 0.0,
                    "{name} {what} {corners}: clockwise on screen"
                );
                let ndc: Vec<DVec2> = p
                    .iter()
                    .map(|v| {
                        DVec2::new(
                            2.0 * v.x / camera.width as f64 - 1.0,
                            1.0 - 2.0 * v.y / camera.height as f64,
                        )
                    })
                    .collect();
                assert!(
                    twice_area(&ndc) > 0.0,
                    "{name} {what}: positive area in NDC"
                );
                let n = p.len();
                let mut turning = 0.0;
                for k in 0..n {
                    let e1 = p[(k + 1) % n] - p[k];
                    let e2 = p[(k + 2) % n] - p[(k + 1) % n];
                    let cross = e1.perp_dot(e2);
                    assert!(
                        cross < -1e-9 * e1.length() * e2.length(),
                        "{name} {what} {corners}: turn {k} is not counter-clockwise: {p:?}"
                    );
                    turning += cross.atan2(e1.dot(e2));
                }
                assert!(
                    (turning + TAU).abs() < 1e-9,
                    "{name} {what} {corners}: turns add up to {turning}, not -2 pi"
                );
                polygons += 1;
            }
        }
    }
    assert!(polygons >= 200 * CORNERS.len(), "{polygons} polygons");
}

#[test]
fn polygon_holds_and_touches_the_silhouette() {
    // Every silhouette and rim point and every covered pixel centre is inside; every edge
    // touches the exact region (its nearest sampled point is on the edge line); and a polygon
    // around a whole ellipse has the least area an n-gon around an ellipse can have, the
    // affine image of the regular n-gon around a circle: n tan(pi / n) / pi times the ellipse's.
    let (mut worst_out, mut worst_touch, mut worst_area) = (0.0f64, 0.0f64, 0.0f64);
    let (mut whole, mut clipped) = (0, 0);
    for (name, camera) in cameras() {
        for (what, e) in scene(&camera) {
            let Some(o) = outline(&e, &camera, SAMPLES) else {
                continue;
            };
            let pixels = covered(&e, &camera);
            let r = extent(&o.points);
            let size = (r[2] - r[0]).max(r[3] - r[1]).max(1.0);
            for corners in CORNERS {
                let b = e
                    .screen_bounds(&camera, corners)
                    .expect("something beyond near");
                // Counter-clockwise on screen, as the previous test asserts; reversed, it has the
                // positive area `outside_by` wants.
                let poly: Vec<DVec2> = b.polygon.iter().rev().copied().collect();
                let out = o
                    .points
                    .iter()
                    .map(|&p| outside_by(&poly, p))
                    .fold(f64::NEG_INFINITY, f64::max);
                worst_out = worst_out.max(out / size);
                assert!(
                    out <= 1e-9 * size,
                    "{name} {what} {corners}: a silhouette point is {out} px outside"
                );
                for &p in &pixels {
                    assert!(
                        outside_by(&poly, p) <= 1e-9 * size,
                        "{name} {what} {corners}: covered pixel {p} outside the polygon"
                    );
                }
                let n = poly.len();
                for k in 0..n {
                    let (a, edge) = (poly[k], poly[(k + 1) % n] - poly[k]);
                    let normal = edge.perp() / edge.length(); // inward
                    let gap = o
                        .points
                        .iter()
                        .map(|&p| normal.dot(p - a))
                        .fold(f64::INFINITY, f64::min);
                    worst_touch = worst_touch.max(gap / size);
                    assert!(
                        gap <= 1e-6 * size,
                        "{name} {what} {corners}: edge {k} is {gap} px off the silhouette"
                    );
                }
                if let Some(ring) = &o.silhouette {
                    // The sampled ring's orientation depends on its parametrisation.
                    let ratio = (twice_area(&b.polygon) / twice_area(ring)).abs();
                    let c = corners as f64;
                    let want = c * (PI / c).tan() / PI;
                    worst_area = worst_area.max((ratio / want - 1.0).abs());
                    assert!(
                        (ratio / want - 1.0).abs() < 1e-6,
                        "{name} {what} {corners}: area ratio {ratio}, want {want}"
                    );
                    whole += 1;
                } else {
                    clipped += 1;
                }
            }
        }
    }
    eprintln!(
        "polygon: {whole} around whole ellipses, {clipped} rects of cut ones; worst outside \
         {worst_out:e}, worst edge gap {worst_touch:e} (x size); worst relative \
         area ratio error {worst_area:e}"
    );
    assert!(whole >= 150 * CORNERS.len() && clipped >= 20 * CORNERS.len());
}
