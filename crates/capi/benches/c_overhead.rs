//! What the C call path costs over the Rust one: the same host (the test host's device,
//! dynamic rendering target and gpu-allocator), the same million glyphs of about 2 pixels and
//! the same camera, drawn by a renderer through the Rust API and one through the C ABI, frames
//! interleaved; and the upload of the glyphs each way (the C path converts `EsGlyph` records
//! into ellipsoids). Prints medians and ratios.
//!
//! ```sh
//! cargo bench -p ellipsoid-splat-capi --bench c_overhead [-- FRAMES]
//! ```

use std::time::Instant;

use ash::vk;
use ellipsoid_splat::{Camera, EllipsoidRenderer, Pass, RendererOptions, Scene, Target};
use ellipsoid_splat_capi::*;
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_test_host::{DepthKind, Host, HostTarget, TargetKind};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;
const GLYPHS: usize = 1_000_000;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn es(status: EsStatus, what: &str) {
    if status != EsStatus::Success {
        // SAFETY: the library's message pointer is a valid C string until the next failure.
        let message = unsafe { std::ffi::CStr::from_ptr(es_last_error()) };
        panic!("{what}: {status:?}: {message:?}");
    }
}

fn main() {
    let frames: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(15);
    let mut host = Host::new(false).expect("a Vulkan device");
    let target = HostTarget::new(
        &mut host,
        TargetKind::Dynamic,
        DepthKind::ReversedInfinite,
        vk::SampleCountFlags::TYPE_1,
        WIDTH,
        HEIGHT,
    )
    .unwrap();
    let scene = random_cloud(GLYPHS, 7, 40.0, 0.03);
    let (centre, radius) = scene.bounding_sphere().unwrap();
    let camera = Camera::framing(centre, radius, WIDTH, HEIGHT).unwrap();
    let glyphs: Vec<EsGlyph> = scene
        .ellipsoids
        .iter()
        .map(|e| EsGlyph {
            center: e.center.to_array(),
            radii: e.radii.to_array(),
            rotation: [e.rotation.w, e.rotation.x, e.rotation.y, e.rotation.z],
            color: e.color,
        })
        .collect();

    // The Rust renderer, on a gpu-allocator of its own made as the C ABI makes its own (so
    // both start from the same allocator state).
    let pass = Pass::Dynamic {
        color_formats: vec![HostTarget::COLOR_FORMAT],
        depth_format: HostTarget::DEPTH_FORMAT,
    };
    let rust_target = Target::new(pass);
    let features = rust_target
        .required_features()
        .union(if host.int64_atomics() {
            ellipsoid_splat::DeviceFeatures::COMPUTE_SPLAT
        } else {
            ellipsoid_splat::DeviceFeatures::default()
        });
    let handles = host.handles();
    let mut rust_allocator = Allocator::new(&AllocatorCreateDesc {
        instance: handles.instance.clone(),
        device: handles.device.clone(),
        physical_device: handles.physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })
    .unwrap();
    let host_device = ellipsoid_splat::HostDevice::new(
        handles.instance,
        handles.physical_device,
        handles.device,
        handles.queue_family,
        features,
    );
    // SAFETY: the test host's device enables these features; the allocator is on it.
    let mut rust = unsafe {
        EllipsoidRenderer::new(
            &host_device,
            &mut rust_allocator,
            RendererOptions::new(rust_target),
        )
    }
    .unwrap();

    // The C renderer on the same device, with the library's own allocator.
    // SAFETY: loads the system's Vulkan loader for its vkGetInstanceProcAddr.
    let entry = unsafe { ash::Entry::load() }.unwrap();
    let device_info = EsDeviceInfo {
        struct_size: std::mem::size_of::<EsDeviceInfo>() as u32,
        get_instance_proc_addr: Some(entry.static_fn().get_instance_proc_addr),
        instance: host.instance().handle(),
        physical_device: host.physical_device(),
        device: host.device().handle(),
        queue_family_index: host.queue_family(),
        enabled_features: ES_FEATURE_MAINTENANCE4
            | ES_FEATURE_DYNAMIC_RENDERING
            | if host.int64_atomics() {
                ES_FEATURE_SHADER_INT64 | ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS
            } else {
                0
            },
    };
    let color_format = HostTarget::COLOR_FORMAT;
    let target_info = EsTargetInfo {
        struct_size: std::mem::size_of::<EsTargetInfo>() as u32,
        render_pass: vk::RenderPass::null(),
        subpass: 0,
        color_attachment_count: 1,
        color_formats: &color_format,
        depth_format: HostTarget::DEPTH_FORMAT,
        samples: 1,
        aux_outputs: 0,
    };
    let create = EsRendererCreateInfo {
        struct_size: std::mem::size_of::<EsRendererCreateInfo>() as u32,
        device: &device_info,
        target: &target_info,
        allocator: std::ptr::null(),
        settings: std::ptr::null(),
        frames_in_flight: 1,
        pipeline_cache: vk::PipelineCache::null(),
    };
    let mut c: *mut EsRenderer = std::ptr::null_mut();
    // SAFETY: valid create info pointing at live locals; the host's handles outlive it.
    es(
        unsafe { es_renderer_create(&create, &mut c) },
        "es_renderer_create",
    );
    // SAFETY: a valid camera and output.
    let c_camera = {
        let eye = camera.eye.to_array();
        let target = camera.target.to_array();
        let up = camera.up.to_array();
        let mut out = std::mem::MaybeUninit::<EsCamera>::uninit();
        let fov = match camera.projection {
            ellipsoid_splat::Projection::Perspective { fov_y_deg } => fov_y_deg,
            _ => unreachable!("framing makes a perspective camera"),
        };
        // SAFETY: three doubles each and a writable camera.
        es(
            unsafe {
                es_camera_look_at(
                    eye.as_ptr(),
                    target.as_ptr(),
                    up.as_ptr(),
                    fov,
                    camera.near,
                    WIDTH,
                    HEIGHT,
                    out.as_mut_ptr(),
                )
            },
            "es_camera_look_at",
        );
        // SAFETY: written by the successful call.
        unsafe { out.assume_init() }
    };

    // Uploads, interleaved, both from the same raw records (centre, semi-axes, quaternion,
    // colour): a Rust host builds its ellipsoids with `Ellipsoid::new`, the C path converts
    // its `EsGlyph` records the same way inside the call.
    let (mut rust_upload, mut c_upload) = (Vec::new(), Vec::new());
    for k in 0..9 {
        // Alternate which goes first; each frame slot begins as a host's frame would, so the
        // buffers an upload replaces are freed between them.
        for use_c in if k % 2 == 0 {
            [false, true]
        } else {
            [true, false]
        } {
            let start = Instant::now();
            let cmd = host.begin().unwrap();
            if use_c {
                // SAFETY: slot 0 is free (each upload is waited for); recording outside any
                // pass; the glyphs are read during the call.
                unsafe {
                    es(es_renderer_begin_frame(c, 0), "begin_frame");
                    es(
                        es_renderer_upload(c, cmd, glyphs.as_ptr(), glyphs.len()),
                        "es_renderer_upload",
                    );
                }
            } else {
                let rebuilt = Scene::new(
                    glyphs
                        .iter()
                        .map(|g| {
                            let [w, x, y, z] = g.rotation;
                            ellipsoid_splat::Ellipsoid::new(
                                glam::DVec3::from_array(g.center),
                                glam::DVec3::from_array(g.radii),
                                glam::DQuat::from_xyzw(x, y, z, w),
                                Some(g.color),
                            )
                            .unwrap()
                        })
                        .collect(),
                );
                let (device, allocator) = (host.device(), &mut rust_allocator);
                // SAFETY: as above.
                unsafe {
                    rust.begin_frame(device, allocator, 0).unwrap();
                    rust.upload(device, allocator, cmd, &rebuilt).unwrap();
                }
                drop(rebuilt); // as the C call frees its converted records before returning
            }
            host.submit_and_wait().unwrap();
            let ms = start.elapsed().as_secs_f64() * 1e3;
            if use_c {
                c_upload.push(ms)
            } else {
                rust_upload.push(ms)
            }
        }
    }

    // Frames, interleaved, after three warm-up frames each (the still camera's frames).
    let (mut rust_frames, mut c_frames) = (Vec::new(), Vec::new());
    for k in 0..frames + 3 {
        for use_c in [false, true] {
            let start = Instant::now();
            let cmd = host.begin().unwrap();
            let (device, allocator) = (host.device(), &mut rust_allocator);
            // SAFETY: slot 0 is free (each frame is waited for); pre-pass outside the pass,
            // the draw inside the target's pass.
            unsafe {
                if use_c {
                    es(es_renderer_begin_frame(c, 0), "begin_frame");
                    es(
                        es_renderer_record_prepass(c, cmd, &c_camera),
                        "record_prepass",
                    );
                    target.begin_pass(device, cmd);
                    es(es_renderer_record(c, cmd, &c_camera), "record");
                } else {
                    rust.begin_frame(device, allocator, 0).unwrap();
                    rust.record_prepass(device, allocator, cmd, &camera)
                        .unwrap();
                    target.begin_pass(device, cmd);
                    rust.record(device, allocator, cmd, &camera).unwrap();
                }
            }
            target.end_pass(host.device(), cmd);
            host.submit_and_wait().unwrap();
            let ms = start.elapsed().as_secs_f64() * 1e3;
            if k >= 3 {
                if use_c {
                    c_frames.push(ms)
                } else {
                    rust_frames.push(ms)
                }
            }
        }
    }
    let ratios: Vec<f64> = c_frames
        .iter()
        .zip(&rust_frames)
        .map(|(c, r)| c / r)
        .collect();
    println!(
        "{GLYPHS} glyphs at {WIDTH}x{HEIGHT}, {frames} interleaved frames each:\n\
         frame  Rust {:.2} ms  C {:.2} ms  C/Rust median of pairs {:.4}\n\
         upload Rust {:.1} ms  C {:.1} ms  (each from raw records)  C/Rust median of pairs {:.3}",
        median(rust_frames),
        median(c_frames),
        median(ratios),
        median(rust_upload.clone()),
        median(c_upload.clone()),
        median(
            c_upload
                .iter()
                .zip(&rust_upload)
                .map(|(c, r)| c / r)
                .collect()
        ),
    );

    // SAFETY: the GPU is idle; each renderer goes with its own allocator.
    unsafe {
        host.device().device_wait_idle().unwrap();
        es(es_renderer_destroy(c), "es_renderer_destroy");
        rust.destroy(host.device(), &mut rust_allocator);
    }
    target.destroy(&mut host);
}
