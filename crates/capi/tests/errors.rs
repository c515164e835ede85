//! Bad input through the C ABI is a status and a message naming what and why -- never a
//! crash: null pointers, too-small `struct_size`, values out of range.

use std::ffi::CStr;

use ash::vk::{self, Handle};
use ellipsoid_splat_capi::*;

fn last_error() -> String {
    // SAFETY: the library keeps a valid C string per thread.
    unsafe { CStr::from_ptr(es_last_error()) }
        .to_string_lossy()
        .into_owned()
}

const EYE: [f64; 3] = [0.0, 0.0, 5.0];
const TARGET: [f64; 3] = [0.0, 0.0, 0.0];
const UP: [f64; 3] = [0.0, 1.0, 0.0];

fn look_at(fov: f64, width: u32, out: *mut EsCamera) -> EsStatus {
    // SAFETY: valid arrays; `out` is null or writable.
    unsafe {
        es_camera_look_at(
            EYE.as_ptr(),
            TARGET.as_ptr(),
            UP.as_ptr(),
            fov,
            0.1,
            width,
            48,
            out,
        )
    }
}

/// `es_target_required_features` of `target`: the status and the bits.
fn required_features(target: &EsTargetInfo) -> (EsStatus, u32) {
    let mut features = 0;
    // SAFETY: valid pointers; the target's handles are only recorded.
    let status = unsafe { es_target_required_features(target, &mut features) };
    (status, features)
}

#[test]
fn bad_arguments_are_named_errors() {
    let mut camera = std::mem::MaybeUninit::<EsCamera>::uninit();
    assert_eq!(look_at(45.0, 64, camera.as_mut_ptr()), EsStatus::Success);
    // SAFETY: written by the successful call.
    let camera = unsafe { camera.assume_init() };
    assert_eq!(
        (camera.width, camera.struct_size as usize),
        (64, std::mem::size_of::<EsCamera>())
    );

    let mut out = camera;
    assert_eq!(look_at(200.0, 64, &mut out), EsStatus::ErrorInvalidArgument);
    assert!(
        last_error().contains("es_camera_look_at") && last_error().contains("fov"),
        "{}",
        last_error()
    );
    assert_eq!(look_at(45.0, 0, &mut out), EsStatus::ErrorInvalidArgument);
    assert!(last_error().contains("image size"), "{}", last_error());
    assert_eq!(
        look_at(45.0, 64, std::ptr::null_mut()),
        EsStatus::ErrorInvalidArgument
    );
    assert!(last_error().contains("out_camera"), "{}", last_error());

    // A view and projection that mirror the image are refused, with the fix named.
    let mirrored: [f32; 16] = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.1, 0.0,
    ];
    let view: [f32; 16] = [
        1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -5.0, 1.0,
    ];
    let viewport = EsViewport {
        x: 0,
        y: 0,
        width: 64,
        height: 48,
    };
    // SAFETY: 16 floats each and a writable camera.
    let status =
        unsafe { es_camera_from_matrices(view.as_ptr(), mirrored.as_ptr(), viewport, &mut out) };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(last_error().contains("mirror"), "{}", last_error());
    // The same with the viewport flipped is a y-up projection drawn right.
    let flipped = EsViewport {
        x: 0,
        y: 48,
        width: 64,
        height: -48,
    };
    // SAFETY: as above.
    let status =
        unsafe { es_camera_from_matrices(view.as_ptr(), mirrored.as_ptr(), flipped, &mut out) };
    assert_eq!(status, EsStatus::Success, "{}", last_error());

    // A renderer call with a null renderer is refused before anything is read.
    let mut settings = std::mem::MaybeUninit::<EsSettings>::uninit();
    // SAFETY: a writable struct.
    let status = unsafe { es_settings_default(settings.as_mut_ptr()) };
    assert_eq!(status, EsStatus::Success);
    let mut plan = std::mem::MaybeUninit::<EsFramePlan>::uninit();
    // SAFETY: a null renderer is refused before anything is read.
    let status = unsafe { es_renderer_plan(std::ptr::null_mut(), &camera, plan.as_mut_ptr()) };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(
        last_error().contains("renderer") && last_error().contains("null"),
        "{}",
        last_error()
    );

    // Option structs: null, or a struct_size below the first version's.
    let color = vk::Format::R8G8B8A8_UNORM;
    let mut target = EsTargetInfo {
        struct_size: 4,
        render_pass: vk::RenderPass::null(),
        subpass: 0,
        color_attachment_count: 1,
        color_formats: &color,
        depth_format: vk::Format::D32_SFLOAT,
        samples: 1,
        aux_outputs: 0,
    };
    assert_eq!(required_features(&target).0, EsStatus::ErrorInvalidArgument);
    assert!(
        last_error().contains("struct_size is 4"),
        "{}",
        last_error()
    );
    target.struct_size = std::mem::size_of::<EsTargetInfo>() as u32;
    assert_eq!(
        required_features(&target),
        (
            EsStatus::Success,
            ES_FEATURE_MAINTENANCE4 | ES_FEATURE_DYNAMIC_RENDERING
        )
    );
    target.samples = 3;
    assert_eq!(required_features(&target).0, EsStatus::ErrorInvalidArgument);
    assert!(last_error().contains("samples"), "{}", last_error());
    target.samples = 4;
    target.render_pass = vk::RenderPass::from_raw(1);
    assert_eq!(
        required_features(&target),
        (
            EsStatus::Success,
            ES_FEATURE_MAINTENANCE4 | ES_FEATURE_SAMPLE_RATE_SHADING
        ),
        "a render pass needs no dynamic rendering"
    );

    let mut renderer: *mut EsRenderer = std::ptr::null_mut();
    // SAFETY: a null create info is refused.
    let status = unsafe { es_renderer_create(std::ptr::null(), &mut renderer) };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(
        renderer.is_null() && last_error().contains("create info"),
        "{}",
        last_error()
    );
    // SAFETY: destroying null is allowed.
    let status = unsafe { es_renderer_destroy(std::ptr::null_mut()) };
    assert_eq!(status, EsStatus::Success);
    assert_eq!(es_abi_version(), ES_ABI_VERSION);
}
