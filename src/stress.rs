//! The numerical-stability sweep behind `ellipsoid-splat stress`: scenes and cameras that push
//! one parameter at a time to its extreme, each rendered on the GPU and by the float64
//! reference, with the error checked against [`Bounds::STRICT`].

use glam::{DQuat, DVec3, EulerRot};

use crate::camera::{Camera, Projection};
use crate::compare::{compare, Bounds, ErrorStats};
use crate::ellipsoid::Ellipsoid;
use crate::error::Result;
use crate::offscreen::OffscreenRenderer;
use crate::reference::render_reference;
use crate::renderer::Intersection;
use crate::scene::{random_cloud, Scene};

/// One scene and camera of a sweep.
#[derive(Clone, Debug)]
pub struct StressPoint {
    /// Which sweep: `distance`, `aspect`, `offset`, `fov`, `near`, `size`, `scale`, `coincident`.
    pub sweep: &'static str,
    /// The series within the sweep, e.g. `needle edge-on`.
    pub case: String,
    /// The swept value (the x axis of the sweep's plot).
    pub parameter: f64,
    /// What is drawn.
    pub scene: Scene,
    /// How it is seen.
    pub camera: Camera,
}

/// The outcome of one point with one intersection method.
#[derive(Clone, Debug)]
pub struct StressResult {
    /// Sweep name.
    pub sweep: &'static str,
    /// Series within the sweep.
    pub case: String,
    /// Swept value.
    pub parameter: f64,
    /// Intersection formulation used on the GPU.
    pub method: Intersection,
    /// Error against the reference.
    pub stats: ErrorStats,
    /// `None` when every bound holds, else which bounds broke.
    pub broken: Option<String>,
}

impl StressResult {
    /// Largest ratio of a measured error to its bound (1 = at the bound).
    pub fn worst_ratio(&self, bounds: &Bounds) -> f64 {
        let s = &self.stats;
        [
            s.coverage_mismatch_fraction / bounds.coverage_fraction,
            s.depth_rel_p99 / bounds.depth_rel_p99,
            s.depth_rel_max / bounds.depth_rel_max,
            s.normal_deg_p99 / bounds.normal_deg_p99,
            s.normal_deg_max / bounds.normal_deg_max,
            s.id_mismatch_fraction / bounds.id_mismatch_fraction,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }
}

/// Sweep resolution: the CLI's full sweep, or the reduced one the tests run (every parameter's
/// extremes and a middle value, on small images).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extent {
    /// Every point, 256x192.
    Full,
    /// Extremes and a middle value, 96x72.
    Reduced,
}

impl Extent {
    fn size(self) -> (u32, u32) {
        match self {
            Extent::Full => (256, 192),
            Extent::Reduced => (96, 72),
        }
    }

    /// Keeps every value for `Full`; first, middle and last for `Reduced`.
    fn pick(self, values: &[f64]) -> Vec<f64> {
        match self {
            Extent::Full => values.to_vec(),
            Extent::Reduced => {
                let mut v = vec![values[0], values[values.len() / 2], values[values.len() - 1]];
                v.dedup();
                v
            }
        }
    }
}

/// The test ellipsoid: semi-axes 1 : 0.6 : 0.35 in a general orientation.
fn base_ellipsoid(center: DVec3, scale: f64) -> Ellipsoid {
    Ellipsoid::new(
        center,
        DVec3::new(1.0, 0.6, 0.35) * scale,
        DQuat::from_euler(EulerRot::XYZ, 0.5, 0.9, -0.3),
        Some([0.85, 0.55, 0.3]),
    )
    .expect("constant ellipsoid is valid")
}

/// Twenty overlapping ellipsoids within a sphere of radius about 2.
fn cloud() -> Scene {
    random_cloud(20, 5, 1.3, 0.7)
}

fn perspective(eye: DVec3, target: DVec3, fov: f64, near: f64, (w, h): (u32, u32)) -> Camera {
    Camera::new(eye, target, DVec3::Y, Projection::Perspective { fov_y_deg: fov }, near, w, h)
        .expect("sweep camera is valid")
}

/// Distance from `e`'s centre to its surface along unit direction `dir`.
fn surface_distance(e: &Ellipsoid, dir: DVec3) -> f64 {
    1.0 / (e.to_parameter() * dir).length()
}

/// Camera on `dir` from the scene's bounding sphere, at the distance where the sphere fills
/// the field of view.
fn framing_camera(scene: &Scene, dir: DVec3, fov: f64, size: (u32, u32)) -> Camera {
    let (c, r) = scene.bounding_sphere().expect("sweep scenes are not empty");
    let half = (fov.to_radians() * 0.5).sin();
    let distance = r / half * 1.05;
    let near = (distance - r).max(distance * 1e-4) * 0.5;
    perspective(c + dir.normalize() * distance, c, fov, near, size)
}

/// Every sweep point of the stress test.
pub fn sweep_points(extent: Extent) -> Vec<StressPoint> {
    let size = extent.size();
    let mut points = Vec::new();
    let view = DVec3::new(0.35, 0.45, 1.0).normalize();

    // Distance: eye at k times the centre-to-surface distance along the line of sight, field of
    // view fitted to the silhouette (wide when close, 1e-5 degrees at 1e7).
    for k in extent.pick(&[1.01, 1.1, 2.0, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7]) {
        let e = base_ellipsoid(DVec3::new(0.3, -0.2, 0.1), 1.0);
        let s = surface_distance(&e, view);
        let d = k * s;
        let fov = if d > 1.2 { (2.0 * (1.3 / (d * d - 1.0).sqrt()).atan()).to_degrees() } else { 160.0 };
        let camera = perspective(e.center + view * d, e.center, fov.min(160.0), 0.5 * (d - s), size);
        points.push(StressPoint {
            sweep: "distance",
            case: "ellipsoid 1:0.6:0.35".into(),
            parameter: k,
            scene: Scene::new(vec![e]),
            camera,
        });
    }

    // Aspect ratio: needles and pancakes, edge-on, face-on and at 45 degrees.
    for aspect in extent.pick(&[1.0, 10.0, 100.0, 1e3, 1e4]) {
        for (shape, radii) in [
            ("needle", DVec3::new(1.0, 1.0 / aspect, 1.0 / aspect)),
            ("pancake", DVec3::new(1.0, 1.0, 1.0 / aspect)),
        ] {
            // The needle's long axis is x; the pancake's thin axis is z.
            for (view_name, angle) in [("face-on", 0.0f64), ("45deg", 45.0), ("edge-on", 90.0)] {
                let axis = if shape == "needle" { DVec3::X } else { DVec3::Z };
                let across = if shape == "needle" { DVec3::Z } else { DVec3::X };
                // Face-on looks along the pancake's thin axis / across the needle.
                let a = angle.to_radians();
                let dir = if shape == "needle" {
                    across * a.cos() + axis * a.sin()
                } else {
                    axis * a.cos() + across * a.sin()
                };
                let rotation = DQuat::from_euler(EulerRot::XYZ, 0.2, 0.3, 0.1);
                let e = Ellipsoid::new(DVec3::ZERO, radii, rotation, Some([0.3, 0.6, 0.9]))
                    .expect("sweep ellipsoid is valid");
                let dir = rotation * dir + DVec3::new(0.0, 1e-3, 0.0);
                points.push(StressPoint {
                    sweep: "aspect",
                    case: format!("{shape} {view_name}"),
                    parameter: aspect,
                    camera: perspective(dir.normalize() * 3.0, DVec3::ZERO, 45.0, 0.5, size),
                    scene: Scene::new(vec![e]),
                });
            }
        }
    }

    // World offset: the same scene and camera translated far from the origin.
    for offset in extent.pick(&[0.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7]) {
        let shift = DVec3::new(0.6, -0.48, 0.64) * offset;
        let mut scene = cloud();
        for e in &mut scene.ellipsoids {
            e.center += shift;
        }
        let camera = framing_camera(&scene, view, 45.0, size);
        points.push(StressPoint {
            sweep: "offset",
            case: "cloud of 20".into(),
            parameter: offset,
            scene,
            camera,
        });
    }

    // Field of view, the cloud framed to fill it; and an orthographic view.
    for fov in extent.pick(&[0.001, 0.01, 0.1, 1.0, 10.0, 45.0, 90.0, 120.0, 150.0, 170.0]) {
        let scene = cloud();
        let camera = framing_camera(&scene, view, fov, size);
        points.push(StressPoint {
            sweep: "fov",
            case: "perspective".into(),
            parameter: fov,
            scene,
            camera,
        });
    }
    {
        let scene = cloud();
        let (c, r) = scene.bounding_sphere().expect("cloud is not empty");
        let mut camera = perspective(c + view * 10.0, c, 45.0, 1.0, size);
        camera.projection = Projection::Orthographic { height: 2.2 * r };
        points.push(StressPoint {
            sweep: "fov",
            case: "orthographic".into(),
            parameter: 0.0,
            scene,
            camera,
        });
    }

    // Near-plane cuts through the cloud at several fields of view, and a camera inside one
    // large ellipsoid at several depths.
    for fov in [45.0, 120.0, 170.0] {
        for cut in extent.pick(&[0.05, 0.25, 0.5, 0.75, 0.95]) {
            let scene = cloud();
            let mut camera = framing_camera(&scene, view, fov, size);
            let (c, r) = scene.bounding_sphere().expect("cloud is not empty");
            let d = (c - camera.eye).length();
            camera.near = (d - r) + cut * 2.0 * r;
            points.push(StressPoint {
                sweep: "near",
                case: format!("cut, fov {fov}"),
                parameter: cut,
                scene,
                camera,
            });
        }
    }
    for inside in extent.pick(&[0.0, 0.5, 0.9, 0.99]) {
        let e = base_ellipsoid(DVec3::new(0.3, -0.2, 0.1), 2.0);
        let dir = DVec3::new(-0.2, 0.3, 0.9).normalize();
        let eye = e.center + dir * (inside * surface_distance(&e, dir));
        let target = eye + DVec3::new(0.5, -0.3, -1.0);
        points.push(StressPoint {
            sweep: "near",
            case: "camera inside".into(),
            parameter: inside,
            scene: Scene::new(vec![e]),
            camera: perspective(eye, target, 100.0, 0.05, size),
        });
    }

    // Sub-pixel and few-pixel ellipsoids: a grid of glyphs at irregular sub-pixel positions.
    for pixels in extent.pick(&[0.05, 0.2, 0.5, 1.0, 2.0, 4.0]) {
        let (w, h) = size;
        let distance = 50.0;
        let fov: f64 = 30.0;
        let pixel = 2.0 * distance * (fov.to_radians() * 0.5).tan() / h as f64;
        let radius = 0.5 * pixels * pixel;
        let mut glyphs = Vec::new();
        let n = 12;
        for gy in 0..n {
            for gx in 0..n {
                // Golden-ratio jitter scatters the centres over sub-pixel phases.
                let jx = ((gx * n + gy) as f64 * 0.618_034).fract();
                let jy = ((gy * n + gx) as f64 * 0.414_214).fract();
                let x = ((gx as f64 + 0.5) / n as f64 - 0.5) * w as f64 * 0.9 + jx;
                let y = ((gy as f64 + 0.5) / n as f64 - 0.5) * h as f64 * 0.9 + jy;
                let rotation = DQuat::from_euler(EulerRot::XYZ, gx as f64, gy as f64, 0.3);
                glyphs.push(
                    Ellipsoid::new(
                        DVec3::new(x * pixel, y * pixel, 0.0),
                        DVec3::new(1.0, 0.7, 0.5) * radius,
                        rotation,
                        Some([0.9, 0.9, 0.9]),
                    )
                    .expect("sweep ellipsoid is valid"),
                );
            }
        }
        points.push(StressPoint {
            sweep: "size",
            case: "12x12 glyphs".into(),
            parameter: pixels,
            scene: Scene::new(glyphs),
            camera: perspective(DVec3::new(0.0, 0.0, distance), DVec3::ZERO, fov, 1.0, size),
        });
    }

    // Scale: the cloud and its camera scaled from tiny to huge.
    for scale in extent.pick(&[1e-6, 1e-3, 1.0, 1e3, 1e6]) {
        let mut scene = cloud();
        for e in &mut scene.ellipsoids {
            e.center *= scale;
            e.radii *= scale;
        }
        let camera = framing_camera(&scene, view, 45.0, size);
        points.push(StressPoint {
            sweep: "scale",
            case: "cloud of 20".into(),
            parameter: scale,
            scene,
            camera,
        });
    }

    // Near-coincident surfaces: a copy of an ellipsoid pushed back by gap x distance. The
    // farther copy is drawn first, so draw order cannot hide a wrong depth.
    for gap in extent.pick(&[1e-3, 1e-4, 1e-5, 1e-6, 1e-7]) {
        let front = base_ellipsoid(DVec3::ZERO, 1.0);
        let distance = 6.0;
        let mut back = front;
        back.center = front.center - view * (gap * distance);
        back.color = [0.2, 0.4, 0.9];
        points.push(StressPoint {
            sweep: "coincident",
            case: "copy behind".into(),
            parameter: gap,
            scene: Scene::new(vec![back, front]),
            camera: perspective(view * distance, DVec3::ZERO, 30.0, 1.0, size),
        });
    }
    points
}

/// Renders `point` with `method` on the GPU and by the reference, and measures the error.
pub fn run_point(renderer: &mut OffscreenRenderer, point: &StressPoint, method: Intersection) -> Result<StressResult> {
    renderer.set_intersection(method);
    let frame = renderer.render(&point.scene, &point.camera)?;
    let reference = render_reference(&point.scene, &point.camera)?;
    let stats = compare(&frame, &reference)?;
    let broken = stats.check(&Bounds::STRICT).err();
    Ok(StressResult {
        sweep: point.sweep,
        case: point.case.clone(),
        parameter: point.parameter,
        method,
        stats,
        broken,
    })
}
