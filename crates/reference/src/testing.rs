//! Test support: every GPU test renders on a validated device (core + synchronization
//! validation; any message fails), compares with the float64 reference, and tears down
//! checking for leaks and late validation messages.

use crate::compare::{compare, Bounds, ErrorStats};
use crate::reference::render_reference;
use crate::shading::compare_colors;
use ellipsoid_splat::{Camera, Frame, InstanceFormat, OffscreenRenderer, Outputs, Scene};
use ellipsoid_splat::{ContextOptions, FramePlan, Settings, NO_INSTANCE};
use ellipsoid_splat::{HiddenLayers, PathKind, PlanMode};

/// Prints the library's log on stderr, for runs that want each validation message as it
/// arrives (`scripts/validation-modes.sh` sets `ELLIPSOID_SPLAT_PRINT_VALIDATION`).
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }

    fn log(&self, record: &log::Record) {
        eprintln!("{}", record.args());
    }

    fn flush(&self) {}
}

/// Installs [`StderrLog`] once when `ELLIPSOID_SPLAT_PRINT_VALIDATION` is set.
fn print_log_if_asked() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if std::env::var_os("ELLIPSOID_SPLAT_PRINT_VALIDATION").is_some()
            && log::set_logger(&StderrLog).is_ok()
        {
            log::set_max_level(log::LevelFilter::Info);
        }
    });
}

/// A renderer on a device with validation and synchronization validation on.
pub fn validated_renderer() -> OffscreenRenderer {
    print_log_if_asked();
    OffscreenRenderer::new(&ContextOptions::validated())
        .expect("validated Vulkan device (lavapipe)")
}

/// Fails the test on any validation message so far, then tears the renderer down checking
/// for leaks and late messages.
pub fn finish_validated(renderer: OffscreenRenderer) {
    renderer
        .context()
        .check_validation()
        .expect("no validation messages");
    renderer
        .finish()
        .expect("clean shutdown: no leaks, no validation messages");
}

/// Renders `scene` on the GPU under validation and returns the frame; fails the test on any
/// validation message, leak, or error.
pub fn render_gpu(scene: &Scene, camera: &Camera) -> Frame {
    let mut renderer = validated_renderer();
    let frame = renderer
        .render(scene, camera, Outputs::ALL)
        .expect("GPU render");
    finish_validated(renderer);
    frame
}

/// GPU against reference; asserts `bounds` and that the scene covers at least
/// `min_covered` pixels (so the comparison is not vacuous). Returns the statistics.
pub fn assert_matches_reference(
    scene: &Scene,
    camera: &Camera,
    bounds: &Bounds,
    min_covered: usize,
) -> ErrorStats {
    let frame = render_gpu(scene, camera);
    let reference = render_reference(scene, camera).expect("reference render");
    let stats = compare(&frame, &reference).expect("same size");
    println!("{stats}");
    assert!(
        stats.covered_pixels >= min_covered,
        "scene covers only {} pixels (< {min_covered}): the comparison would prove little",
        stats.covered_pixels
    );
    if let Err(broken) = stats.check(bounds) {
        panic!("GPU differs from the float64 reference: {broken}\n{stats}");
    }
    stats
}

/// The error bounds of the compact instance format (float16 semi-axes rounded to 2^-11
/// relative, snorm16 rotation to 2^-15 rad) for `scene` seen by `camera`: the surface moves by
/// up to 2^-11 of the largest semi-axis plus the rotation's share, so relative depth errs by up
/// to about 2 x 2^-11 r_max / d_min; a normal turns by up to 2^-11 rad from the rounded axes
/// and by the curvature times that displacement at the hit point, up to 2^-11 (r_max/r_min)^2
/// rad: about 0.25 degrees for glyphs of aspect <= 3.
pub fn compact_format_bounds(scene: &Scene, camera: &Camera) -> Bounds {
    let eps = 2f64.powi(-11);
    let r_max = scene
        .ellipsoids
        .iter()
        .map(|e| e.radii.max_element())
        .fold(0.0, f64::max);
    let d_min = scene
        .ellipsoids
        .iter()
        .map(|e| camera.view_depth(e.center) - r_max)
        .fold(f64::INFINITY, f64::min);
    let depth = 2.0 * eps * r_max / d_min;
    Bounds {
        coverage_fraction: 2e-3,
        depth_rel_p99: depth,
        depth_rel_max: depth,
        normal_deg_p99: 0.25,
        normal_deg_max: 1.0,
        ..Bounds::STRICT
    }
}

/// `bounds` widened by what standard Z cannot hold in perspective. The shader writes
/// `z = a + b d + c/d` (`1 - n/d` with an infinite far plane, scaled by `f/(f-n)` with a finite
/// one); near 1 its last addition rounds to half of float32's 2^-24 and the terms before it err
/// by as much again, so `z` is good to about `2^-24` absolute, and the view depth read back as
/// `n / (1 - z)` errs by `2^-24 d / n` relative -- once `d > 17 n`, more than the strict
/// `1e-6`. That quantisation is added to the bounds, taken at the farthest surface the scene
/// can show (the far plane's depth at most). Reversed Z and orthographic maps keep float32's
/// relative precision: `bounds` unchanged.
pub fn depth_convention_bounds(bounds: Bounds, scene: &Scene, camera: &Camera) -> Bounds {
    if camera.depth.reversed || camera.is_orthographic() {
        return bounds;
    }
    let d_max = scene
        .ellipsoids
        .iter()
        .map(|e| camera.view_depth(e.center) + e.radii.max_element())
        .fold(camera.near, f64::max);
    let d_max = camera.depth.far.map_or(d_max, |far| d_max.min(far));
    let quantisation = 2f64.powi(-24) * d_max / camera.near;
    Bounds {
        depth_rel_p99: bounds.depth_rel_p99 + quantisation,
        depth_rel_max: bounds.depth_rel_max + quantisation,
        ..bounds
    }
}

/// How closely two frames of one scene, drawn by two paths of the renderer that compute the
/// same arithmetic (the compute splat and the draw, a shader variant and the general shader),
/// must agree on the renderer's driver.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Agreement {
    /// Bit for bit: the driver compiles the same functions to the same arithmetic in every
    /// stage and variant (lavapipe: one LLVM back end, no contraction).
    Bits,
    /// The same glyph wherever the float64 reference is unambiguous, and the second frame
    /// within the reference's bounds: a driver may round the two builds differently
    /// (NVIDIA's does; design §9.5), and where a pixel's float32 floor is large no fixed
    /// tolerance between the two frames would hold.
    Reference,
}

impl Agreement {
    /// `Bits` on lavapipe, `Reference` elsewhere.
    pub fn of(renderer: &OffscreenRenderer) -> Agreement {
        if renderer.context().info().driver.starts_with("llvmpipe") {
            Agreement::Bits
        } else {
            Agreement::Reference
        }
    }
}

/// What a frame shows: the scene, the camera, and the instance format it was drawn with (the
/// compact format has bounds of its own); drawn with the default material.
#[derive(Clone, Copy)]
pub struct Seen<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The camera.
    pub camera: &'a Camera,
    /// The instance format.
    pub format: InstanceFormat,
}

/// The bounds a frame of `seen` is held to: `Bounds::STRICT`, or the compact format's, widened
/// where standard Z cannot hold them.
pub fn bounds_for(seen: Seen) -> Bounds {
    let Seen {
        scene,
        camera,
        format,
    } = seen;
    let bounds = match format {
        InstanceFormat::Compact => compact_format_bounds(scene, camera),
        _ => Bounds::STRICT,
    };
    depth_convention_bounds(bounds, scene, camera)
}

/// Asserts that `other` agrees with `first` (both showing `seen`) as `agreement` asks, and that
/// `first` shows enough glyph pixels for that to mean something.
pub fn assert_frames_agree(
    agreement: Agreement,
    name: &str,
    first: &Frame,
    other: &Frame,
    seen: Seen,
) {
    let shown = first.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    assert!(shown > 300, "{name}: only {shown} pixels show a glyph");
    let differ = |what: &str, count: usize| {
        assert_eq!(count, 0, "{name}: {count} pixels differ in {what}");
    };
    let count = |a: &[u32], b: &[u32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    if agreement == Agreement::Reference {
        let Seen { scene, camera, .. } = seen;
        let reference = render_reference(scene, camera).expect("reference render");
        let ids = (0..first.len())
            .filter(|&k| first.id[k] != other.id[k] && !reference.ambiguous[k])
            .count();
        differ("ID where the reference is unambiguous", ids);
        for (which, frame) in [("first", first), ("second", other)] {
            let stats = compare(frame, &reference).expect("same size");
            if let Err(broken) = stats.check(&bounds_for(seen)) {
                panic!("{name}: the {which} frame against the reference: {broken}\n{stats}");
            }
            let colors = compare_colors(frame, scene, camera, &Settings::default().material)
                .expect("colour comparison");
            if let Err(broken) = colors.check() {
                panic!("{name}: the {which} frame: {broken}");
            }
            if which == "second" {
                let depths = count(&bits(&first.depth), &bits(&other.depth));
                println!("{name}: {depths} depths differ in their bits; {stats}; {colors}");
            }
        }
        return;
    }
    differ("ID", count(&first.id, &other.id));
    let normal_bits = |v: &[[f32; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    differ("depth", count(&bits(&first.depth), &bits(&other.depth)));
    differ(
        "normal",
        count(&normal_bits(&first.normal), &normal_bits(&other.normal)),
    );
    let colors = (first.color.iter().zip(&other.color))
        .filter(|(a, b)| a != b)
        .count();
    differ("colour", colors);
}

/// The shipped settings with the frame plan fixed on `kind` wherever it can serve a frame
/// (tests that set paths side by side).
pub fn fixed_path(kind: PathKind) -> Settings {
    let mut settings = Settings::default();
    settings.plan = PlanMode::Fixed(kind);
    settings
}

/// Whether `plan`'s frame splats.
pub fn splats(plan: &FramePlan) -> bool {
    plan.path.splat().is_some()
}

/// Whether `plan`'s frame stamps the glyphs it shows (the visible-first splat's frames, and
/// the first frame after an upload before them).
pub fn stamps(plan: &FramePlan) -> bool {
    plan.path
        .splat()
        .is_some_and(|s| s.hidden != HiddenLayers::SplatAll)
}

/// Whether `plan`'s frame runs the visible-first splat.
pub fn visible_first(plan: &FramePlan) -> bool {
    plan.path
        .splat()
        .is_some_and(|s| matches!(s.hidden, HiddenLayers::VisibleFirst { .. }))
}
