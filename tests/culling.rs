//! The culling pre-pass skips work without changing a single pixel: frames with and without
//! it are identical, bit for bit, in colour, depth, normal and instance ID.

mod common;

use common::validated_renderer;
use ellipsoid_splat::renderer::Culling;
use ellipsoid_splat::scene::random_cloud;
use ellipsoid_splat::{Camera, Projection};
use glam::DVec3;

#[test]
fn culling_changes_no_pixel() {
    // A field around the eye (most of it off screen, some behind), plus far glyphs too small
    // to reach a pixel centre.
    let mut scene = random_cloud(3_000, 17, 20.0, 0.8);
    let far = random_cloud(2_000, 18, 30.0, 0.004);
    scene
        .ellipsoids
        .extend(far.ellipsoids.into_iter().map(|mut e| {
            e.center.z -= 400.0;
            e
        }));
    let perspective = Camera::new(
        DVec3::new(1.0, 0.5, 2.0),
        DVec3::new(14.0, 12.0, -30.0),
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 60.0 },
        0.05,
        160,
        120,
    )
    .unwrap();
    let mut orthographic = perspective;
    orthographic.projection = Projection::Orthographic { height: 12.0 };
    let mut renderer = validated_renderer();
    for camera in [perspective, orthographic] {
        renderer.set_culling(Culling::OFF);
        let plain = renderer
            .render(&scene, &camera)
            .expect("render without culling");
        for culling in [
            Culling::ON,
            Culling {
                frustum: true,
                pixel_centres: false,
            },
            Culling {
                frustum: false,
                pixel_centres: true,
            },
        ] {
            renderer.set_culling(culling);
            let culled = renderer
                .render(&scene, &camera)
                .expect("render with culling");
            assert!(plain
                .id
                .iter()
                .any(|&id| id != ellipsoid_splat::NO_INSTANCE));
            assert_eq!(plain.id, culled.id, "{culling:?}: instance IDs differ");
            assert_eq!(plain.color, culled.color, "{culling:?}: colours differ");
            assert_eq!(plain.depth, culled.depth, "{culling:?}: depths differ");
            assert_eq!(plain.normal, culled.normal, "{culling:?}: normals differ");
        }
    }
    renderer
        .context()
        .check_validation()
        .expect("no validation messages");
    renderer.finish().expect("clean shutdown");
}
