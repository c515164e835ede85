//! `examples/minimal.rs` runs as written: its own instance and device under the validation
//! layer (it exits non-zero on any message), and the pixels it reports covered are the ones the
//! float64 reference covers for the same three glyphs and camera.

use std::path::PathBuf;
use std::process::Command;

use ellipsoid_splat::{Camera, Ellipsoid, Scene, NO_INSTANCE};
use ellipsoid_splat_reference::render_reference;
use glam::{DQuat, DVec3};

/// The example's binary, which `cargo test` builds beside the test binaries' directory.
fn minimal_binary() -> PathBuf {
    let deps = std::env::current_exe()
        .unwrap()
        .parent()
        .unwrap()
        .to_path_buf();
    deps.parent().unwrap().join("examples").join("minimal")
}

#[test]
fn the_minimal_host_covers_the_reference_pixels_without_validation_messages() {
    let binary = minimal_binary();
    assert!(binary.exists(), "{} was not built", binary.display());
    let output = Command::new(&binary).output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "minimal failed:\n{stdout}\n{stderr}"
    );
    let covered: usize = stdout
        .split("cover ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no coverage line in {stdout:?}"));

    // The example's scene and camera, as it builds them.
    let glyph = |k: f64| {
        Ellipsoid::new(
            DVec3::new(1.2 * k, 0.3 * k, 0.0),
            DVec3::new(0.5, 0.9, 0.3),
            DQuat::from_rotation_z(0.4 * k),
            Some([0.9, 0.5, 0.2]),
        )
        .unwrap()
    };
    let scene = Scene::new(vec![glyph(-1.0), glyph(0.0), glyph(1.0)]);
    let (centre, radius) = scene.bounding_sphere().unwrap();
    let camera = Camera::framing(centre, radius, 320, 240).unwrap();
    let reference = render_reference(&scene, &camera).unwrap();
    let hit = reference.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    let ambiguous_hits = (0..reference.len())
        .filter(|&p| reference.ambiguous[p])
        .count();
    println!("minimal: {covered} covered, reference {hit} ({ambiguous_hits} ambiguous pixels)");
    assert!(hit > 1000, "the scene is in view");
    assert!(
        covered.abs_diff(hit) <= ambiguous_hits,
        "minimal covers {covered} pixels, the reference {hit} (only {ambiguous_hits} are ambiguous)"
    );
}
