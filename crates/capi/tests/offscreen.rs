//! The offscreen renderer through the C ABI draws what the Rust API's `OffscreenRenderer`
//! draws, bit for bit, into the host's arrays (each output alone too), under validation; bad
//! input is a status and a message naming what and why.

use std::ffi::CStr;

use ellipsoid_splat::{ContextOptions, Ellipsoid, OffscreenRenderer, Outputs, Scene};
use ellipsoid_splat_capi::*;
use glam::{DQuat, DVec3};

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;
const PIXELS: usize = (WIDTH * HEIGHT) as usize;

fn last_error() -> String {
    // SAFETY: the library keeps a valid C string per thread.
    unsafe { CStr::from_ptr(es_last_error()) }
        .to_string_lossy()
        .into_owned()
}

/// A few overlapping glyphs in front of the camera.
fn glyphs() -> Vec<EsGlyph> {
    (0..30)
        .map(|i| {
            let t = f64::from(i);
            let q = DQuat::from_axis_angle(DVec3::new(1.0, t, 0.5).normalize(), 0.3 * t);
            EsGlyph {
                center: [
                    (t * 0.7).sin() * 2.0,
                    (t * 1.3).cos() * 1.5,
                    (t * 0.4).sin(),
                ],
                radii: [0.3 + 0.02 * t, 0.5, 0.2 + 0.01 * t],
                rotation: [q.w, q.x, q.y, q.z],
                color: [(t / 30.0) as f32, 0.5, 1.0 - (t / 30.0) as f32],
            }
        })
        .collect()
}

fn camera() -> EsCamera {
    let mut camera = std::mem::MaybeUninit::<EsCamera>::uninit();
    let (eye, target, up) = ([1.0, 2.0, 8.0], [0.0; 3], [0.0, 1.0, 0.0]);
    // SAFETY: valid arrays and a writable camera.
    let status = unsafe {
        es_camera_look_at(
            eye.as_ptr(),
            target.as_ptr(),
            up.as_ptr(),
            40.0,
            1.0,
            WIDTH,
            HEIGHT,
            camera.as_mut_ptr(),
        )
    };
    assert_eq!(status, EsStatus::Success, "{}", last_error());
    // SAFETY: written by the successful call.
    unsafe { camera.assume_init() }
}

/// The host's arrays of one frame.
struct Arrays {
    color: Vec<u8>,
    depth: Vec<f32>,
    normal: Vec<f32>,
    id: Vec<u32>,
}

impl Arrays {
    fn new() -> Self {
        // Filled with a value no output has, so an array left unwritten shows.
        Self {
            color: vec![7; PIXELS * 4],
            depth: vec![-7.0; PIXELS],
            normal: vec![-7.0; PIXELS * 3],
            id: vec![7_000_000; PIXELS],
        }
    }

    /// The buffers of the outputs `which` names (colour, depth, normal, id).
    fn buffers(&mut self, which: [bool; 4]) -> EsFrameBuffers {
        let pick = |on: bool, p: *mut u8| if on { p } else { std::ptr::null_mut() };
        EsFrameBuffers {
            struct_size: std::mem::size_of::<EsFrameBuffers>() as u32,
            color: pick(which[0], self.color.as_mut_ptr()),
            depth: pick(which[1], self.depth.as_mut_ptr().cast()).cast(),
            normal: pick(which[2], self.normal.as_mut_ptr().cast()).cast(),
            id: pick(which[3], self.id.as_mut_ptr().cast()).cast(),
        }
    }
}

fn create(validation: u32) -> *mut EsOffscreenRenderer {
    let info = EsOffscreenCreateInfo {
        struct_size: std::mem::size_of::<EsOffscreenCreateInfo>() as u32,
        validation,
        device: std::ptr::null(),
        settings: std::ptr::null(),
    };
    let mut renderer = std::ptr::null_mut();
    // SAFETY: a valid create info and a writable handle.
    let status = unsafe { es_offscreen_create(&info, &mut renderer) };
    assert_eq!(status, EsStatus::Success, "{}", last_error());
    renderer
}

#[test]
fn the_offscreen_renderer_draws_what_the_rust_api_draws() {
    let glyphs = glyphs();
    let camera = camera();
    let renderer = create(1);
    let mut rust = OffscreenRenderer::new(&ContextOptions::validated()).unwrap();
    let scene = Scene::new(
        glyphs
            .iter()
            .map(|g| {
                let [w, x, y, z] = g.rotation;
                Ellipsoid::new(
                    DVec3::from_array(g.center),
                    DVec3::from_array(g.radii),
                    DQuat::from_xyzw(x, y, z, w),
                    Some(g.color),
                )
                .unwrap()
            })
            .collect(),
    );
    let library = ellipsoid_splat::Camera::new(
        DVec3::new(1.0, 2.0, 8.0),
        DVec3::ZERO,
        DVec3::Y,
        ellipsoid_splat::Projection::Perspective { fov_y_deg: 40.0 },
        1.0,
        WIDTH,
        HEIGHT,
    )
    .unwrap()
    .with_depth(ellipsoid_splat::DepthConvention::REVERSED_INFINITE)
    .unwrap();
    let expected = rust.render(&scene, &library, Outputs::ALL).unwrap();
    assert!(
        expected.id.iter().filter(|&&id| id != ES_NO_GLYPH).count() > PIXELS / 10,
        "the glyphs are in view"
    );
    // Every output at once, then each alone (the others stay untouched).
    let every = [true; 4];
    let alone = (0..4).map(|k| std::array::from_fn(|j| j == k));
    for which in std::iter::once(every).chain(alone) {
        let mut arrays = Arrays::new();
        let buffers = arrays.buffers(which);
        // SAFETY: live renderer; the glyphs, camera and buffers are valid and large enough.
        let status = unsafe {
            es_offscreen_render(renderer, glyphs.as_ptr(), glyphs.len(), &camera, &buffers)
        };
        assert_eq!(status, EsStatus::Success, "{}", last_error());
        let untouched = Arrays::new();
        let bits = |v: &[f32]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        let written: [(bool, bool); 4] = [
            (
                arrays.color == expected.color.as_flattened(),
                arrays.color == untouched.color,
            ),
            (
                bits(&arrays.depth) == bits(&expected.depth),
                arrays.depth == untouched.depth,
            ),
            (
                bits(&arrays.normal) == bits(expected.normal.as_flattened()),
                arrays.normal == untouched.normal,
            ),
            (arrays.id == expected.id, arrays.id == untouched.id),
        ];
        for (k, (equal, left)) in written.into_iter().enumerate() {
            assert!(
                if which[k] { equal } else { left },
                "output {k} of {which:?}"
            );
        }
    }
    // SAFETY: the renderer is not used again.
    let status = unsafe { es_offscreen_destroy(renderer) };
    assert_eq!(status, EsStatus::Success, "{}", last_error());
    rust.finish().unwrap();
}

#[test]
fn bad_offscreen_arguments_are_named_errors() {
    let glyphs = glyphs();
    let camera = camera();
    let mut arrays = Arrays::new();
    let buffers = arrays.buffers([true; 4]);
    let mut handle = std::ptr::null_mut();
    // SAFETY: a null create info is refused; the handle is writable.
    let status = unsafe { es_offscreen_create(std::ptr::null(), &mut handle) };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(last_error().contains("create info"), "{}", last_error());
    assert!(handle.is_null());

    // SAFETY: a null renderer is refused before anything else is read.
    let status =
        unsafe { es_offscreen_render(std::ptr::null_mut(), glyphs.as_ptr(), 1, &camera, &buffers) };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(last_error().contains("renderer"), "{}", last_error());

    let renderer = create(1);
    let render = |glyphs: &[EsGlyph], camera: &EsCamera, buffers: *const EsFrameBuffers| {
        // SAFETY: live renderer; valid glyphs and camera; buffers null or valid.
        let status = unsafe {
            es_offscreen_render(renderer, glyphs.as_ptr(), glyphs.len(), camera, buffers)
        };
        (status, last_error())
    };
    let (status, message) = render(&glyphs, &camera, std::ptr::null());
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("invalid buffers: is null"), "{message}");

    let mut flat = glyphs.clone();
    flat[3].radii[2] = 0.0;
    let (status, message) = render(&flat, &camera, &buffers);
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("glyph 3"), "{message}");

    let mut inset = camera;
    inset.viewport_origin = [4, 0];
    let (status, message) = render(&glyphs, &inset, &buffers);
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("viewport_origin"), "{message}");

    let mut old = buffers;
    old.struct_size = 8;
    let (status, message) = render(&glyphs, &camera, &old);
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("struct_size is 8"), "{message}");

    // After the refusals the renderer still draws.
    let (status, message) = render(&glyphs, &camera, &buffers);
    assert_eq!(status, EsStatus::Success, "{message}");
    // SAFETY: the renderer is not used again.
    let status = unsafe { es_offscreen_destroy(renderer) };
    assert_eq!(status, EsStatus::Success, "{}", last_error());
}
