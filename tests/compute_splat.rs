//! The compute splat draws exactly what the instanced draw draws: on scenes of glyphs of a
//! few pixels and of tens to hundreds of pixels many layers deep, colour, depth, normal and
//! instance ID are compared bit for bit with the draw (on lavapipe; on a driver that rounds
//! the stages differently: the same IDs, both within the reference's bounds), in perspective
//! and orthographic views, with the near plane cutting glyphs, in standard and reversed
//! depth, with compact instances, and where glyphs tie exactly in depth (the lower instance
//! must win, as in the draw). Every case is drawn twice: the first splatted frame of a scene
//! splats every glyph and stamps those it shows, the next, with the same camera, is the
//! visible-first splat (those first, then the rest its hits do not hide); and a camera
//! stopping along an orbit matches the draw at every frame.

use ellipsoid_splat::internals::SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL;
#[cfg(feature = "research")]
use ellipsoid_splat::Culling;
#[cfg(feature = "research")]
use ellipsoid_splat::PlanReason;
use ellipsoid_splat::{
    Camera, DepthConvention, Ellipsoid, InstanceFormat, OffscreenRenderer, Outputs, Projection,
    Scene, Settings, NO_INSTANCE,
};
use ellipsoid_splat::{PathKind, PlanMode};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::testing::{
    assert_frames_agree, finish_validated, splats, stamps, validated_renderer, visible_first,
    Agreement, Seen,
};
use glam::{DQuat, DVec3};

/// Renders `scene` with and without the compute splat and asserts the frames agree
/// and that the splat really ran, its resolve reading the set-up the splat stored.
fn assert_splat_matches_draw(
    renderer: &mut OffscreenRenderer,
    name: &str,
    scene: &Scene,
    camera: &Camera,
    format: InstanceFormat,
) {
    assert_splat_matches_draw_set_up(renderer, name, scene, camera, (format, true));
}

/// As `assert_splat_matches_draw`, the splat setting glyphs up once (its resolve reads their
/// stored set-up) or not (the resolve sets each pixel's glyph up again).
fn assert_splat_matches_draw_set_up(
    renderer: &mut OffscreenRenderer,
    name: &str,
    scene: &Scene,
    camera: &Camera,
    (format, setup_once): (InstanceFormat, bool),
) {
    // Visible first however deep the scene lies, to check it on every case.
    let settings = |compute_splat| {
        let mut settings = Settings::default();
        settings.plan = PlanMode::Fixed(if compute_splat {
            PathKind::VisibleFirst
        } else {
            PathKind::Draw
        });
        settings.instance_format = format;
        // The draw sets nothing up once: its records would be the splat's very bytes.
        settings.setup_once = setup_once && compute_splat;
        settings
    };
    renderer.set_settings(settings(false));
    renderer.upload(scene).expect("upload");
    let plan = renderer.plan(camera).expect("plan");
    assert!(!splats(&plan), "{name}: {plan:?}");
    let drawn = renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("draw")
        .0;
    renderer.set_settings(settings(true));
    renderer.upload(scene).expect("upload");
    // A frame of a camera a little aside first: its set-up records are wrong for `camera`, so
    // a frame that did not store its own would show them; the second upload forgets its
    // stamps.
    renderer
        .render_uploaded(&aside(camera), Outputs::COLOR_DEPTH)
        .expect("splat aside");
    renderer.upload(scene).expect("upload");
    let plan = renderer.plan(camera).expect("plan");
    assert!(splats(&plan), "{name}: the plan does not splat: {plan:?}");
    assert!(
        !visible_first(&plan),
        "{name}: a new scene has no stamps yet"
    );
    // Set up once where asked and the glyphs are few enough for the image (design §5.6).
    let image_px = camera.width as f64 * camera.height as f64;
    let sparse = scene.ellipsoids.len() as f64 <= SPLAT_SETUP_ONCE_MAX_GLYPHS_PER_PIXEL * image_px;
    assert_eq!(
        plan.path.splat().map(|s| s.setup_once),
        Some(setup_once && sparse),
        "{name}: {plan:?}"
    );
    let splatted = renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("splat")
        .0;
    let shown = drawn.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    assert!(shown > 500, "{name}: only {shown} pixels show a glyph");
    let agreement = Agreement::of(renderer);
    let seen = Seen {
        scene,
        camera,
        format,
    };
    assert_frames_agree(agreement, name, &drawn, &splatted, seen);
    // The next frame splats first what this one showed.
    let plan = renderer.plan(camera).expect("plan");
    assert!(visible_first(&plan), "{name}: second frame: {plan:?}");
    let second = renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("visible-first splat")
        .0;
    assert_frames_agree(
        agreement,
        &format!("{name}, visible first"),
        &drawn,
        &second,
        seen,
    );
}

/// `camera` with its eye moved aside by a twentieth of its distance to the target.
fn aside(camera: &Camera) -> Camera {
    let back = camera.eye - camera.target;
    let side = back.cross(camera.up).normalize() * back.length() * 0.05;
    Camera {
        eye: camera.eye + side,
        ..*camera
    }
}

/// Asserts that some glyph of `scene` reaches in front of `camera`'s near plane (so the
/// frame has caps to draw).
fn assert_reaches_near_plane(scene: &Scene, camera: &Camera) {
    assert!(
        scene
            .ellipsoids
            .iter()
            .any(|e| camera.view_depth(e.center) < camera.near + e.radii.max_element()),
        "no glyph reaches the near plane"
    );
}

/// 18,000 glyphs of one or two pixels, 320x240 (few enough for the splat to set them up once).
fn tiny_glyphs() -> (Scene, Camera) {
    let camera =
        Camera::look_at(DVec3::new(2.0, 3.0, 25.0), DVec3::ZERO, 45.0, 1.0, 320, 240).unwrap();
    (random_cloud(18_000, 21, 10.0, 0.06), camera)
}

#[test]
fn splat_matches_the_draw() {
    let mut renderer = validated_renderer();
    let (scene, camera) = tiny_glyphs();
    let full = InstanceFormat::Full;
    assert_splat_matches_draw(&mut renderer, "perspective", &scene, &camera, full);
    let ortho = Camera {
        projection: Projection::Orthographic { height: 22.0 },
        ..camera
    };
    assert_splat_matches_draw(&mut renderer, "orthographic", &scene, &ortho, full);
    for (label, depth) in [
        ("standard infinite", DepthConvention::STANDARD_INFINITE),
        (
            "standard finite",
            DepthConvention {
                reversed: false,
                far: Some(40.0),
            },
        ),
        (
            "reversed finite",
            DepthConvention {
                reversed: true,
                far: Some(40.0),
            },
        ),
    ] {
        let camera = camera.with_depth(depth).expect("depth convention");
        assert_splat_matches_draw(&mut renderer, label, &scene, &camera, full);
    }
    let compact = InstanceFormat::Compact;
    assert_splat_matches_draw(&mut renderer, "compact", &scene, &camera, compact);
    // The near plane inside the cloud cuts glyphs (caps), none of which reaches the eye plane.
    let inside = Camera::look_at(DVec3::new(0.3, 0.2, 6.0), DVec3::ZERO, 60.0, 4.5, 320, 240)
        .expect("camera");
    let small = random_cloud(18_000, 22, 3.0, 0.02);
    assert_reaches_near_plane(&small, &inside);
    assert_splat_matches_draw(&mut renderer, "near-plane cut", &small, &inside, full);
    finish_validated(renderer);
}

/// With set-up once off, the resolve sets each pixel's glyph up again: the same picture.
#[test]
fn splat_without_set_up_once_matches_the_draw() {
    let mut renderer = validated_renderer();
    let (scene, camera) = tiny_glyphs();
    let not_once = (InstanceFormat::Full, false);
    assert_splat_matches_draw_set_up(&mut renderer, "perspective", &scene, &camera, not_once);
    let ortho = Camera {
        projection: Projection::Orthographic { height: 22.0 },
        ..camera
    };
    assert_splat_matches_draw_set_up(&mut renderer, "orthographic", &scene, &ortho, not_once);
    finish_validated(renderer);
}

/// Glyphs of tens to hundreds of pixels, many layers deep, in an image whose sides are no
/// multiple of the resolve tile (its last row and column of tiles are partial), too large for
/// the draw's set-up once: the splat still matches the draw (bit for bit on lavapipe).
#[test]
fn medium_glyphs_many_layers_deep_match_the_draw() {
    let mut renderer = validated_renderer();
    let camera = Camera::look_at(
        DVec3::new(3.0, -2.0, 24.0),
        DVec3::ZERO,
        45.0,
        1.0,
        333,
        250,
    )
    .unwrap();
    let scene = random_cloud(6_000, 23, 10.0, 0.5);
    renderer.upload(&scene).expect("upload");
    let plan = renderer.plan(&camera).expect("plan");
    let area = plan.mean_area_px.expect("glyphs on screen");
    assert!(area > 50.0, "mean glyph area {area} px");
    assert!(!plan.setup_once(), "{plan:?}");
    let full = InstanceFormat::Full;
    assert_splat_matches_draw(&mut renderer, "medium perspective", &scene, &camera, full);
    let ortho = Camera {
        projection: Projection::Orthographic { height: 20.0 },
        ..camera
    };
    assert_splat_matches_draw(&mut renderer, "medium orthographic", &scene, &ortho, full);
    let standard = camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention");
    assert_splat_matches_draw(
        &mut renderer,
        "medium standard depth",
        &scene,
        &standard,
        full,
    );
    // The near plane cuts the nearest glyphs.
    let inside = Camera::look_at(DVec3::new(0.5, 0.2, 7.0), DVec3::ZERO, 60.0, 5.5, 333, 250)
        .expect("camera");
    let cut = random_cloud(6_000, 24, 5.0, 0.25);
    assert_reaches_near_plane(&cut, &inside);
    assert_splat_matches_draw(&mut renderer, "medium near-plane cut", &cut, &inside, full);
    finish_validated(renderer);
}

/// Tiny glyphs with a few of thousands of pixels among them and two that reach the eye plane:
/// the splat leaves those to the draw, which depth-tests them against the resolve, and the
/// frame matches the draw (bit for bit on lavapipe).
#[test]
fn glyphs_too_large_to_splat_are_drawn_in_the_same_frame() {
    let (scene, camera) = tiny_glyphs();
    let mut glyphs = scene.ellipsoids;
    // Glyphs of about 100 x 70 px (boxes beyond the splat's 4,096 pixel centres) at
    // instances 100, 200, ..., overlapping small ones in front and behind.
    for k in 1..=12 {
        let t = k as f64;
        glyphs[100 * k] = Ellipsoid::new(
            DVec3::new(
                7.0 * (t * 0.9).sin(),
                5.0 * (t * 1.7).cos(),
                4.0 * (t * 0.6).sin(),
            ),
            DVec3::new(5.0, 3.5, 2.0),
            DQuat::from_rotation_z(t),
            Some([0.9, 0.3, 0.2]),
        )
        .expect("large glyph");
    }
    // Beside the eye and crossing its plane: shown at the image's edge.
    let eye = DVec3::new(2.0, 3.0, 25.0);
    let towards = (DVec3::ZERO - eye).normalize();
    let side = towards.cross(DVec3::Y).normalize();
    for (k, s) in [(5_000, 1.0), (5_001, -1.0)] {
        glyphs[k] = Ellipsoid::new(
            eye + side * (2.0 * s) + towards * 0.5,
            DVec3::new(1.8, 6.0, 3.0),
            DQuat::IDENTITY,
            Some([0.2, 0.4, 0.9]),
        )
        .expect("eye-plane glyph");
    }
    let scene = Scene::new(glyphs);
    let mut renderer = validated_renderer();
    let full = InstanceFormat::Full;
    assert_splat_matches_draw(&mut renderer, "mixed sizes", &scene, &camera, full);
    let standard = camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention");
    assert_splat_matches_draw(
        &mut renderer,
        "mixed sizes, standard",
        &scene,
        &standard,
        full,
    );
    // The eye-plane glyphs and most large ones really show.
    let frame = renderer
        .render(&scene, &camera, Outputs::ALL)
        .expect("render");
    let pixels = |id: u32| frame.id.iter().filter(|&&shown| shown == id).count();
    for id in [5_000, 5_001] {
        assert!(
            pixels(id) > 200,
            "glyph {id} shows on {} pixels",
            pixels(id)
        );
    }
    let large = (1..=12).filter(|k| pixels(100 * k) > 200).count();
    assert!(large >= 6, "only {large} of 12 large glyphs show");
    // And they took the draw: the splatted frame shades at least the drawn footprints of the
    // 14 (counted in a frame that draws them alone) plus, in the resolve, every pixel a tiny
    // glyph shows; had the splat taken the large ones, it would shade at most one fragment
    // per pixel besides the eye-plane glyphs' footprints.
    #[cfg(feature = "research")]
    {
        let overflow: Vec<u32> = (1..=12).map(|k| 100 * k).chain([5_000, 5_001]).collect();
        let count = |renderer: &mut OffscreenRenderer, scene: &Scene, splat: bool| {
            renderer.set_settings({
                let mut settings = Settings::default();
                settings.plan = PlanMode::Fixed(if splat {
                    PathKind::Splat
                } else {
                    PathKind::Draw
                });
                settings
            });
            renderer.upload(scene).expect("upload");
            renderer.set_count_fragments(true);
            let (frame, timing) = renderer
                .render_uploaded(&camera, Outputs::ALL)
                .expect("counted render");
            renderer.set_count_fragments(false);
            (frame, timing.shaded_fragments.expect("fragment count"))
        };
        let alone = Scene::new(
            overflow
                .iter()
                .map(|&k| scene.ellipsoids[k as usize])
                .collect(),
        );
        let (_, drawn_alone) = count(&mut renderer, &alone, false);
        let (frame, shaded) = count(&mut renderer, &scene, true);
        let tiny_shown = frame
            .id
            .iter()
            .filter(|&&id| id != NO_INSTANCE && !overflow.contains(&id))
            .count() as u64;
        assert!(
            shaded >= drawn_alone + tiny_shown,
            "{shaded} fragments shaded, fewer than the {drawn_alone} of the large glyphs' \
             footprints and {tiny_shown} tiny glyphs' pixels: the splat took large glyphs"
        );
    }
    finish_validated(renderer);
}

#[test]
fn exact_depth_ties_go_to_the_lower_instance_as_in_the_draw() {
    // Every glyph twice, the copy later in instance order and in another colour: both have
    // the very same depth at every pixel, and the draw shows the first.
    let (scene, camera) = tiny_glyphs();
    let mut tied = Vec::with_capacity(2 * scene.len());
    for e in scene.ellipsoids.iter().take(10_000) {
        tied.push(*e);
        tied.push(Ellipsoid {
            color: [0.1, 0.9, 0.1],
            ..*e
        });
    }
    let tied = Scene::new(tied);
    let mut renderer = validated_renderer();
    assert_splat_matches_draw(&mut renderer, "ties", &tied, &camera, InstanceFormat::Full);
    let standard = camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention");
    assert_splat_matches_draw(
        &mut renderer,
        "ties, standard depth",
        &tied,
        &standard,
        InstanceFormat::Full,
    );
    // The copies never show, drawn or splatted, in either convention: every visible ID is
    // even (the reference calls tied pixels ambiguous, so this is the ties' own check).
    for (label, camera) in [("reversed", &camera), ("standard", &standard)] {
        for compute_splat in [false, true] {
            renderer.set_settings({
                let mut settings = Settings::default();
                settings.plan = PlanMode::Fixed(if compute_splat {
                    PathKind::Splat
                } else {
                    PathKind::Draw
                });
                settings
            });
            let frame = renderer
                .render(&tied, camera, Outputs::ALL)
                .expect("render");
            let shown = frame.id.iter().filter(|&&id| id != NO_INSTANCE).count();
            let odd = frame
                .id
                .iter()
                .filter(|&&id| id != NO_INSTANCE && id % 2 == 1)
                .count();
            assert!(shown > 500, "{label}: only {shown} pixels shown");
            assert_eq!(
                odd, 0,
                "{label}, splat {compute_splat}: {odd} pixels show the later copy of a tied pair"
            );
        }
    }
    finish_validated(renderer);
}

/// A camera stopping at points of an orbit around a scene of glyphs many layers deep, with a
/// drawn frame, a new scene uploaded and the depth convention changed on the way: the first
/// frame after an upload splats everything and stamps what it shows, every later one is the
/// visible-first splat from the last stamps (the camera moved or not); all match the draw of
/// the same camera (bit for bit on lavapipe).
#[test]
fn visible_first_frames_match_the_draw_at_each_stop_of_an_orbit() {
    let mut scene = random_cloud(6_000, 25, 10.0, 0.5);
    let splat = {
        let mut settings = Settings::default();
        settings.plan = PlanMode::Fixed(PathKind::VisibleFirst);
        settings
    };
    let mut splatted = validated_renderer();
    splatted.set_settings(splat);
    splatted.upload(&scene).expect("upload");
    let mut drawn = validated_renderer();
    drawn.set_settings({
        let mut settings = splat;
        settings.plan = PlanMode::Fixed(PathKind::Draw);
        settings
    });
    drawn.upload(&scene).expect("upload");
    for stop in 0..6 {
        let angle = 0.3 * stop as f64;
        let eye = DVec3::new(24.0 * angle.sin(), 3.0 - stop as f64, 24.0 * angle.cos());
        let camera = Camera::look_at(eye, DVec3::ZERO, 45.0, 1.0, 240, 180).unwrap();
        let camera = if stop >= 4 {
            camera
                .with_depth(DepthConvention::STANDARD_INFINITE)
                .unwrap()
        } else {
            camera
        };
        if stop == 3 {
            // A hundred glyphs jump across the scene: a new upload, with no stamps.
            for e in &mut scene.ellipsoids[1_000..1_100] {
                e.center = -e.center;
            }
            for renderer in [&mut splatted, &mut drawn] {
                renderer.upload(&scene).expect("upload");
            }
        }
        let expected = drawn.render_uploaded(&camera, Outputs::ALL).unwrap().0;
        for k in 0..3 {
            let (marks, first) = (true, !(k == 0 && (stop == 0 || stop == 3)));
            if stop == 2 && k == 2 {
                // A drawn frame between stamps nothing and keeps the stamps of the last.
                splatted.set_settings({
                    let mut settings = splat;
                    settings.plan = PlanMode::Fixed(PathKind::Draw);
                    settings
                });
                splatted.render_uploaded(&camera, Outputs::ALL).unwrap();
                splatted.set_settings(splat);
            }
            let plan = splatted.plan(&camera).expect("plan");
            assert!(splats(&plan), "stop {stop}: {plan:?}");
            assert_eq!(stamps(&plan), marks, "stop {stop}, frame {k}");
            assert_eq!(visible_first(&plan), first, "stop {stop}, frame {k}");
            let frame = splatted.render_uploaded(&camera, Outputs::ALL).unwrap().0;
            let name = format!("stop {stop}, frame {k}");
            let seen = Seen {
                scene: &scene,
                camera: &camera,
                format: InstanceFormat::Full,
            };
            assert_frames_agree(Agreement::of(&splatted), &name, &expected, &frame, seen);
        }
    }
    finish_validated(splatted);
    finish_validated(drawn);
}

/// The camera jumps from one cluster of glyphs to another that no frame showed yet, farther
/// away, with a drawn frame between: the visible-first splat's first pass hits nothing, so no
/// resolve tile is marked, and its second pass must find every occlusion tile holding nothing
/// (not the depths an earlier frame or the draw's culling left there), or the new cluster
/// would be culled as hidden; in both depth conventions.
#[test]
fn visible_first_after_a_jump_to_glyphs_never_shown_matches_the_draw() {
    let mut scene = random_cloud(2_000, 31, 3.0, 0.4);
    let far: Vec<Ellipsoid> = scene
        .ellipsoids
        .iter()
        .map(|e| Ellipsoid {
            center: e.center + DVec3::new(60.0, 0.0, 0.0),
            ..*e
        })
        .collect();
    scene.ellipsoids.extend(far);
    let fixed = |kind| {
        let mut settings = Settings::default();
        settings.plan = PlanMode::Fixed(kind);
        settings
    };
    let mut splatted = validated_renderer();
    splatted.set_settings(fixed(PathKind::VisibleFirst));
    splatted.upload(&scene).expect("upload");
    let mut drawn = validated_renderer();
    drawn.set_settings(fixed(PathKind::Draw));
    drawn.upload(&scene).expect("upload");
    for standard in [false, true] {
        let depth = |camera: Camera| {
            if standard {
                camera
                    .with_depth(DepthConvention::STANDARD_INFINITE)
                    .unwrap()
            } else {
                camera
            }
        };
        let near_cluster = depth(
            Camera::look_at(DVec3::new(0.0, 1.0, 9.0), DVec3::ZERO, 45.0, 1.0, 200, 150).unwrap(),
        );
        let far_cluster = depth(
            Camera::look_at(
                DVec3::new(60.0, 1.0, 18.0),
                DVec3::new(60.0, 0.0, 0.0),
                45.0,
                1.0,
                200,
                150,
            )
            .unwrap(),
        );
        // Stamps of the near cluster, tiles from its hits, then the draw's culling's tiles.
        for _ in 0..2 {
            splatted
                .render_uploaded(&near_cluster, Outputs::ALL)
                .unwrap();
        }
        splatted.set_settings(fixed(PathKind::Draw));
        splatted
            .render_uploaded(&near_cluster, Outputs::ALL)
            .unwrap();
        splatted.set_settings(fixed(PathKind::VisibleFirst));
        let plan = splatted.plan(&far_cluster).expect("plan");
        assert!(visible_first(&plan), "standard {standard}: {plan:?}");
        let expected = drawn.render_uploaded(&far_cluster, Outputs::ALL).unwrap().0;
        let shown = expected.id.iter().filter(|&&id| id != NO_INSTANCE).count();
        assert!(
            shown > 2_000,
            "standard {standard}: only {shown} pixels shown"
        );
        let frame = splatted
            .render_uploaded(&far_cluster, Outputs::ALL)
            .unwrap()
            .0;
        let seen = Seen {
            scene: &scene,
            camera: &far_cluster,
            format: InstanceFormat::Full,
        };
        let name = format!("far cluster after a jump, standard depth {standard}");
        assert_frames_agree(Agreement::of(&splatted), &name, &expected, &frame, seen);
    }
    finish_validated(splatted);
    finish_validated(drawn);
}

#[test]
fn splat_over_several_chunks_matches_the_draw() {
    // 1,500 tiny glyphs in 6 chunks of 256: each chunk splats into the shared visibility
    // buffer and resolves its own pixels; ties and overlaps across chunks resolve as in one
    // draw. Then with large glyphs in every chunk, which each chunk's own keep bits,
    // compaction and indirect command leave to the draw; in both depth conventions.
    let (scene, camera) = tiny_glyphs();
    let tiny = Scene::new(scene.ellipsoids[..1_500].to_vec());
    let mut mixed = tiny.ellipsoids.clone();
    for k in 0..6 {
        let t = k as f64;
        mixed[150 + 220 * k] = Ellipsoid::new(
            DVec3::new(6.0 * (t * 1.3).sin(), 4.0 * (t * 0.7).cos(), 3.0 * t - 7.0),
            DVec3::new(4.5, 3.0, 2.0),
            DQuat::from_rotation_z(t),
            Some([0.9, 0.5, 0.1]),
        )
        .expect("large glyph");
    }
    let mixed = Scene::new(mixed);
    let standard = camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention");
    let mut renderer = validated_renderer();
    for (name, scene, camera) in [
        ("tiny", &tiny, camera),
        ("with large glyphs", &mixed, camera),
        ("with large glyphs, standard depth", &mixed, standard),
    ] {
        chunked_splat_matches_the_draw(&mut renderer, name, scene, &camera);
    }
    finish_validated(renderer);
}

/// Renders `scene` drawn whole, splatted in chunks of 256 and splatted whole, and asserts
/// the three frames agree.
fn chunked_splat_matches_the_draw(
    renderer: &mut OffscreenRenderer,
    name: &str,
    scene: &Scene,
    camera: &Camera,
) {
    let render = |renderer: &mut OffscreenRenderer, compute_splat: bool, chunk: u32| {
        renderer.set_settings({
            let mut settings = Settings::default();
            settings.plan = PlanMode::Fixed(if compute_splat {
                PathKind::Splat
            } else {
                PathKind::Draw
            });
            settings.max_chunk_instances = chunk;
            // As in `assert_splat_matches_draw_set_up`: no records from the draw.
            settings.setup_once = compute_splat;
            settings
        });
        renderer.upload(scene).expect("upload");
        let plan = renderer.plan(camera).expect("plan");
        assert_eq!(splats(&plan), compute_splat, "{name}: {plan:?}");
        if compute_splat {
            // As in `assert_splat_matches_draw_set_up`: set-up records wrong for `camera`.
            renderer
                .render_uploaded(&aside(camera), Outputs::COLOR_DEPTH)
                .expect("splat aside");
        }
        renderer
            .render_uploaded(camera, Outputs::ALL)
            .expect("render")
            .0
    };
    let drawn = render(renderer, false, u32::MAX);
    let chunked = render(renderer, true, 256);
    let whole = render(renderer, true, u32::MAX);
    let shown = drawn.id.iter().filter(|&&id| id != NO_INSTANCE).count();
    let late = drawn
        .id
        .iter()
        .filter(|&&id| id != NO_INSTANCE && id >= 256)
        .count();
    assert!(
        shown > 300 && late > 200,
        "{name}: {shown} shown, {late} from later chunks"
    );
    let agreement = Agreement::of(renderer);
    for (label, frame) in [("six chunks", &chunked), ("one chunk", &whole)] {
        let seen = Seen {
            scene,
            camera,
            format: InstanceFormat::Full,
        };
        assert_frames_agree(agreement, &format!("{name}, {label}"), &drawn, frame, seen);
    }
}

/// The benchmark's paths' cases: medium glyphs many layers deep in perspective, orthographic
/// and standard depth, a near-plane cut, exact depth ties, glyphs reaching the eye plane, and
/// six chunks (name, scene, camera, most instances per chunk).
#[cfg(feature = "research")]
fn research_cases() -> Vec<(&'static str, Scene, Camera, u32)> {
    research_cases_sized(6_000, (333, 250), 10_000)
}

/// `research_cases` with `glyphs` medium glyphs, images of `width` x `height` pixels and
/// `tied_pairs` pairs of tied glyphs.
#[cfg(feature = "research")]
fn research_cases_sized(
    glyphs: usize,
    (width, height): (u32, u32),
    tied_pairs: usize,
) -> Vec<(&'static str, Scene, Camera, u32)> {
    let camera = Camera::look_at(
        DVec3::new(3.0, -2.0, 24.0),
        DVec3::ZERO,
        45.0,
        1.0,
        width,
        height,
    )
    .unwrap();
    let medium = random_cloud(glyphs, 23, 10.0, 0.5);
    let ortho = Camera {
        projection: Projection::Orthographic { height: 20.0 },
        ..camera
    };
    let standard = camera
        .with_depth(DepthConvention::STANDARD_INFINITE)
        .expect("depth convention");
    let inside = Camera::look_at(
        DVec3::new(0.5, 0.2, 7.0),
        DVec3::ZERO,
        60.0,
        5.5,
        width,
        height,
    )
    .expect("camera");
    let cut = random_cloud(glyphs, 24, 5.0, 0.25);
    assert_reaches_near_plane(&cut, &inside);
    let (tiny, tiny_camera) = tiny_glyphs();
    let mut tied = Vec::new();
    for e in tiny.ellipsoids.iter().take(tied_pairs) {
        tied.push(*e);
        tied.push(Ellipsoid {
            color: [0.1, 0.9, 0.1],
            ..*e
        });
    }
    let tied = Scene::new(tied);
    // Two glyphs through the eye plane among the medium ones.
    let mut eye_plane = medium.ellipsoids.clone();
    for (k, x) in [(10, -1.0), (20, 1.5)] {
        eye_plane[k] = Ellipsoid::new(
            DVec3::new(x, 0.3, 24.0),
            DVec3::new(0.8, 0.5, 1.5),
            DQuat::from_rotation_y(0.4),
            Some([0.2, 0.4, 0.9]),
        )
        .expect("glyph");
    }
    let eye_plane = Scene::new(eye_plane);
    vec![
        ("perspective", medium.clone(), camera, u32::MAX),
        ("orthographic", medium.clone(), ortho, u32::MAX),
        ("standard depth", medium.clone(), standard, u32::MAX),
        ("near-plane cut", cut, inside, u32::MAX),
        ("exact ties", tied, tiny_camera, u32::MAX),
        ("through the eye plane", eye_plane, camera, u32::MAX),
        ("six chunks", medium, camera, 1_000),
    ]
}

/// Renders `scene` with `method` (at most `chunk` instances per chunk); checks its plan with
/// `check`.
#[cfg(feature = "research")]
fn render_method(
    renderer: &mut OffscreenRenderer,
    method: ellipsoid_splat::research::Method,
    (scene, camera, chunk): (&Scene, &Camera, u32),
    check: impl Fn(&ellipsoid_splat::FramePlan),
) -> ellipsoid_splat::Frame {
    renderer.set_draw_config(method.config());
    renderer.set_tiled_splat(method.tiled_splat());
    renderer.set_settings({
        let mut settings = method.settings();
        settings.max_chunk_instances = chunk;
        settings
    });
    renderer.upload(scene).expect("upload");
    check(&renderer.plan(camera).expect("plan"));
    renderer
        .render_uploaded(camera, Outputs::ALL)
        .expect("render")
        .0
}

/// The benchmark's visibility-buffer draw (`impostor-visbuffer`: every glyph rasterized into
/// the visibility buffer, then the splat's resolve) draws what the draw draws (bit for bit
/// on lavapipe), in every case of `research_cases`.
#[cfg(feature = "research")]
#[test]
fn visibility_buffer_draw_matches_the_draw() {
    use ellipsoid_splat::research::Method;
    let mut renderer = validated_renderer();
    let agreement = Agreement::of(&renderer);
    for (name, scene, camera, chunk) in research_cases() {
        let case = (&scene, &camera, chunk);
        let drawn = render_method(&mut renderer, Method::ImpostorDraw, case, |_| {});
        let visbuffer = render_method(&mut renderer, Method::ImpostorVisbuffer, case, |plan| {
            // The visibility-buffer draw is a baseline: the draw's path, no culling (a host
            // prints the draw's reason rather than naming it; its `Debug` says which).
            assert!(
                matches!(plan.reason, PlanReason::Only(why) if format!("{why:?}") == "Baseline")
                    && plan.culling() == Culling::OFF,
                "{name}: {plan:?}"
            );
        });
        let seen = Seen {
            scene: &scene,
            camera: &camera,
            format: InstanceFormat::Full,
        };
        assert_frames_agree(agreement, name, &drawn, &visbuffer, seen);
    }
    finish_validated(renderer);
}

/// The benchmark's tiled splat (`impostor-tiled`: each 8 x 8 tile's glyphs ray cast by one
/// workgroup keeping the tile's keys, written once) draws what the draw draws (bit for bit on
/// lavapipe), in every case of `research_cases`: ties to the lower instance, glyphs through
/// the eye plane left to the draw, later chunks keeping what earlier ones left.
#[cfg(feature = "research")]
#[test]
fn tiled_splat_matches_the_draw() {
    use ellipsoid_splat::research::Method;
    let mut renderer = validated_renderer();
    let agreement = Agreement::of(&renderer);
    for (name, scene, camera, chunk) in research_cases() {
        let case = (&scene, &camera, chunk);
        let drawn = render_method(&mut renderer, Method::ImpostorDraw, case, |_| {});
        let tiled = render_method(&mut renderer, Method::ImpostorTiled, case, |plan| {
            assert!(plan.path.splat().is_some(), "{name}: {plan:?}");
        });
        let seen = Seen {
            scene: &scene,
            camera: &camera,
            format: InstanceFormat::Full,
        };
        assert_frames_agree(agreement, name, &drawn, &tiled, seen);
    }
    finish_validated(renderer);
}

/// The benchmark's ray-cast counts (`research`): the visible-pixel floor ray casts exactly
/// the pixels the float64 reference shows a glyph at, each once; the splat ray casts every
/// covered pixel centre of every glyph (hidden layers included) at least once, and its
/// resolve one more per pixel it shades; the draw one per fragment it shades.
#[cfg(feature = "research")]
#[test]
fn ray_casts_are_counted_against_the_reference() {
    use ellipsoid_splat::research::Method;
    use ellipsoid_splat_reference::reference::render_reference;

    // Glyphs of a few to tens of pixels, several layers deep.
    let camera = Camera::look_at(
        DVec3::new(3.0, -2.0, 24.0),
        DVec3::ZERO,
        45.0,
        1.0,
        240,
        180,
    )
    .unwrap();
    let scene = random_cloud(6_000, 23, 10.0, 0.3);
    let reference = render_reference(&scene, &camera).unwrap();
    let visible = reference.id.iter().filter(|&&id| id != NO_INSTANCE).count() as u64;
    let centres = reference.silhouette_pixels();
    assert!(
        2 * centres > 3 * visible,
        "{centres} covered centres, {visible} visible pixels"
    );
    let mut renderer = validated_renderer();
    renderer.set_count_fragments(true);
    let mut counts = |method: Method| {
        renderer.set_settings(method.settings());
        renderer.set_draw_config(method.config());
        renderer.set_splat_floor(method.splat_floor());
        renderer.upload(&scene).expect("upload");
        if method == Method::FloorVisible {
            renderer
                .set_floor_pixels(&reference.id, reference.width)
                .expect("floor pixels");
        }
        let timing = renderer.render_uploaded(&camera, Outputs::ALL).unwrap().1;
        (
            timing.compute_ray_casts.expect("counted"),
            timing.shaded_fragments.expect("counted"),
        )
    };
    assert_eq!(counts(Method::FloorVisible), (visible, 0));
    let (walked, resolved) = counts(Method::ImpostorCompute);
    assert!(
        walked >= centres,
        "{walked} ray casts for {centres} covered centres"
    );
    assert!(
        walked < centres * 2,
        "{walked} ray casts for {centres} covered centres"
    );
    // Each pixel the splat shows is shaded once: the reference's count, within the coverage
    // bound (float32 against float64 at silhouettes).
    let off = resolved.abs_diff(visible);
    assert!(
        off * 1_000 <= visible,
        "{resolved} resolved, {visible} visible pixels"
    );
    let (arithmetic, none) = counts(Method::FloorArithmetic);
    assert_eq!(
        (arithmetic, none),
        (walked, 0),
        "the floor walks what the splat walks"
    );
    let (compute, fragments) = counts(Method::ImpostorDraw);
    assert_eq!(compute, 0);
    assert!(
        fragments >= centres,
        "{fragments} fragments for {centres} covered centres"
    );
    finish_validated(renderer);
}

/// The traced path (`research`, method `impostor-traced`: ray queries along a hierarchy of
/// the glyphs' boxes, one invocation per pixel) draws what the draw draws, on the cases of
/// the visibility-buffer draw that fit one chunk: perspective, orthographic, standard depth,
/// the near plane cutting glyphs, exact ties (the lower instance wins) and glyphs through the
/// eye plane. Only drivers with ray queries run it (Mesa 25's lavapipe, not 22's): elsewhere
/// it says it skipped.
#[cfg(feature = "research")]
#[test]
fn traced_path_matches_the_draw() {
    use ellipsoid_splat::research::Method;
    let mut renderer = validated_renderer();
    if !renderer.context().info().ray_query {
        println!("traced_path_matches_the_draw: SKIPPED the traced cases (no ray queries)");
        finish_validated(renderer);
        return;
    }
    // Smaller than the visibility-buffer draw's cases (lavapipe's traversal is slow), in one
    // chunk (the traced path's hierarchy covers one), and a finite standard depth besides.
    let mut cases: Vec<_> = research_cases_sized(2_000, (200, 150), 3_000)
        .into_iter()
        .filter(|&(_, _, _, chunk)| chunk == u32::MAX)
        .collect();
    let (_, medium, camera, _) = cases[0].clone();
    let finite = camera
        .with_depth(DepthConvention {
            reversed: false,
            far: Some(30.0),
        })
        .expect("depth convention");
    cases.push(("standard finite depth", medium, finite, u32::MAX));
    let agreement = Agreement::of(&renderer);
    for (name, scene, camera, _) in &cases {
        let (scene, camera) = (scene, *camera);
        let render = |renderer: &mut OffscreenRenderer, method: Method| {
            renderer.set_draw_config(method.config());
            renderer.set_settings(method.settings());
            renderer.set_traced(method.traced());
            renderer.upload(scene).expect("upload");
            // The traced method replaces only the splat's frames: the frame must splat.
            let plan = renderer.plan(&camera).expect("plan");
            assert_eq!(
                splats(&plan),
                method == Method::ImpostorTraced,
                "{name}: {plan:?}"
            );
            renderer
                .render_uploaded(&camera, Outputs::ALL)
                .expect("render")
                .0
        };
        let drawn = render(&mut renderer, Method::ImpostorDraw);
        let traced = render(&mut renderer, Method::ImpostorTraced);
        let seen = Seen {
            scene,
            camera: &camera,
            format: InstanceFormat::Full,
        };
        assert_frames_agree(agreement, name, &drawn, &traced, seen);
        // A second frame traces the hierarchy the first built.
        let again = renderer
            .render_uploaded(&camera, Outputs::ALL)
            .expect("render")
            .0;
        assert_frames_agree(
            agreement,
            &format!("{name}, built before"),
            &drawn,
            &again,
            seen,
        );
    }
    renderer.set_traced(ellipsoid_splat::research::TracedBuild::Off);
    finish_validated(renderer);
}
