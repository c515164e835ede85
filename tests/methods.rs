//! Every `bench` method renders under validation, and each is as accurate as its design
//! allows: the exact impostors match the reference, the approximations err where expected.

use ellipsoid_splat::Outputs;
use ellipsoid_splat_reference::testing as common;

use common::{finish_validated, validated_renderer};
use ellipsoid_splat::research::{DrawConfig, Footprint, Method};
use ellipsoid_splat::{Camera, Projection, NO_INSTANCE};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::compare::{compare, Bounds};
use ellipsoid_splat_reference::reference::render_reference;
use glam::DVec3;

#[test]
fn every_method_renders_what_it_promises() {
    let scene = random_cloud(150, 9, 3.0, 0.9);
    let camera = Camera::new(
        DVec3::new(3.0, 2.5, 8.0),
        DVec3::ZERO,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 50.0 },
        0.5,
        240,
        160,
    )
    .unwrap();
    let reference = render_reference(&scene, &camera).unwrap();
    let mut renderer = validated_renderer();
    let mut mesh_mismatch = Vec::new();
    for method in Method::ALL {
        renderer.set_draw_config(method.config());
        renderer.set_settings(method.settings());
        renderer.set_tiled_splat(method.tiled_splat());
        let frame = renderer
            .render(&scene, &camera, Outputs::ALL)
            .expect("render");
        let stats = compare(&frame, &reference).unwrap();
        let name = method.name();
        println!("{name:<22} {stats}");
        assert!(stats.covered_pixels > 10_000);
        match method {
            Method::Impostor
            | Method::ImpostorOrientedRect
            | Method::ImpostorWorldQuad
            | Method::ImpostorAxisRect
            | Method::ImpostorHexagon
            | Method::ImpostorOctagon
            | Method::ImpostorFastNormal
            | Method::ImpostorEstimate
            | Method::ImpostorCompute
            | Method::ImpostorVisibleFirst
            | Method::ImpostorDraw
            | Method::ImpostorFirstFrame
            | Method::ImpostorVisbuffer
            | Method::ImpostorTiled
            // The floors replace only frames that splat, which glyphs this large never do.
            | Method::FloorMemory
            | Method::FloorArithmetic
            | Method::FloorVisible
            // Not in `Method::ALL` (they need ray queries): `traced_path_matches_the_draw` in
            // tests/compute_splat.rs holds them to the draw, bit for bit.
            | Method::ImpostorTraced
            | Method::ImpostorTracedRebuild => {
                assert_eq!(
                    stats.check(&Bounds::STRICT),
                    Ok(()),
                    "{name} is exact: {stats}"
                );
            }
            Method::ImpostorCompact => {
                // Float16 semi-axes and a snorm16 rotation: within the quantisation's error
                // (derived in `common::compact_format_bounds`), far below what a pixel shows.
                let bounds = common::compact_format_bounds(&scene, &camera);
                assert_eq!(stats.check(&bounds), Ok(()), "{name}: {stats}");
            }
            Method::ImpostorTextbook | Method::BoxProxy => {
                // Near and moderately sized: the textbook quadratic still finds every hit.
                assert_eq!(stats.coverage_mismatch, 0, "{name}: {stats}");
                assert!(
                    stats.depth_rel_p99 < 1e-4 && stats.normal_deg_p99 < 0.1,
                    "{name}: {stats}"
                );
            }
            Method::ImpostorFlatDepth => {
                // Same coverage, but the quad's constant depth is measurably wrong.
                assert_eq!(stats.coverage_mismatch, 0, "{name}: {stats}");
                assert!(
                    stats.depth_rel_p99 > 1e-3,
                    "{name} should err in depth: {stats}"
                );
            }
            Method::Mesh(level) => {
                mesh_mismatch.push(stats.coverage_mismatch);
                if level == 4 {
                    assert!(
                        stats.normal_deg_p99 < 1.0 && stats.depth_rel_p99 < 1e-3,
                        "{stats}"
                    );
                }
            }
            Method::FlatFill => {
                // The footprint contains the silhouette: every covered pixel is filled.
                let missed = (0..reference.len())
                    .filter(|&k| reference.id[k] != NO_INSTANCE && frame.id[k] == NO_INSTANCE)
                    .count();
                assert_eq!(missed, 0, "flat-fill leaves covered pixels empty");
            }
        }
    }
    // Finer tessellation, fewer silhouette pixels wrong.
    assert!(
        mesh_mismatch.windows(2).all(|w| w[1] < w[0]),
        "{mesh_mismatch:?}"
    );
    finish_validated(renderer);
}

/// The footprints shade what their geometry promises: an n-gon circumscribing an ellipse
/// covers n tan(pi/n) / pi of its area (4/pi for the oriented rectangle), measured with the
/// exact fragment counter against the reference's silhouette pixels.
#[test]
fn footprints_shade_their_area_ratio() {
    let mut scene = random_cloud(120, 21, 4.0, 0.6);
    for e in &mut scene.ellipsoids {
        e.radii.x *= 3.0; // elongated glyphs at every angle: where axis-aligned boxes waste most
    }
    let camera = Camera::new(
        DVec3::new(2.0, 1.5, 14.0),
        DVec3::ZERO,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 45.0 },
        1.0,
        480,
        320,
    )
    .unwrap();
    let silhouette = render_reference(&scene, &camera)
        .unwrap()
        .silhouette_pixels() as f64;
    let mut renderer = validated_renderer();
    assert!(
        renderer.context().info().fragment_stores_and_atomics,
        "lavapipe supports fragment stores"
    );
    renderer.upload(&scene).unwrap();
    renderer.set_count_fragments(true);
    let mut ratios = Vec::new();
    let triangle = DrawConfig {
        footprint: Footprint::Triangle,
        ..DrawConfig::default()
    };
    renderer.set_draw_config(triangle);
    let (_, timing) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
    let ratio = timing.shaded_fragments.expect("counted") as f64 / silhouette;
    let expected = 3.0 * (std::f64::consts::PI / 3.0).tan() / std::f64::consts::PI;
    assert!(
        (ratio - expected).abs() < 0.03,
        "triangle: {ratio} vs {expected}"
    );
    for (method, expected) in [
        (Method::ImpostorOrientedRect, 4.0 / std::f64::consts::PI),
        (
            Method::ImpostorHexagon,
            6.0 * (std::f64::consts::PI / 6.0).tan() / std::f64::consts::PI,
        ),
        (
            Method::ImpostorOctagon,
            8.0 * (std::f64::consts::PI / 8.0).tan() / std::f64::consts::PI,
        ),
    ] {
        renderer.set_draw_config(method.config());
        let (_, timing) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
        let shaded = timing.shaded_fragments.expect("counted") as f64;
        let ratio = shaded / silhouette;
        println!("{}: {ratio:.4} (geometry {expected:.4})", method.name());
        assert!(
            (ratio - expected).abs() < 0.03,
            "{}: {ratio} vs {expected}",
            method.name()
        );
        ratios.push(ratio);
    }
    renderer.set_draw_config(Method::ImpostorAxisRect.config());
    let (_, timing) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
    let axis_rect = timing.shaded_fragments.unwrap() as f64 / silhouette;
    println!("impostor-axis-rect: {axis_rect:.4}");
    assert!(
        axis_rect > ratios[0] + 0.1,
        "axis-aligned boxes waste more on thin glyphs"
    );
    finish_validated(renderer);
}

/// The quad's constant depth is the glyph's nearest point, so hardware that honours the
/// conservative-depth layout the fragment stages declare (`depth_less` under reversed Z,
/// mirrored to `depth_greater` under standard Z) may reject a hidden glyph's fragments before
/// ray casting them: every depth the exact hit writes must lie at or behind the quad's. Drawn
/// with the quad's depth alone (`impostor-flat-depth`) and with the exact hit, at every pixel
/// where both show the same glyph, in perspective (both depth conventions), with the near
/// plane cutting glyphs, and orthographic.
#[test]
fn every_written_depth_lies_at_or_behind_the_quad() {
    use ellipsoid_splat::DepthConvention;
    let scene = random_cloud(150, 9, 3.0, 0.9);
    let perspective = Camera::new(
        DVec3::new(3.0, 2.5, 8.0),
        DVec3::ZERO,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 50.0 },
        0.5,
        240,
        160,
    )
    .unwrap();
    let cameras = [
        ("reversed", perspective),
        (
            "standard",
            perspective
                .with_depth(DepthConvention::STANDARD_INFINITE)
                .unwrap(),
        ),
        (
            "near-plane cut",
            Camera {
                near: 7.5,
                ..perspective
            },
        ),
        (
            "orthographic",
            Camera {
                projection: Projection::Orthographic { height: 8.0 },
                ..perspective
            },
        ),
    ];
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    for (name, camera) in cameras {
        renderer.set_draw_config(Method::ImpostorFlatDepth.config());
        let quads = renderer.render_uploaded(&camera, Outputs::ALL).unwrap().0;
        renderer.set_draw_config(Method::Impostor.config());
        let exact = renderer.render_uploaded(&camera, Outputs::ALL).unwrap().0;
        let (mut compared, mut behind) = (0, 0);
        for k in 0..exact.len() {
            if exact.id[k] == NO_INSTANCE || exact.id[k] != quads.id[k] {
                continue;
            }
            compared += 1;
            assert!(
                exact.depth[k] >= quads.depth[k],
                "{name}: pixel {k} of glyph {}: written depth {} before the quad's {}",
                exact.id[k],
                exact.depth[k],
                quads.depth[k]
            );
            behind += (exact.depth[k] > quads.depth[k]) as usize;
        }
        assert!(compared > 5_000, "{name}: only {compared} pixels compared");
        assert!(
            behind > compared / 2,
            "{name}: the quads sit on the surfaces"
        );
    }
    finish_validated(renderer);
}
