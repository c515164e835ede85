//! `OffscreenRenderer::update` replaces part of the uploaded scene: a scene updated in place
//! (two ranges, within its uploaded bounds and largest radius) draws exactly what uploading
//! the updated scene whole draws -- colour, depth, normal and ID bit for bit -- and a range
//! past the uploaded count is refused without changing the picture.

use ellipsoid_splat::{Camera, Ellipsoid, Error, Frame, Outputs, Scene};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use glam::{DQuat, DVec3};

/// Every output as bits, so that two frames compare exactly (+inf and -0.0 included).
fn bits(frame: &Frame) -> (Vec<[u8; 4]>, Vec<u32>, Vec<u32>, Vec<u32>) {
    (
        frame.color.clone(),
        frame.depth.iter().map(|v| v.to_bits()).collect(),
        frame.normal.iter().flatten().map(|v| v.to_bits()).collect(),
        frame.id.clone(),
    )
}

#[test]
fn a_partly_updated_scene_draws_what_uploading_it_whole_draws() {
    let mut ellipsoids = random_cloud(400, 5, 3.0, 0.4).ellipsoids;
    // Two large glyphs at opposite corners hold the bounds and the largest radius, so the
    // updates below (inside the cloud, smaller) keep the scene's origin and radius scale.
    for corner in [-4.5, 4.5] {
        ellipsoids.push(
            Ellipsoid::new(
                DVec3::splat(corner),
                DVec3::splat(0.9),
                DQuat::IDENTITY,
                None,
            )
            .expect("corner glyph"),
        );
    }
    let before = Scene::new(ellipsoids.clone());
    let changed = |e: &Ellipsoid, k: usize| {
        let turn = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.3 + k as f64);
        Ellipsoid::new(
            e.center * 0.8 + DVec3::new(0.1, -0.2, 0.05),
            e.radii * 0.7,
            turn * e.rotation,
            Some([0.9, (k % 7) as f32 / 7.0, 0.2]),
        )
        .expect("updated glyph")
    };
    let mut updated = ellipsoids.clone();
    for k in (100..180).chain(250..251) {
        updated[k] = changed(&ellipsoids[k], k);
    }
    let after = Scene::new(updated.clone());
    assert_eq!(
        before.bounds(),
        after.bounds(),
        "the updates keep the bounds"
    );

    let camera = Camera::look_at(DVec3::new(1.0, 2.0, 11.0), DVec3::ZERO, 50.0, 0.5, 160, 120)
        .expect("camera");
    let mut renderer = validated_renderer();
    renderer.upload(&before).expect("upload");
    let (old, _) = renderer
        .render_uploaded(&camera, Outputs::ALL)
        .expect("frame before the update");
    renderer
        .update(100, &updated[100..180])
        .expect("update 100..180");
    renderer
        .update(250, &updated[250..251])
        .expect("update 250");
    // Past the end: refused, nothing changes.
    let refused = renderer.update(401, &updated[100..102]);
    assert!(matches!(refused, Err(Error::Invalid { .. })), "{refused:?}");
    renderer.update(10, &[]).expect("an empty update");
    let (partial, _) = renderer
        .render_uploaded(&camera, Outputs::ALL)
        .expect("frame after the update");
    renderer
        .upload(&after)
        .expect("upload of the updated scene");
    let (whole, _) = renderer
        .render_uploaded(&camera, Outputs::ALL)
        .expect("frame of the whole updated scene");
    finish_validated(renderer);

    let covered = whole.id.iter().filter(|&&id| id != u32::MAX).count();
    assert!(covered > 4_000, "the scene covers only {covered} pixels");
    let moved = whole
        .id
        .iter()
        .filter(|&&id| (100..180).contains(&id) || id == 250)
        .count();
    assert!(moved > 300, "the updated glyphs cover only {moved} pixels");
    assert!(bits(&old) != bits(&whole), "the update changes the picture");
    let (p, w) = (bits(&partial), bits(&whole));
    assert!(p.0 == w.0, "colour differs");
    assert!(p.1 == w.1, "depth differs");
    assert!(p.2 == w.2, "normal differs");
    assert!(p.3 == w.3, "ID differs");
}
