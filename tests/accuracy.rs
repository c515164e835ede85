//! GPU impostors against the float64 reference renderer, under validation.

use ellipsoid_splat_reference::testing as common;

use common::assert_matches_reference;
use ellipsoid_splat::{Camera, Ellipsoid, Projection, Scene};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::compare::Bounds;
use glam::{DQuat, DVec3, EulerRot};

#[test]
fn rotated_ellipsoid_matches_reference() {
    let e = Ellipsoid::new(
        DVec3::new(0.3, -0.2, 0.1),
        DVec3::new(2.0, 0.7, 0.35),
        DQuat::from_euler(EulerRot::XYZ, 0.4, 1.1, -0.7),
        Some([0.8, 0.3, 0.2]),
    )
    .unwrap();
    let scene = Scene::new(vec![e]);
    let camera =
        Camera::look_at(DVec3::new(1.5, 2.0, 6.0), DVec3::ZERO, 45.0, 0.1, 320, 240).unwrap();
    assert_matches_reference(&scene, &camera, &Bounds::STRICT, 5_000);
}

#[test]
fn sphere_matches_reference() {
    let e = Ellipsoid::new(
        DVec3::new(0.0, 0.0, -3.0),
        DVec3::splat(1.0),
        DQuat::IDENTITY,
        None,
    )
    .unwrap();
    let scene = Scene::new(vec![e]);
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.5, 2.0),
        DVec3::new(0.0, 0.0, -3.0),
        30.0,
        0.5,
        256,
        256,
    )
    .unwrap();
    assert_matches_reference(&scene, &camera, &Bounds::STRICT, 5_000);
}

#[test]
fn overlapping_random_cloud_matches_reference() {
    let scene = random_cloud(300, 7, 3.0, 0.8);
    let camera =
        Camera::look_at(DVec3::new(4.0, 3.0, 9.0), DVec3::ZERO, 50.0, 0.5, 320, 240).unwrap();
    let stats = assert_matches_reference(&scene, &camera, &Bounds::STRICT, 20_000);
    assert!(
        stats.id_mismatch == 0,
        "visible instance differs at {} pixels",
        stats.id_mismatch
    );
}

#[test]
fn orthographic_view_matches_reference() {
    let scene = random_cloud(200, 11, 3.0, 0.8);
    let camera = Camera::new(
        DVec3::new(-5.0, 4.0, 8.0),
        DVec3::ZERO,
        DVec3::Y,
        Projection::Orthographic { height: 9.0 },
        0.5,
        300,
        200,
    )
    .unwrap();
    assert_matches_reference(&scene, &camera, &Bounds::STRICT, 10_000);
}

#[test]
fn small_tensor_field_matches_reference() {
    let scene = ellipsoid_splat_loaders::tensor_field(6);
    let camera = Camera::framing(DVec3::ZERO, 5.5, 320, 200).unwrap();
    assert_matches_reference(&scene, &camera, &Bounds::STRICT, 8_000);
}
