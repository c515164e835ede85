//! The shader variant chosen from the scene computes the same bits as the general shaders on
//! lavapipe (elsewhere: the same glyphs, within the reference's bounds): the cap-free fragment
//! stage when nothing reaches the near plane. (The sphere path saved under 5 % on both
//! lavapipes and was removed; spheres stay in the scenes.)

use ellipsoid_splat::Outputs;
use ellipsoid_splat_reference::testing as common;

use common::{assert_frames_agree, finish_validated, validated_renderer, Agreement, Seen};
use ellipsoid_splat::Scene;
use ellipsoid_splat::{Camera, Projection};
use ellipsoid_splat::{InstanceFormat, OffscreenRenderer};
use ellipsoid_splat_loaders::random_cloud;
use glam::{DQuat, DVec3};

/// Renders with the variant off and on; returns whether the draw took it.
fn assert_same_frames(renderer: &mut OffscreenRenderer, scene: &Scene, camera: &Camera) -> bool {
    renderer.upload(scene).expect("upload");
    renderer.set_settings({
        let mut settings = *renderer.settings();
        settings.cap_free_path = false;
        settings
    });
    let (general, _) = renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("render");
    assert!(general
        .id
        .iter()
        .any(|&id| id != ellipsoid_splat::NO_INSTANCE));
    renderer.set_settings({
        let mut settings = *renderer.settings();
        settings.cap_free_path = true;
        settings
    });
    let (variant, _) = renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("render");
    let seen = Seen {
        scene,
        camera,
        format: InstanceFormat::Full,
    };
    assert_frames_agree(
        Agreement::of(renderer),
        "variants",
        &general,
        &variant,
        seen,
    );
    renderer.plan(camera).expect("plan").no_caps
}

#[test]
fn variants_change_no_pixel() {
    // Spheres, some stored with a rotation, and ellipsoids in front of the camera and, in the
    // second view, around and behind the near plane.
    let mut spheres = random_cloud(2_000, 41, 6.0, 0.6);
    for (k, e) in spheres.ellipsoids.iter_mut().enumerate() {
        e.radii = DVec3::splat(e.radii.x);
        if k % 2 == 0 {
            e.rotation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        }
    }
    let ellipsoids = random_cloud(2_000, 42, 6.0, 0.6);
    let outside = Camera::look_at(DVec3::new(3.0, 4.0, 20.0), DVec3::ZERO, 45.0, 1.0, 160, 120)
        .expect("camera");
    let inside = Camera::look_at(
        DVec3::new(0.5, 0.2, 1.0),
        DVec3::new(-4.0, -3.0, -6.0),
        70.0,
        0.05,
        160,
        120,
    )
    .expect("camera");
    let mut orthographic = outside;
    orthographic.projection = Projection::Orthographic { height: 14.0 };
    let mut renderer = validated_renderer();
    for scene in [&spheres, &ellipsoids] {
        for (camera, clear_of_near_plane) in
            [(&outside, true), (&inside, false), (&orthographic, true)]
        {
            let taken = assert_same_frames(&mut renderer, scene, camera);
            assert_eq!(taken, clear_of_near_plane, "variant chosen");
        }
    }
    finish_validated(renderer);
}
