//! Test support: every GPU test renders on a validated device (core + synchronization
//! validation; any message fails), compares with the float64 reference, and tears down
//! checking for leaks and late validation messages.

use crate::compare::{compare, Bounds, ErrorStats};
use crate::reference::render_reference;
use ellipsoid_splat::ContextOptions;
use ellipsoid_splat::{Camera, Frame, OffscreenRenderer, Outputs, Scene};

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

/// `bounds` widened to what standard Z can hold in perspective: the depth attachment keeps
/// `z = 1 - n/d` (times `f/(f-n)` with a far plane) to float32's 2^-24 near 1, and the view
/// depth read back from it errs by `2^-24 d / n` relative -- twice that for the rounding of
/// `z` itself -- at the farthest surface `d` the scene can show. Reversed Z and orthographic
/// maps keep float32's relative precision: `bounds` unchanged.
pub fn depth_convention_bounds(bounds: Bounds, scene: &Scene, camera: &Camera) -> Bounds {
    if camera.depth.reversed || camera.is_orthographic() {
        return bounds;
    }
    let d_max = scene
        .ellipsoids
        .iter()
        .map(|e| camera.view_depth(e.center) + e.radii.max_element())
        .fold(camera.near, f64::max);
    let floor = 2.0 * 2f64.powi(-24) * d_max / camera.near;
    Bounds {
        depth_rel_p99: bounds.depth_rel_p99.max(floor),
        depth_rel_max: bounds.depth_rel_max.max(floor),
        ..bounds
    }
}
