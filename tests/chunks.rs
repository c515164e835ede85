//! Scenes larger than one storage-buffer binding are drawn in chunks, each with its own
//! descriptor set, pre-pass and draw. Chunking changes no pixel: here the chunk size is
//! lowered so a few thousand glyphs make many chunks, and every output is compared bit for
//! bit with the one-chunk rendering.

use ellipsoid_splat::Outputs;
use ellipsoid_splat_reference::testing as common;

use common::{finish_validated, validated_renderer};
use ellipsoid_splat::Scene;
use ellipsoid_splat::{Camera, NO_INSTANCE};
use ellipsoid_splat_loaders::random_cloud;
use glam::DVec3;

fn assert_chunking_changes_nothing(scene: &Scene, camera: &Camera, expect_setup_once: bool) {
    let mut renderer = validated_renderer();
    renderer.upload(scene).unwrap();
    assert_eq!(
        renderer.plan(camera).expect("plan").setup_once(),
        expect_setup_once
    );
    let (whole, _) = renderer.render_uploaded(camera, Outputs::ALL).unwrap();
    renderer.set_settings({
        let mut settings = *renderer.settings();
        settings.max_chunk_instances = 256;
        settings
    });
    // The chunk size takes effect at the next upload: until then the scene is drawn as
    // uploaded, with the buffers and descriptor sets cut for it.
    let (before_upload, _) = renderer.render_uploaded(camera, Outputs::ALL).unwrap();
    assert_eq!(
        whole, before_upload,
        "a new chunk size changed the frame before the upload"
    );
    renderer.upload(scene).unwrap();
    let (chunked, _) = renderer.render_uploaded(camera, Outputs::ALL).unwrap();
    let shown = whole.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    let high = whole
        .id
        .iter()
        .filter(|&&id| id != NO_INSTANCE && id >= 256)
        .count();
    assert!(
        shown > 2_000 && high > 1_000,
        "{shown} pixels shown, {high} from later chunks"
    );
    assert_eq!(whole.id, chunked.id, "instance IDs differ");
    assert_eq!(whole.color, chunked.color, "colours differ");
    assert_eq!(whole.depth, chunked.depth, "depths differ");
    assert_eq!(whole.normal, chunked.normal, "normals differ");
    finish_validated(renderer);
}

#[test]
fn chunks_draw_the_same_picture() {
    // 3,000 glyphs in 12 chunks of 256, with every culling on.
    let scene = random_cloud(3_000, 11, 8.0, 0.5);
    let camera =
        Camera::look_at(DVec3::new(4.0, 5.0, 22.0), DVec3::ZERO, 45.0, 1.0, 200, 150).unwrap();
    assert_chunking_changes_nothing(&scene, &camera, false);
}

#[test]
fn chunks_draw_the_same_picture_with_the_set_up_in_the_pre_pass() {
    // Small glyphs on screen: the pre-pass computes the set-up records, sliced per chunk.
    let scene = random_cloud(3_000, 12, 8.0, 0.12);
    let camera =
        Camera::look_at(DVec3::new(4.0, 5.0, 40.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    assert_chunking_changes_nothing(&scene, &camera, true);
}

/// The compact 32-byte format: the same scene within the quantisation's error of the
/// float64 reference, and chunked exactly like the full format.
#[test]
fn compact_instances_stay_within_their_quantisation_error() {
    use ellipsoid_splat::InstanceFormat;
    use ellipsoid_splat_reference::compare::compare;
    use ellipsoid_splat_reference::reference::render_reference;
    let scene = random_cloud(2_000, 13, 8.0, 0.6);
    let camera =
        Camera::look_at(DVec3::new(4.0, 5.0, 22.0), DVec3::ZERO, 45.0, 1.0, 240, 180).unwrap();
    let reference = render_reference(&scene, &camera).unwrap();
    let mut renderer = validated_renderer();
    renderer.set_settings({
        let mut settings = *renderer.settings();
        settings.instance_format = InstanceFormat::Compact;
        settings
    });
    renderer.upload(&scene).unwrap();
    let (compact, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
    let stats = compare(&compact, &reference).unwrap();
    println!("compact: {stats}");
    // The quantisation's error, derived in `common::compact_format_bounds`.
    let bounds = common::compact_format_bounds(&scene, &camera);
    if let Err(broken) = stats.check(&bounds) {
        panic!("compact format beyond its quantisation error: {broken}\n{stats}");
    }
    renderer.set_settings({
        let mut settings = *renderer.settings();
        settings.max_chunk_instances = 256;
        settings
    });
    renderer.upload(&scene).unwrap();
    let (chunked, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
    assert_eq!(compact.id, chunked.id);
    assert_eq!(compact.depth, chunked.depth);
    finish_validated(renderer);
}
