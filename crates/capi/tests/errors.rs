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

/// `es_renderer_create` with `settings` and handles that are all null: the settings are
/// checked first, so a bad one is what the call names.
fn create_with(settings: &EsSettings) -> (EsStatus, String) {
    let color = vk::Format::R8G8B8A8_UNORM;
    let target = EsTargetInfo {
        struct_size: std::mem::size_of::<EsTargetInfo>() as u32,
        render_pass: vk::RenderPass::null(),
        subpass: 0,
        color_attachment_count: 1,
        color_formats: &color,
        depth_format: vk::Format::D32_SFLOAT,
        samples: 1,
        aux_outputs: 0,
    };
    let device = EsDeviceInfo {
        struct_size: std::mem::size_of::<EsDeviceInfo>() as u32,
        get_instance_proc_addr: None,
        instance: vk::Instance::null(),
        physical_device: vk::PhysicalDevice::null(),
        device: vk::Device::null(),
        queue_family_index: 0,
        enabled_features: 0,
    };
    let info = EsRendererCreateInfo {
        struct_size: std::mem::size_of::<EsRendererCreateInfo>() as u32,
        device: &device,
        target: &target,
        allocator: std::ptr::null(),
        settings,
        frames_in_flight: 1,
        pipeline_cache: vk::PipelineCache::null(),
    };
    let mut renderer: *mut EsRenderer = std::ptr::null_mut();
    // SAFETY: valid structs; the null device is refused before any handle is used.
    let status = unsafe { es_renderer_create(&info, &mut renderer) };
    assert!(renderer.is_null());
    (status, last_error())
}

#[test]
fn settings_name_a_known_plan_mode_and_path() {
    let mut settings = std::mem::MaybeUninit::<EsSettings>::uninit();
    // SAFETY: a writable struct.
    let status = unsafe { es_settings_default(settings.as_mut_ptr()) };
    assert_eq!(status, EsStatus::Success);
    // SAFETY: written by the successful call.
    let defaults = unsafe { settings.assume_init() };
    assert_eq!(
        defaults.struct_size as usize,
        std::mem::size_of::<EsSettings>()
    );
    assert_eq!(defaults.plan_mode, EsPlanMode::Measure as u32);
    assert_eq!(defaults.fixed_path, EsPathKind::None as u32);

    // Good settings pass, and the null device is what the call then names.
    let (status, message) = create_with(&defaults);
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("get_instance_proc_addr"), "{message}");

    let cases = [
        (
            7,
            EsPathKind::None as u32,
            1,
            "EsSettings.plan_mode: 7 is not an EsPlanMode",
        ),
        (
            EsPlanMode::Fixed as u32,
            EsPathKind::None as u32,
            1,
            "EsSettings.fixed_path",
        ),
        (
            EsPlanMode::Fixed as u32,
            42,
            1,
            "EsSettings.fixed_path: 42 is not an EsPathKind",
        ),
        (
            EsPlanMode::Measure as u32,
            42,
            1,
            "EsSettings.fixed_path: 42",
        ),
        (
            EsPlanMode::Fixed as u32,
            EsPathKind::Splat as u32,
            0,
            "EsSettings.compute_splat",
        ),
    ];
    for (plan_mode, fixed_path, compute_splat, words) in cases {
        let mut bad = defaults;
        bad.plan_mode = plan_mode;
        bad.fixed_path = fixed_path;
        bad.compute_splat = compute_splat;
        let (status, message) = create_with(&bad);
        assert_eq!(status, EsStatus::ErrorInvalidArgument, "{message}");
        assert!(
            message.contains("es_renderer_create") && message.contains(words),
            "{words}: {message}"
        );
    }

    // A first-version struct (52 bytes) is read as such: what lies beyond it is not the
    // host's and is never looked at.
    let mut first = defaults;
    first.struct_size = 52;
    first.plan_mode = 0xdead_beef;
    first.fixed_path = 0xdead_beef;
    let (status, message) = create_with(&first);
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    assert!(message.contains("get_instance_proc_addr"), "{message}");
    first.struct_size = 48;
    let (_, message) = create_with(&first);
    assert!(message.contains("struct_size is 48"), "{message}");
}

#[test]
fn the_plan_and_wisdom_calls_refuse_a_null_renderer() {
    let mut plan = std::mem::MaybeUninit::<EsFramePlan>::uninit();
    let mut size = 0usize;
    let bytes = [0u8; 8];
    // SAFETY: each call refuses the null renderer before reading anything else.
    let statuses = unsafe {
        [
            (
                es_renderer_last_plan(std::ptr::null_mut(), plan.as_mut_ptr()),
                "es_renderer_last_plan",
            ),
            (
                es_renderer_plan_wisdom(std::ptr::null_mut(), std::ptr::null_mut(), &mut size),
                "es_renderer_plan_wisdom",
            ),
            (
                es_renderer_load_plan_wisdom(std::ptr::null_mut(), bytes.as_ptr(), bytes.len()),
                "es_renderer_load_plan_wisdom",
            ),
            (
                es_renderer_can_measure(std::ptr::null_mut(), std::ptr::null_mut()),
                "es_renderer_can_measure",
            ),
        ]
    };
    for (status, function) in statuses {
        assert_eq!(status, EsStatus::ErrorInvalidArgument, "{function}");
    }
    // The message is the last call's.
    assert!(
        last_error().contains("es_renderer_can_measure") && last_error().contains("null"),
        "{}",
        last_error()
    );
}
