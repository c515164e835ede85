//! The numerical-stability sweep behind `ellipsoid-splat stress`: scenes and cameras that push
//! one parameter at a time to its extreme, each rendered on the GPU and by the float64
//! reference, with the error checked against [`Bounds::STRICT`].

use glam::{DQuat, DVec3, EulerRot};

use crate::error::Result;
use ellipsoid_splat::research::{DrawConfig, Intersection};
use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat::OffscreenRenderer;
use ellipsoid_splat::{Camera, Projection};
use ellipsoid_splat::{Outputs, Scene};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::render_reference;
use ellipsoid_splat_reference::{compare, Bounds, ErrorStats};

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
    /// Largest ratio of a checked error to its bound (1 = at the bound); depth and normal
    /// errors beyond the float32 floor, as [`ErrorStats::check`] judges them.
    pub fn worst_ratio(&self, bounds: &Bounds) -> f64 {
        let s = &self.stats;
        [
            s.coverage_mismatch_fraction / bounds.coverage_fraction,
            s.depth_cond_p99 / bounds.depth_rel_p99,
            s.depth_cond_max / bounds.depth_rel_max,
            s.normal_cond_p99 / bounds.normal_deg_p99,
            s.normal_cond_max / bounds.normal_deg_max,
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
    /// Size of the images this extent renders.
    pub fn size(self) -> (u32, u32) {
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
                let mut v = vec![
                    values[0],
                    values[values.len() / 2],
                    values[values.len() - 1],
                ];
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
    Camera::look_at(eye, target, fov, near, w, h).expect("sweep camera is valid")
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

/// Nearest and farthest view depth any ellipsoid of `scene` reaches.
fn depth_extent(scene: &Scene, camera: &Camera) -> (f64, f64) {
    let f = camera.basis().forward;
    scene
        .ellipsoids
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
            let depth = camera.view_depth(e.center);
            let half = (e.to_world().transpose() * f).length();
            (lo.min(depth - half), hi.max(depth + half))
        })
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
        let fov = if d > 1.2 {
            (2.0 * (1.3 / (d * d - 1.0).sqrt()).atan()).to_degrees()
        } else {
            160.0
        };
        let camera = perspective(
            e.center + view * d,
            e.center,
            fov.min(160.0),
            0.5 * (d - s),
            size,
        );
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
                let axis = if shape == "needle" {
                    DVec3::X
                } else {
                    DVec3::Z
                };
                let across = if shape == "needle" {
                    DVec3::Z
                } else {
                    DVec3::X
                };
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

    // Near-plane cuts through the cloud at several fields of view: the plane swept from the
    // nearest to the farthest view depth the ellipsoids reach.
    for fov in [45.0, 120.0, 170.0] {
        for cut in extent.pick(&[0.05, 0.25, 0.5, 0.75, 0.95]) {
            let scene = cloud();
            let mut camera = framing_camera(&scene, view, fov, size);
            let (nearest, farthest) = depth_extent(&scene, &camera);
            camera.near = nearest + cut * (farthest - nearest);
            points.push(StressPoint {
                sweep: "near",
                case: format!("cut, fov {fov}"),
                parameter: cut,
                scene,
                camera,
            });
        }
    }
    // The eye in the middle of the cloud: ellipsoids behind, beside (crossing the eye plane)
    // and in front, some cut by the near plane, at wide fields of view.
    for fov in [90.0, 170.0] {
        for near in extent.pick(&[1e-3, 1e-2, 0.1, 0.3]) {
            let scene = cloud();
            let (c, _) = scene.bounding_sphere().expect("cloud is not empty");
            let eye = c + DVec3::new(0.05, -0.1, 0.02);
            points.push(StressPoint {
                sweep: "near",
                case: format!("eye in cloud, fov {fov}"),
                parameter: near,
                scene,
                camera: perspective(eye, eye + view, fov, near, size),
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
pub fn run_point(
    renderer: &mut OffscreenRenderer,
    point: &StressPoint,
    method: Intersection,
) -> Result<StressResult> {
    renderer.set_draw_config(DrawConfig {
        intersection: method,
        ..DrawConfig::default()
    });
    let frame = renderer.render(&point.scene, &point.camera, Outputs::ALL)?;
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

/// Columns of `stress.csv`.
pub const CSV_HEADER: &[&str] = &[
    "sweep",
    "case",
    "parameter",
    "method",
    "width",
    "height",
    "covered_pixels",
    "ambiguous_pixels",
    "compared_pixels",
    "coverage_mismatch",
    "coverage_fraction",
    "depth_rel_p99",
    "depth_rel_max",
    "depth_f32_floor_p99",
    "depth_beyond_floor_p99",
    "depth_beyond_floor_max",
    "normal_deg_p99",
    "normal_deg_max",
    "normal_f32_floor_p99",
    "normal_beyond_floor_p99",
    "normal_beyond_floor_max",
    "id_mismatch",
    "worst_over_bound",
    "pass",
    "broken",
];

/// Name of a method in tables and plots.
pub fn method_name(method: Intersection) -> &'static str {
    match method {
        Intersection::Stable => "stable",
        Intersection::Textbook => "textbook",
    }
}

impl StressResult {
    /// One CSV row in [`CSV_HEADER`] order.
    pub fn csv_row(&self, width: u32, height: u32) -> Vec<String> {
        let s = &self.stats;
        let e = |v: f64| format!("{v:.4e}");
        vec![
            self.sweep.to_string(),
            self.case.clone(),
            format!("{}", self.parameter),
            method_name(self.method).to_string(),
            width.to_string(),
            height.to_string(),
            s.covered_pixels.to_string(),
            s.ambiguous_pixels.to_string(),
            s.compared_pixels.to_string(),
            s.coverage_mismatch.to_string(),
            e(s.coverage_mismatch_fraction),
            e(s.depth_rel_p99),
            e(s.depth_rel_max),
            e(s.depth_floor_p99),
            e(s.depth_cond_p99),
            e(s.depth_cond_max),
            e(s.normal_deg_p99),
            e(s.normal_deg_max),
            e(s.normal_floor_p99),
            e(s.normal_cond_p99),
            e(s.normal_cond_max),
            s.id_mismatch.to_string(),
            e(self.worst_ratio(&Bounds::STRICT)),
            if self.broken.is_none() { "yes" } else { "no" }.to_string(),
            self.broken.clone().unwrap_or_default(),
        ]
    }
}

/// What a sweep's parameter measures.
pub fn parameter_label(sweep: &str) -> &'static str {
    match sweep {
        "distance" => "eye-centre distance / centre-surface distance along the line of sight",
        "aspect" => "aspect ratio (largest / smallest semi-axis)",
        "offset" => "distance of scene and camera from the world origin",
        "fov" => "vertical field of view (degrees)",
        "near" => "near-plane position: cut fraction, eye-in-cloud near, or inside fraction",
        "size" => "projected size (pixels)",
        "scale" => "scale of scene and camera",
        "coincident" => "gap between the surfaces / distance",
        _ => "parameter",
    }
}

/// Sweeps whose parameter is plotted on a linear axis (fractions); the rest are logarithmic.
fn linear_sweep(sweep: &str) -> bool {
    sweep == "near"
}

/// Writes `stress.csv`, one `stress_<sweep>.png` per sweep (worst error over bound against the
/// swept parameter, one line per case and method) into `dir`, and returns the printed table.
pub fn write_report(
    results: &[StressResult],
    size: (u32, u32),
    dir: &std::path::Path,
) -> Result<String> {
    use crate::report::{fmt_sci, format_table, line_chart, write_csv, Axis, Series, Threshold};

    std::fs::create_dir_all(dir).map_err(|source| crate::error::Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let rows: Vec<Vec<String>> = results.iter().map(|r| r.csv_row(size.0, size.1)).collect();
    write_csv(&dir.join("stress.csv"), CSV_HEADER, &rows)?;

    let mut sweeps: Vec<&'static str> = results.iter().map(|r| r.sweep).collect();
    sweeps.dedup();
    for sweep in &sweeps {
        let mut series: Vec<Series> = Vec::new();
        for r in results.iter().filter(|r| r.sweep == *sweep) {
            let name = format!("{} ({})", r.case, method_name(r.method));
            // Floored so perfect points stay on the log axis.
            let point = (r.parameter, r.worst_ratio(&Bounds::STRICT).max(1e-3));
            match series.iter_mut().find(|s| s.name == name) {
                Some(s) => s.points.push(point),
                None => series.push(Series::new(name, vec![point])),
            }
        }
        let x = if linear_sweep(sweep) {
            Axis::linear(parameter_label(sweep))
        } else {
            Axis::log(parameter_label(sweep))
        };
        line_chart(
            &dir.join(format!("stress_{sweep}.png")),
            &format!("stress sweep '{sweep}': worst error / bound (floored at 1e-3)"),
            &x,
            &Axis::log("worst error / bound"),
            &series,
            &[Threshold::new(1.0, "bound")],
        )?;
    }

    let header = [
        "sweep",
        "case",
        "parameter",
        "method",
        "covered",
        "cov.mis",
        "depth p99",
        "beyond f32",
        "normal p99",
        "beyond f32",
        "worst/bound",
        "pass",
    ];
    let table: Vec<Vec<String>> = results
        .iter()
        .map(|r| {
            let s = &r.stats;
            vec![
                r.sweep.to_string(),
                r.case.clone(),
                fmt_sci(r.parameter),
                method_name(r.method).to_string(),
                s.covered_pixels.to_string(),
                s.coverage_mismatch.to_string(),
                fmt_sci(s.depth_rel_p99),
                fmt_sci(s.depth_cond_p99),
                fmt_sci(s.normal_deg_p99),
                fmt_sci(s.normal_cond_p99),
                fmt_sci(r.worst_ratio(&Bounds::STRICT)),
                if r.broken.is_none() { "yes" } else { "NO" }.to_string(),
            ]
        })
        .collect();
    Ok(format_table(&header, &table))
}
