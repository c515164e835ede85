//! `ellipsoid-splat conformance`: does this device's driver draw ellipsoids exactly? The
//! accuracy cases -- perspective and orthographic, both depth conventions, a finite far plane,
//! near-plane cuts and an eye inside, exact ties, tiny glyphs, the compute path and the draw,
//! general cameras, 4x MSAA coverage -- each rendered under the validation layer and compared
//! with the float64 reference against the strict bounds, colours with the shading model. A
//! report per case, a JUnit file for CI systems, exit status 1 on any failure.

use std::fmt::Write as _;
use std::path::Path;

use ash::vk;
use ellipsoid_splat::research::{DrawConfig, Method};
use ellipsoid_splat::{
    Camera, ContextOptions, DepthConvention, Ellipsoid, Intrinsics, Material, OffscreenRenderer,
    Outputs, Projection, Scene, Settings,
};
use ellipsoid_splat::{PathKind, PlanMode};
use ellipsoid_splat_loaders::{random_cloud, tensor_field};
use ellipsoid_splat_reference::compare::{compare, Bounds, ErrorStats};
use ellipsoid_splat_reference::coverage::{compare_coverage, reference_coverage, SamplePattern};
use ellipsoid_splat_reference::reference::render_reference;
use ellipsoid_splat_reference::shading::compare_colors;
use glam::{DVec2, DVec3};

use crate::error::Result;

/// How a case's frame is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path_ {
    /// The shipped renderer as the plan decides (the compute splat where it pays).
    Shipped,
    /// The draw, never the compute splat.
    Draw,
    /// The compute splat for every glyph it can take.
    Splat,
    /// 4x MSAA, each sample's coverage against the reference's.
    Msaa4,
    /// Every glyph twice (exact depth ties): the same frame as each glyph once, the lower
    /// index winning every tie (the reference calls tied pixels ambiguous).
    Ties,
}

/// One case: a scene, a camera and how it is drawn.
struct Case {
    name: &'static str,
    scene: Scene,
    camera: Camera,
    path: Path_,
}

/// One case's outcome.
pub struct Outcome {
    /// The case's name.
    pub name: &'static str,
    /// Why it failed (`None`: passed; `Some("")` never).
    pub failure: Option<String>,
    /// Its figures, for the report.
    pub figures: String,
    /// Validation messages during the case.
    pub messages: usize,
}

fn look(eye: DVec3, size: (u32, u32)) -> Camera {
    Camera::look_at(eye, DVec3::ZERO, 45.0, 0.5, size.0, size.1).expect("a valid camera")
}

/// The cases; `quick` takes smaller images.
fn cases(quick: bool) -> Vec<Case> {
    let size = if quick { (160, 120) } else { (320, 240) };
    let cloud = random_cloud(if quick { 400 } else { 2000 }, 5, 4.0, 0.5);
    let field = tensor_field(if quick { 8 } else { 14 });
    let (centre, radius) = field.bounding_sphere().expect("a tensor field");
    let framed = Camera::framing(centre, radius, size.0, size.1).expect("framing");
    let mut standard = framed;
    standard.depth = DepthConvention {
        reversed: false,
        // Beyond every glyph: the standard map's depths, not a cut (the test suite cuts).
        far: Some(framed.view_depth(centre) + 2.0 * radius),
    };
    let ortho = Camera {
        projection: Projection::Orthographic {
            height: 2.2 * radius,
        },
        ..framed
    };
    // The eye inside the cloud: glyphs cut by the near plane and around the eye.
    let inside = Camera::look_at(
        DVec3::new(0.1, 0.2, 0.3),
        DVec3::new(3.0, 0.5, -2.0),
        60.0,
        0.05,
        size.0,
        size.1,
    )
    .expect("a valid camera");
    let near_cut = Camera {
        near: 7.0,
        ..look(DVec3::new(0.0, 0.0, 9.0), size)
    };
    // Exact ties: every glyph twice, the lower index must win.
    let twice: Vec<Ellipsoid> = cloud
        .ellipsoids
        .iter()
        .chain(&cloud.ellipsoids)
        .copied()
        .collect();
    let tiny = random_cloud(if quick { 20_000 } else { 100_000 }, 9, 4.0, 0.02);
    let general = Camera {
        projection: Projection::PerspectiveIntrinsics(
            Intrinsics::from_tangents(-0.5, 0.35, -0.3, 0.42, size.0, size.1).expect("tangents"),
        ),
        jitter: DVec2::new(0.31, -0.27),
        ..look(DVec3::new(2.0, 3.0, 11.0), size)
    };
    let white: Vec<Ellipsoid> = cloud
        .ellipsoids
        .iter()
        .map(|e| Ellipsoid {
            color: [1.0; 3],
            ..*e
        })
        .collect();
    let cloud_camera = look(DVec3::new(2.0, 3.0, 11.0), size);
    vec![
        Case {
            name: "tensor field, perspective, reversed Z",
            scene: field.clone(),
            camera: framed,
            path: Path_::Shipped,
        },
        Case {
            name: "tensor field, standard Z, finite far plane",
            scene: field.clone(),
            camera: standard,
            path: Path_::Draw,
        },
        Case {
            name: "tensor field, orthographic",
            scene: field,
            camera: ortho,
            path: Path_::Shipped,
        },
        Case {
            name: "cloud, eye inside",
            scene: cloud.clone(),
            camera: inside,
            path: Path_::Shipped,
        },
        Case {
            name: "cloud, near-plane cuts",
            scene: cloud.clone(),
            camera: near_cut,
            path: Path_::Draw,
        },
        Case {
            name: "cloud, exact ties",
            scene: Scene::new(twice),
            camera: cloud_camera,
            path: Path_::Ties,
        },
        Case {
            name: "tiny glyphs, the compute splat",
            scene: tiny.clone(),
            camera: cloud_camera,
            path: Path_::Splat,
        },
        Case {
            name: "tiny glyphs, the draw",
            scene: tiny,
            camera: cloud_camera,
            path: Path_::Draw,
        },
        Case {
            name: "cloud, off-centre jittered pinhole",
            scene: cloud.clone(),
            camera: general,
            path: Path_::Shipped,
        },
        Case {
            name: "cloud, 4x MSAA coverage",
            scene: Scene::new(white),
            camera: cloud_camera,
            path: Path_::Msaa4,
        },
        Case {
            name: "cloud, the compute splat",
            scene: cloud,
            camera: cloud_camera,
            path: Path_::Splat,
        },
    ]
}

fn settings(path: Path_) -> Settings {
    let mut settings = Settings::default();
    // Conformance runs are reproducible: no path is explored.
    settings.plan = PlanMode::Estimate;
    match path {
        Path_::Shipped => {}
        Path_::Draw | Path_::Ties => settings.plan = PlanMode::Fixed(PathKind::Draw),
        Path_::Splat => settings.plan = PlanMode::Fixed(PathKind::Splat),
        Path_::Msaa4 => settings.material = Material::unlit(),
    }
    settings
}

/// Runs every case on the device `device` picks (under the validation layer); `method`
/// replaces the shipped draw (a baseline: the command's own test breaks it on purpose).
/// Returns the device summary and the outcomes.
pub fn run(
    device: Option<String>,
    quick: bool,
    method: Option<Method>,
) -> Result<(String, Vec<String>, Vec<Outcome>)> {
    let mut options = ContextOptions::validated();
    options.device = device;
    let mut renderer = OffscreenRenderer::new(&options)?;
    let info = renderer.context().info().clone();
    let summary = format!(
        "{} ({:?}), driver {}, Vulkan {}.{}.{}",
        info.name,
        info.device_type,
        info.driver,
        vk::api_version_major(info.api_version),
        vk::api_version_minor(info.api_version),
        vk::api_version_patch(info.api_version)
    );
    let mut left_out = Vec::new();
    if !info.compute_splat {
        left_out.push(
            "the compute splat (no 64-bit buffer atomics): its cases draw instead".to_string(),
        );
    }
    let msaa = renderer.set_samples(vk::SampleCountFlags::TYPE_4).is_ok();
    renderer.set_samples(vk::SampleCountFlags::TYPE_1)?;
    if !msaa {
        left_out.push("4x MSAA (not offered): its case is skipped".to_string());
    }
    let mut outcomes = Vec::new();
    for case in cases(quick) {
        if case.path == Path_::Msaa4 && !msaa {
            continue;
        }
        let before = renderer.context().validation_failures().len();
        renderer.set_settings(settings(case.path));
        renderer.set_draw_config(method.map_or(DrawConfig::default(), |m| m.config()));
        let result = check(&mut renderer, &case);
        let messages = renderer.context().validation_failures().len() - before;
        let (failure, figures) = match result {
            Ok((failure, figures)) => (failure, figures),
            Err(e) => (Some(format!("error: {e}")), String::new()),
        };
        let failure = match (failure, messages) {
            (None, 0) => None,
            (None, n) => Some(format!("{n} validation message(s)")),
            (Some(f), 0) => Some(f),
            (Some(f), n) => Some(format!("{f}; {n} validation message(s)")),
        };
        outcomes.push(Outcome {
            name: case.name,
            failure,
            figures,
            messages,
        });
    }
    renderer.set_draw_config(DrawConfig::default());
    renderer.finish()?;
    Ok((summary, left_out, outcomes))
}

/// One case against the reference: why it fails (if it does) and its figures.
fn check(renderer: &mut OffscreenRenderer, case: &Case) -> Result<(Option<String>, String)> {
    if case.path == Path_::Msaa4 {
        renderer.set_samples(vk::SampleCountFlags::TYPE_4)?;
        let frame = renderer.render(&case.scene, &case.camera, Outputs::COLOR_DEPTH);
        renderer.set_samples(vk::SampleCountFlags::TYPE_1)?;
        let coverage = reference_coverage(&case.scene, &case.camera, SamplePattern::Standard4)?;
        let stats = compare_coverage(&frame?, &coverage)?;
        let failure = (stats.wrong > 0)
            .then(|| format!("{} pixels resolve to the wrong sample count", stats.wrong));
        return Ok((failure, stats.to_string()));
    }
    if case.path == Path_::Ties {
        let doubled = renderer.render(&case.scene, &case.camera, Outputs::ALL)?;
        let half = case.scene.len() / 2;
        let once = Scene::new(case.scene.ellipsoids[..half].to_vec());
        let single = renderer.render(&once, &case.camera, Outputs::ALL)?;
        let shown = single
            .id
            .iter()
            .filter(|&&id| id != ellipsoid_splat::NO_INSTANCE)
            .count();
        let ids = doubled
            .id
            .iter()
            .zip(&single.id)
            .filter(|(a, b)| a != b)
            .count();
        let depths = doubled
            .depth
            .iter()
            .zip(&single.depth)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        let colors = doubled
            .color
            .iter()
            .zip(&single.color)
            .filter(|(a, b)| a != b)
            .count();
        let figures = format!(
            "{shown} pixels shown; {ids} IDs, {depths} depths, {colors} colours differ from the \
             glyphs drawn once"
        );
        let failure = (ids + depths + colors > 0 || shown < 500).then(|| figures.clone());
        return Ok((failure, figures));
    }
    let frame = renderer.render(&case.scene, &case.camera, Outputs::ALL)?;
    let reference = render_reference(&case.scene, &case.camera)?;
    let stats: ErrorStats = compare(&frame, &reference)?;
    let mut failure = Vec::new();
    if stats.coverage_mismatch > 0 {
        failure.push(format!("{} coverage mismatches", stats.coverage_mismatch));
    }
    if stats.id_mismatch > 0 {
        failure.push(format!("{} ID mismatches", stats.id_mismatch));
    }
    if let Err(broken) = stats.check(&Bounds::STRICT) {
        failure.push(broken);
    }
    if stats.compared_pixels < 500 {
        failure.push(format!(
            "only {} pixels compared: the case proves nothing",
            stats.compared_pixels
        ));
    }
    let colors = compare_colors(
        &frame,
        &case.scene,
        &case.camera,
        &settings(case.path).material,
    )?;
    if let Err(broken) = colors.check() {
        failure.push(broken);
    }
    Ok((
        (!failure.is_empty()).then(|| failure.join("; ")),
        format!("{stats}; {colors}"),
    ))
}

/// The report, one line a case, and the summary line.
pub fn report(summary: &str, left_out: &[String], outcomes: &[Outcome]) -> String {
    let mut text = format!("conformance on {summary}\n");
    for item in left_out {
        let _ = writeln!(text, "left out: {item}");
    }
    for o in outcomes {
        let verdict = if o.failure.is_none() { "pass" } else { "FAIL" };
        let _ = writeln!(
            text,
            "{verdict}  {}: {}",
            o.name,
            o.failure.as_deref().unwrap_or(&o.figures)
        );
    }
    let failed = outcomes.iter().filter(|o| o.failure.is_some()).count();
    let _ = writeln!(
        text,
        "{} of {} cases pass",
        outcomes.len() - failed,
        outcomes.len()
    );
    text
}

fn xml_escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The outcomes as a JUnit XML test suite.
pub fn write_junit(path: &Path, summary: &str, outcomes: &[Outcome]) -> Result<()> {
    let failed = outcomes.iter().filter(|o| o.failure.is_some()).count();
    let mut xml = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuite name=\"ellipsoid-splat conformance\" tests=\"{}\" failures=\"{failed}\">\n  <properties><property name=\"device\" value=\"{}\"/></properties>\n",
        outcomes.len(),
        xml_escape(summary)
    );
    for o in outcomes {
        let _ = write!(
            xml,
            "  <testcase classname=\"conformance\" name=\"{}\">",
            xml_escape(o.name)
        );
        match &o.failure {
            Some(why) => {
                let _ = write!(xml, "<failure message=\"{}\"/>", xml_escape(why));
            }
            None => {
                let _ = write!(xml, "<system-out>{}</system-out>", xml_escape(&o.figures));
            }
        }
        xml.push_str("</testcase>\n");
    }
    xml.push_str("</testsuite>\n");
    crate::output::write_file(path, |w| std::io::Write::write_all(w, xml.as_bytes()))
}
