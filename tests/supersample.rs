//! Supersampling resolves each pixel to the exact fraction of its K x K sample grid that the
//! float64 reference finds covered.

use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::{Camera, Ellipsoid, Material, Outputs, Scene, Settings};
use ellipsoid_splat_reference::coverage::{compare_coverage, reference_coverage, SamplePattern};
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use glam::{DQuat, DVec3};

/// `--supersample 4` resolves each pixel to the exact fraction of its 16-sample grid that
/// the float64 reference finds covered (unlit white glyphs over the background: see
/// `ellipsoid_splat_reference::coverage`).
#[test]
fn four_by_four_supersampling_resolves_the_exact_coverage_fraction() {
    let k = 4;
    let glyphs = (0..12)
        .map(|n| {
            let t = n as f64;
            Ellipsoid::new(
                DVec3::new(
                    3.0 * (t % 6.0) - 7.5,
                    if n < 6 { 2.0 } else { -2.0 } + 0.3 * (t % 6.0),
                    -0.5 * t,
                ),
                DVec3::new(1.2, 0.35 + 0.1 * t, 0.6),
                DQuat::from_rotation_z(0.5 * t + 0.2) * DQuat::from_rotation_x(0.3 * t),
                Some([1.0, 1.0, 1.0]),
            )
            .unwrap()
        })
        .collect();
    let scene = Scene::new(glyphs);
    let camera =
        Camera::look_at(DVec3::new(0.5, 1.0, 16.0), DVec3::ZERO, 45.0, 1.0, 96, 64).unwrap();
    let big = supersampled_camera(&camera, k).unwrap();
    let mut renderer = validated_renderer();
    renderer.set_settings({
        let mut settings = Settings::default();
        settings.material = {
            let mut material = Material::default();
            material.ambient = 1.0;
            material.diffuse = 0.0;
            material.specular = 0.0;
            material
        };
        settings
    });
    let drawn = renderer.render(&scene, &big, Outputs::ALL).unwrap();
    let out = box_filter(&drawn, k).unwrap();
    let coverage = reference_coverage(&scene, &camera, SamplePattern::Grid(k)).unwrap();
    let stats = compare_coverage(&out, &coverage).unwrap();
    assert_eq!(stats.wrong, 0, "{stats}");
    assert!(stats.max_error < 0.25, "{stats}");
    assert!(
        stats.partly_covered > 200 && stats.compared > 5_000,
        "{stats}"
    );
    finish_validated(renderer);
}
