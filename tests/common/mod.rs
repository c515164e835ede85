//! Test harness: every GPU test renders on a validated device (core + synchronization
//! validation; any message fails), compares with the float64 reference, and tears down
//! checking for leaks and late validation messages.

#![allow(dead_code)]

use ellipsoid_splat::compare::{compare, Bounds, ErrorStats};
use ellipsoid_splat::gpu::ContextOptions;
use ellipsoid_splat::reference::render_reference;
use ellipsoid_splat::{Camera, Frame, OffscreenRenderer, Scene};

/// A renderer on a device with validation and synchronization validation on.
pub fn validated_renderer() -> OffscreenRenderer {
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
    let frame = renderer.render(scene, camera).expect("GPU render");
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
