//! Every footprint the benchmark compares (feature `research`) covers exactly the pixels of
//! the float64 reference, in perspective, near-plane cuts and orthographic views.

use ellipsoid_splat::research::{DrawConfig, Footprint};
use ellipsoid_splat::{Camera, Outputs, Projection};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use ellipsoid_splat_reference::{compare, render_reference, Bounds};
use glam::DVec3;

/// Every footprint polygon must contain every covered pixel centre (same fragment shader, so
/// the same accuracy), in perspective (near-plane cuts included) and orthographic views.
#[test]
fn every_footprint_covers_exactly() {
    let scene = random_cloud(250, 3, 3.0, 0.9);
    let mut thin = random_cloud(60, 4, 3.0, 0.9);
    for e in &mut thin.ellipsoids {
        e.radii.y *= 0.02; // needles and blades at every angle
    }
    let perspective_cam =
        Camera::look_at(DVec3::new(3.0, 2.5, 7.0), DVec3::ZERO, 55.0, 0.5, 256, 160).unwrap();
    let mut cut_cam = perspective_cam;
    cut_cam.near = 6.5;
    let mut ortho_cam = perspective_cam;
    ortho_cam.projection = Projection::Orthographic { height: 8.0 };
    let mut renderer = validated_renderer();
    for footprint in [
        Footprint::Triangle,
        Footprint::OrientedRect,
        Footprint::Hexagon,
        Footprint::Octagon,
        Footprint::AxisRect,
        Footprint::WorldQuad,
    ] {
        renderer.set_draw_config(DrawConfig {
            footprint,
            ..DrawConfig::default()
        });
        for (name, scene, camera) in [
            ("cloud", &scene, &perspective_cam),
            ("thin", &thin, &perspective_cam),
            ("cut", &scene, &cut_cam),
            ("ortho", &scene, &ortho_cam),
        ] {
            let frame = renderer
                .render(scene, camera, Outputs::ALL)
                .expect("render");
            let stats = compare(&frame, &render_reference(scene, camera).unwrap()).unwrap();
            println!("{footprint:?} {name}: {stats}");
            assert!(
                stats.covered_pixels > 1_000,
                "{footprint:?} {name}: too little coverage"
            );
            assert!(
                stats.check(&Bounds::STRICT).is_ok(),
                "{footprint:?} {name}: {:?}\n{stats}",
                stats.check(&Bounds::STRICT)
            );
            assert_eq!(stats.coverage_mismatch, 0, "{footprint:?} {name}: {stats}");
        }
    }
    finish_validated(renderer);
}
