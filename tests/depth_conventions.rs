//! Every depth convention a host may use -- reversed or standard Z, finite or infinite far
//! plane, perspective or orthographic -- gives the float64 reference's picture, and a finite
//! far plane hides exactly what lies beyond it.

use ellipsoid_splat::Outputs;
use ellipsoid_splat_reference::testing as common;

use common::{finish_validated, validated_renderer};
use ellipsoid_splat::{Camera, DepthConvention, Ellipsoid, Projection, Scene, NO_INSTANCE};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::compare::{compare, Bounds};
use ellipsoid_splat_reference::reference::render_reference;
use glam::{DQuat, DVec3};

fn conventions(far: f64) -> [DepthConvention; 4] {
    [
        DepthConvention::REVERSED_INFINITE,
        DepthConvention {
            reversed: true,
            far: Some(far),
        },
        DepthConvention::STANDARD_INFINITE,
        DepthConvention {
            reversed: false,
            far: Some(far),
        },
    ]
}

#[test]
fn every_convention_matches_the_reference() {
    let scene = random_cloud(600, 7, 5.0, 0.7);
    let perspective =
        Camera::look_at(DVec3::new(2.0, 3.0, 14.0), DVec3::ZERO, 45.0, 2.0, 200, 150).unwrap();
    let orthographic = Camera {
        projection: Projection::Orthographic { height: 13.0 },
        ..perspective
    };
    let reference_perspective = render_reference(&scene, &perspective).unwrap();
    let reference_orthographic = render_reference(&scene, &orthographic).unwrap();
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    for base in [perspective, orthographic] {
        let reference = if base.is_orthographic() {
            &reference_orthographic
        } else {
            &reference_perspective
        };
        // The far plane lies beyond the whole scene: nothing is clipped.
        for convention in conventions(60.0) {
            let camera = base.with_depth(convention).unwrap();
            let (frame, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
            let stats = compare(&frame, reference).unwrap();
            println!(
                "{convention:?} orthographic {}: {stats}",
                camera.is_orthographic()
            );
            assert!(stats.covered_pixels > 8_000, "{stats}");
            // Standard Z keeps the view depth to about 2^-24 d / n relative in float32 (here
            // d/n <= 10): within the strict bound too.
            let bounds = Bounds::STRICT;
            if let Err(broken) = stats.check(&bounds) {
                panic!("{convention:?}: {broken}\n{stats}");
            }
        }
    }
    finish_validated(renderer);
}

/// A finite far plane through a glyph: pixels whose surface lies beyond it show nothing,
/// pixels nearer show the glyph, as the reference's depths say.
#[test]
fn a_finite_far_plane_hides_what_lies_beyond() {
    let glyph = Ellipsoid::new(
        DVec3::new(0.0, 0.0, -10.0),
        DVec3::new(3.0, 2.0, 4.0),
        DQuat::from_rotation_y(0.6),
        Some([0.8, 0.4, 0.2]),
    )
    .unwrap();
    let scene = Scene::new(vec![glyph]);
    let far = 7.0; // through the glyph's front half (its nearest point is at about 6)
    let base =
        Camera::look_at(DVec3::ZERO, DVec3::new(0.0, 0.0, -1.0), 60.0, 0.5, 160, 120).unwrap();
    let reference = render_reference(&scene, &base).unwrap();
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    for convention in conventions(far).into_iter().filter(|c| c.far.is_some()) {
        let camera = base.with_depth(convention).unwrap();
        let (frame, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
        let (mut shown, mut hidden) = (0, 0);
        for (k, &depth) in reference.depth.iter().enumerate() {
            if !depth.is_finite() || (depth - far).abs() < 1e-4 * far {
                continue; // background, or within rounding of the plane
            }
            let visible = frame.id[k] != NO_INSTANCE;
            if depth < far {
                assert!(
                    visible,
                    "{convention:?}: pixel {k} at depth {depth} is hidden"
                );
                shown += 1;
            } else {
                assert!(!visible, "{convention:?}: pixel {k} at depth {depth} shows");
                hidden += 1;
            }
        }
        assert!(
            shown > 500 && hidden > 500,
            "{shown} shown, {hidden} hidden"
        );
    }
    finish_validated(renderer);
}
