//! Every camera an engine renders with -- off-centre and non-square pinholes, asymmetric
//! per-eye frusta, jittered projections, off-centre orthographic windows, y-up projections
//! drawn with a flipped viewport, a viewport rectangle inside larger attachments, several
//! views in one frame -- against the float64 reference: no coverage mismatch, depth p99 within
//! 1e-6, under validation and synchronization validation.

use ellipsoid_splat::PathKind;
use ellipsoid_splat::{Camera, Frame, HostViewport, Intrinsics, Outputs, Projection, NO_INSTANCE};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_reference::compare::{compare, Bounds, ErrorStats};
use ellipsoid_splat_reference::reference::render_reference;
use ellipsoid_splat_reference::testing::{
    finish_validated, fixed_path, splats, stamps, validated_renderer, visible_first,
};
use glam::{DMat4, DVec2, DVec3, DVec4};

const W: u32 = 200;
const H: u32 = 150;

fn base() -> Camera {
    Camera::look_at(DVec3::new(2.0, 3.0, 14.0), DVec3::ZERO, 45.0, 2.0, W, H).unwrap()
}

/// `frame` against the reference of `camera`'s image: no coverage mismatch, every strict
/// bound, and enough covered pixels to prove something.
fn assert_exact(name: &str, frame: &Frame, camera: &Camera, scene: &ellipsoid_splat::Scene) {
    let reference = render_reference(scene, camera).unwrap();
    let stats: ErrorStats = compare(frame, &reference).unwrap();
    println!("{name}: {stats}");
    assert!(stats.covered_pixels > 3_000, "{name}: {stats}");
    assert_eq!(stats.coverage_mismatch, 0, "{name}: {stats}");
    assert_eq!(stats.id_mismatch, 0, "{name}: {stats}");
    if let Err(broken) = stats.check(&Bounds::STRICT) {
        panic!("{name}: {broken}\n{stats}");
    }
}

/// A y-up projection (OpenGL's, depth in [0, 1], reversed infinite) for a frustum of
/// tangents `l, r, b, t`.
fn y_up_frustum(l: f64, r: f64, b: f64, t: f64, near: f64) -> DMat4 {
    DMat4::from_cols(
        DVec4::new(2.0 / (r - l), 0.0, 0.0, 0.0),
        DVec4::new(0.0, 2.0 / (t - b), 0.0, 0.0),
        DVec4::new((r + l) / (r - l), (t + b) / (t - b), 0.0, -1.0),
        DVec4::new(0.0, 0.0, near, 0.0),
    )
}

/// The general cameras, each with the draw and, in a second renderer, with the compute
/// splat taking every glyph.
fn general_cameras() -> Vec<(&'static str, Camera)> {
    let b = base();
    let with = |projection| Camera { projection, ..b };
    let view = DMat4::look_at_rh(b.eye, b.target, DVec3::Y);
    let flipped = HostViewport {
        x: 0,
        y: H,
        width: W,
        height: -(H as i32),
    };
    vec![
        (
            "off-centre pinhole, non-square pixels",
            with(Projection::PerspectiveIntrinsics(Intrinsics {
                fx: 170.0,
                fy: 190.0,
                cx: 60.0,
                cy: 100.0,
            })),
        ),
        (
            "asymmetric eye frustum",
            with(Projection::PerspectiveIntrinsics(
                Intrinsics::from_tangents(-0.55, 0.35, -0.4, 0.45, W, H).unwrap(),
            )),
        ),
        (
            "jittered perspective",
            b.with_jitter(DVec2::new(0.37, -0.44)).unwrap(),
        ),
        (
            "off-centre orthographic window",
            with(Projection::OrthographicIntrinsics(
                Intrinsics::from_ortho_window(-4.0, 7.0, -6.5, 2.0, W, H).unwrap(),
            )),
        ),
        (
            "y-up projection, flipped viewport",
            Camera::from_view_projection_viewport(
                view,
                y_up_frustum(-0.5, 0.3, -0.35, 0.4, 2.0),
                flipped,
            )
            .unwrap(),
        ),
    ]
}

#[test]
fn every_camera_kind_matches_the_reference() {
    let scene = random_cloud(1500, 7, 5.0, 0.6);
    for splat in [false, true] {
        let mut renderer = validated_renderer();
        renderer.set_settings(fixed_path(if splat {
            PathKind::Splat
        } else {
            PathKind::Draw
        }));
        renderer.upload(&scene).unwrap();
        for (name, camera) in general_cameras() {
            assert!(camera.validate().is_ok(), "{name}");
            let plan = renderer.plan(&camera).unwrap();
            assert_eq!(splats(&plan), splat, "{name}");
            let (frame, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
            assert_exact(&format!("{name}, splat {splat}"), &frame, &camera, &scene);
        }
        finish_validated(renderer);
    }
}

/// The radical inverse of `k` in `base`: the Halton sequence a TAA jitter walks.
fn halton(mut k: u32, base: u32) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while k > 0 {
        f /= base as f64;
        r += f * (k % base) as f64;
        k /= base;
    }
    r
}

/// Eight frames of a Halton (2, 3) jitter, as TAA and upscalers walk it, each exact; the
/// sequence moves the picture (frames differ), and the renderer's plan stays the same.
#[test]
fn a_halton_jitter_sequence_is_exact_frame_by_frame() {
    let scene = random_cloud(1500, 11, 5.0, 0.6);
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    let mut ids = Vec::new();
    for k in 1..=8 {
        let jitter = DVec2::new(halton(k, 2) - 0.5, halton(k, 3) - 0.5);
        let camera = base().with_jitter(jitter).unwrap();
        let (frame, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
        assert_exact(&format!("jitter {k} {jitter}"), &frame, &camera, &scene);
        ids.push(frame.id);
    }
    let moved = ids.windows(2).filter(|pair| pair[0] != pair[1]).count();
    assert_eq!(moved, 7, "every jittered frame shows a different picture");
    finish_validated(renderer);
}

/// A camera drawn at a viewport origin inside larger attachments gives, in its rectangle,
/// exactly the pixels it gives on its own (colour, depth, normal and ID, bit for bit), and
/// background everywhere else.
#[test]
fn a_viewport_rectangle_draws_the_same_pixels_and_nothing_outside() {
    let scene = random_cloud(1500, 5, 5.0, 0.6);
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    for (name, camera) in general_cameras().into_iter().take(3) {
        let (alone, _) = renderer.render_uploaded(&camera, Outputs::ALL).unwrap();
        let inset = camera.with_viewport_origin(37, 21).unwrap();
        let (big, _) = renderer
            .render_views(W + 60, H + 50, &[inset], Outputs::ALL)
            .unwrap();
        assert_eq!(big.crop(37, 21, W, H).as_ref(), Some(&alone), "{name}");
        let background = big.color[0];
        for j in 0..big.height {
            for i in 0..big.width {
                let inside = (37..37 + W).contains(&i) && (21..21 + H).contains(&j);
                let k = big.index(i, j);
                if !inside {
                    assert_eq!(big.id[k], NO_INSTANCE, "{name}: ({i}, {j})");
                    assert_eq!(big.color[k], background, "{name}: ({i}, {j})");
                    assert_eq!(big.depth[k], f32::INFINITY, "{name}: ({i}, {j})");
                }
            }
        }
    }
    finish_validated(renderer);
}

/// A stereo pair: two eyes with mirrored asymmetric frusta, side by side in one attachment,
/// each with its own pre-pass recorded before the one pass, each view exact.
#[test]
fn a_stereo_pair_side_by_side_is_exact() {
    let scene = random_cloud(2000, 3, 5.0, 0.6);
    let centre = base();
    let right = centre.basis().right;
    let eye = |side: f64, tangents: (f64, f64)| Camera {
        eye: centre.eye + side * 0.3 * right,
        target: centre.target + side * 0.3 * right,
        projection: Projection::PerspectiveIntrinsics(
            Intrinsics::from_tangents(tangents.0, tangents.1, -0.42, 0.42, W, H).unwrap(),
        ),
        ..centre
    };
    let left_eye = eye(-1.0, (-0.62, 0.5));
    let right_eye = eye(1.0, (-0.5, 0.62)).with_viewport_origin(W, 0).unwrap();
    for splat in [false, true] {
        let mut renderer = validated_renderer();
        renderer.set_settings(fixed_path(if splat {
            PathKind::Splat
        } else {
            PathKind::Draw
        }));
        renderer.upload(&scene).unwrap();
        let (pair, _) = renderer
            .render_views(2 * W, H, &[left_eye, right_eye], Outputs::ALL)
            .unwrap();
        for (name, camera) in [("left eye", left_eye), ("right eye", right_eye)] {
            let [x, y] = camera.viewport_origin;
            let view = pair.crop(x, y, W, H).unwrap();
            let alone = Camera {
                viewport_origin: [0, 0],
                ..camera
            };
            assert_exact(&format!("{name}, splat {splat}"), &view, &alone, &scene);
        }
        finish_validated(renderer);
    }
}

/// Each view keeps its own history: drawn in the same order frame after frame, each view of a
/// stereo pair stamps what it shows in its first frame and runs the visible-first splat from
/// its own stamps after, and every frame gives the same exact pictures.
#[test]
fn each_view_keeps_its_own_history() {
    let scene = random_cloud(6000, 9, 5.0, 0.5);
    let a = base();
    let b = Camera {
        eye: DVec3::new(-6.0, 2.0, 11.0),
        ..a
    }
    .with_viewport_origin(W, 0)
    .unwrap();
    let mut renderer = validated_renderer();
    renderer.set_settings(fixed_path(PathKind::VisibleFirst));
    renderer.upload(&scene).unwrap();
    let mut frames = Vec::new();
    for frame in 0..4 {
        let plans = [renderer.plan(&a).unwrap(), renderer.plan(&b).unwrap()];
        for plan in &plans {
            assert!(splats(plan));
            // The first frame stamps what it shows, the next ones start from it.
            assert!(stamps(plan), "frame {frame}: {plan:?}");
            assert_eq!(visible_first(plan), frame > 0, "frame {frame}: {plan:?}");
        }
        let (pair, _) = renderer
            .render_views(2 * W, H, &[a, b], Outputs::ALL)
            .unwrap();
        frames.push(pair);
    }
    assert!(frames.windows(2).all(|f| f[0] == f[1]), "frames differ");
    for camera in [a, b] {
        let [x, y] = camera.viewport_origin;
        let view = frames[3].crop(x, y, W, H).unwrap();
        let alone = Camera {
            viewport_origin: [0, 0],
            ..camera
        };
        assert_exact("view of a still pair", &view, &alone, &scene);
    }
    finish_validated(renderer);
}

#[test]
fn views_that_overlap_or_leave_the_attachments_are_refused() {
    let scene = random_cloud(10, 1, 5.0, 0.6);
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    let a = base();
    let b = a.with_viewport_origin(W / 2, 0).unwrap();
    let err = renderer
        .render_views(2 * W, H, &[a, b], Outputs::ALL)
        .unwrap_err();
    assert!(err.to_string().contains("overlap"), "{err}");
    let err = renderer.render_views(W, H, &[b], Outputs::ALL).unwrap_err();
    assert!(err.to_string().contains("beyond"), "{err}");
    let err = renderer.render_views(W, H, &[], Outputs::ALL).unwrap_err();
    assert!(err.to_string().contains("no camera"), "{err}");
    finish_validated(renderer);
}

// docs/embedding.md: stereo_taa_cameras
/// The two cameras of frame `frame` of a stereo headset with temporal antialiasing: each eye's
/// view and Vulkan projection (asymmetric frusta, as OpenXR gives them) jittered by the frame's
/// Halton (2, 3) offset, the left eye drawn in the left half of the attachment, the right eye
/// in the right half.
fn stereo_taa_cameras(
    frame: u32,
    eyes: [(DMat4, DMat4); 2],
    eye_width: u32,
    height: u32,
) -> ellipsoid_splat::Result<[Camera; 2]> {
    let halton = |mut k: u32, base: u32| {
        let (mut f, mut x) = (1.0, 0.0);
        while k > 0 {
            f /= base as f64;
            x += f * (k % base) as f64;
            k /= base;
        }
        x
    };
    let (dx, dy) = (
        halton(frame % 8 + 1, 2) - 0.5,
        halton(frame % 8 + 1, 3) - 0.5,
    );
    // Pixel (i, j) samples the unjittered image at (i + 0.5 + dx, j + 0.5 + dy): the picture
    // moves by (-dx, -dy) pixels, 2 / size NDC units each.
    let (w, h) = (eye_width as f64, height as f64);
    let jitter = DMat4::from_translation(DVec3::new(-2.0 * dx / w, -2.0 * dy / h, 0.0));
    let camera = |k: u32| {
        let (view, projection) = eyes[k as usize];
        let viewport = HostViewport {
            x: k * eye_width,
            y: 0,
            width: eye_width,
            height: height as i32,
        };
        Camera::from_view_projection_viewport(view, jitter * projection, viewport)
    };
    Ok([camera(0)?, camera(1)?])
}
// docs/embedding.md: end

/// The embedding guide's stereo-and-TAA cameras (`docs/embedding.md`): each eye's jittered camera samples the unjittered
/// one's image at the Halton offset, and two frames of the pair drawn as two views of one
/// attachment are exact in both eyes.
#[test]
fn the_embedding_guides_stereo_taa_frames_are_exact() {
    let scene = random_cloud(2000, 5, 5.0, 0.6);
    let centre = base();
    let right = centre.basis().right;
    let y_down = DMat4::from_scale(DVec3::new(1.0, -1.0, 1.0));
    let eyes = [(-1.0, (-0.62, 0.5)), (1.0, (-0.5, 0.62))].map(|(side, (l, r))| {
        let offset = side * 0.3 * right;
        let view = DMat4::look_at_rh(centre.eye + offset, centre.target + offset, DVec3::Y);
        (view, y_down * y_up_frustum(l, r, -0.42, 0.42, 2.0))
    });
    let mut renderer = validated_renderer();
    renderer.upload(&scene).unwrap();
    for frame in 0..2 {
        let cameras = stereo_taa_cameras(frame, eyes, W, H).unwrap();
        let (dx, dy) = (halton(frame + 1, 2) - 0.5, halton(frame + 1, 3) - 0.5);
        for (k, camera) in cameras.iter().enumerate() {
            let (view, projection) = eyes[k];
            let viewport = HostViewport {
                x: k as u32 * W,
                y: 0,
                width: W,
                height: H as i32,
            };
            let still = Camera::from_view_projection_viewport(view, projection, viewport).unwrap();
            for pixel in [DVec2::new(0.5, 0.5), DVec2::new(117.5, 42.5)] {
                let jittered = camera.ray_at_pixel(pixel);
                let sampled = still.ray_at_pixel(pixel + DVec2::new(dx, dy));
                let gap = (jittered.direction.normalize() - sampled.direction.normalize()).length();
                assert!(gap < 1e-9, "eye {k}, frame {frame}: {gap}");
                assert!((jittered.origin - sampled.origin).length() < 1e-9);
            }
        }
        let (pair, _) = renderer
            .render_views(2 * W, H, &cameras, Outputs::ALL)
            .unwrap();
        for camera in cameras {
            let [x, y] = camera.viewport_origin;
            let view = pair.crop(x, y, W, H).unwrap();
            let alone = Camera {
                viewport_origin: [0, 0],
                ..camera
            };
            assert_exact(&format!("stereo TAA frame {frame}"), &view, &alone, &scene);
        }
    }
    finish_validated(renderer);
}
