//! The offscreen renderer draws and reads back only the outputs asked for: each output of a
//! partial frame, drawn by a renderer that never made the other targets, equals the same
//! output of a full frame bit for bit, and the others are empty.

use ellipsoid_splat::{Camera, Outputs};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::testing::{finish_validated, validated_renderer};
use glam::DVec3;

#[test]
fn partial_outputs_equal_the_full_frame_and_leave_the_rest_empty() {
    let scene = random_cloud(400, 3, 3.0, 0.6);
    let camera = Camera::look_at(DVec3::new(0.0, 2.0, 9.0), DVec3::ZERO, 50.0, 0.1, 200, 150)
        .expect("camera");
    let full = {
        let mut renderer = validated_renderer();
        let frame = renderer
            .render(&scene, &camera, Outputs::ALL)
            .expect("full frame");
        finish_validated(renderer);
        frame
    };
    let covered = full.id.iter().filter(|&&id| id != u32::MAX).count();
    assert!(covered > 5_000, "the scene covers only {covered} pixels");
    let only = |color, depth, normal, id| {
        let mut outputs = Outputs::default();
        outputs.color = color;
        outputs.depth = depth;
        outputs.normal = normal;
        outputs.id = id;
        outputs
    };
    for outputs in [
        only(true, false, false, false),
        only(false, true, false, false),
        only(false, false, true, false),
        only(false, false, false, true),
        Outputs::COLOR_DEPTH,
    ] {
        // A new renderer each time: its targets are only those `outputs` need.
        let mut renderer = validated_renderer();
        let frame = renderer
            .render(&scene, &camera, outputs)
            .expect("partial frame");
        finish_validated(renderer);
        assert_eq!((frame.width, frame.height), (full.width, full.height));
        let check = |asked: bool, same: bool, empty: bool, what: &str| {
            if asked {
                assert!(same, "{outputs:?}: {what} differs from the full frame");
            } else {
                assert!(
                    empty,
                    "{outputs:?}: {what} was read back without being asked for"
                );
            }
        };
        check(
            outputs.color,
            frame.color == full.color,
            frame.color.is_empty(),
            "colour",
        );
        let depth_bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        check(
            outputs.depth,
            depth_bits(&frame.depth) == depth_bits(&full.depth),
            frame.depth.is_empty(),
            "depth",
        );
        let normal_bits =
            |n: &[[f32; 3]]| n.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>();
        check(
            outputs.normal,
            normal_bits(&frame.normal) == normal_bits(&full.normal),
            frame.normal.is_empty(),
            "normal",
        );
        check(outputs.id, frame.id == full.id, frame.id.is_empty(), "ID");
    }
}
