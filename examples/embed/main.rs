//! Embedding ellipsoid-splat in a host Vulkan engine.
//!
//! `host.rs` stands in for the engine: its own instance, device (with the renderer's required
//! features enabled), allocator, 4x multisampled render pass with a resolve attachment, and a
//! mesh pipeline -- written against `ash` alone. This program draws the host's meshes (a tilted
//! plane and a cube) and ellipsoids that cut through them in the same subpass, resolves, and
//! writes `embed.png`. It exits non-zero on any validation message.
//!
//! ```sh
//! cargo run --release --example embed            # validation on, writes embed.png
//! cargo run --release --example embed -- --bench # cost of 4x MSAA against 1 sample
//! ```

use ellipsoid_splat_test_host as host;

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use ash::vk;
use ellipsoid_splat::renderer::{EllipsoidRenderer, HostDevice, Pass, RendererOptions, Target};
use ellipsoid_splat::{Camera, Ellipsoid, Scene};
use ellipsoid_splat_loaders::random_cloud;
use glam::{DMat4, DQuat, DVec3};
use host::{
    cube, reversed_infinite_perspective, tilted_plane, write_png, DepthKind, Host, HostResult,
    HostTarget, MeshPipeline, TargetKind,
};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
/// The renderer may be a frame ahead of the GPU (this host waits every frame anyway).
const FRAMES_IN_FLIGHT: u32 = 2;

fn main() -> ExitCode {
    let bench = std::env::args().any(|a| a == "--bench");
    let result = if bench { run_bench() } else { run() };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The host's view: a camera looking at the cube from above and to the side.
fn view_and_projection(width: u32, height: u32) -> (DMat4, DMat4) {
    let view = DMat4::look_at_rh(DVec3::new(3.0, 2.2, 4.0), DVec3::ZERO, DVec3::Y);
    let aspect = f64::from(width) / f64::from(height);
    (
        view,
        reversed_infinite_perspective(50f64.to_radians(), aspect, 0.1),
    )
}

/// A ring of ellipsoids through the plane and around the cube, and one piercing the cube.
fn ellipsoids(turn: f64) -> ellipsoid_splat::Result<Vec<Ellipsoid>> {
    let mut out = Vec::new();
    for k in 0..24 {
        let angle = turn + k as f64 * std::f64::consts::TAU / 24.0;
        let center = DVec3::new(1.5 * angle.cos(), -0.75, 1.5 * angle.sin());
        let rotation = DQuat::from_rotation_y(-angle) * DQuat::from_rotation_x(0.5);
        let hue = k as f32 / 24.0;
        let color = [
            0.5 + 0.5 * (std::f32::consts::TAU * hue).cos(),
            0.4,
            0.5 + 0.5 * (std::f32::consts::TAU * hue).sin(),
        ];
        let radii = DVec3::new(0.15, 0.3, 0.12);
        out.push(Ellipsoid::new(center, radii, rotation, Some(color))?);
    }
    let piercing = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_y(0.3);
    let color = Some([0.95, 0.75, 0.2]);
    out.push(Ellipsoid::new(
        DVec3::new(0.5, 0.5, 0.5),
        DVec3::new(0.9, 0.25, 0.25),
        piercing,
        color,
    )?);
    Ok(out)
}

/// The renderer for the host's device and target.
fn renderer_for(
    host: &mut Host,
    target: &HostTarget,
    pipeline_cache: vk::PipelineCache,
) -> HostResult<EllipsoidRenderer> {
    let (instance, device) = (host.instance().clone(), host.device().clone());
    let handles = HostDevice {
        instance: &instance,
        physical_device: host.physical_device(),
        device: &device,
        queue_family_index: host.queue_family(),
    };
    let options = RendererOptions {
        target: Target {
            // The host's render pass, subpass 0: one colour attachment and a depth attachment.
            pass: Pass::RenderPass {
                render_pass: target.render_pass(),
                subpass: 0,
                color_attachment_count: 1,
                depth_format: HostTarget::DEPTH_FORMAT,
            },
            samples: target.samples(),
            aux_outputs: false,
        },
        frames_in_flight: FRAMES_IN_FLIGHT,
        pipeline_cache,
        settings: Default::default(),
    };
    // SAFETY: the host's handles belong together, its device enables the features of
    // `ellipsoid_splat::features::required_device_features`, and the render pass and pipeline
    // cache outlive the renderer (both are destroyed after it, below).
    unsafe { EllipsoidRenderer::new(&handles, host.allocator_mut(), options) }
        .map_err(|e| e.to_string())
}

/// Records one frame into the host's command buffer: the instance upload (first frame) or an
/// update (later frames) and the culling pre-pass outside the pass, then the host's meshes and
/// the ellipsoids inside it.
fn record_frame(
    host: &mut Host,
    target: &HostTarget,
    mesh: &MeshPipeline,
    renderer: &mut EllipsoidRenderer,
    frame: u32,
    scene: &Scene,
) -> HostResult<()> {
    let (view, projection) = view_and_projection(WIDTH, HEIGHT);
    // The host's own matrices (reversed Z, infinite far plane) become the renderer's camera.
    let camera =
        Camera::from_view_projection(view, projection, WIDTH, HEIGHT).map_err(|e| e.to_string())?;
    let cmd = host.begin()?;
    let device = host.device().clone();
    let allocator = host.allocator_mut();
    let err = |e: ellipsoid_splat::Error| e.to_string();
    // SAFETY: `cmd` is recording; the upload and pre-pass go before the pass, the draw inside
    // the host's subpass; the host waits for each frame before starting the next, so the
    // slot's earlier work is complete when it begins again.
    unsafe {
        renderer
            .begin_frame(&device, allocator, frame % FRAMES_IN_FLIGHT)
            .map_err(err)?;
        if frame == 0 {
            renderer
                .upload(&device, allocator, cmd, scene)
                .map_err(err)?;
        } else {
            // Animate: replace the ring (instances 0..24), keep the piercing ellipsoid.
            let ring = ellipsoids(0.1 * frame as f64).map_err(err)?;
            renderer
                .update(&device, allocator, cmd, 0, &ring[..24])
                .map_err(err)?;
        }
        renderer
            .record_prepass(&device, allocator, cmd, &camera)
            .map_err(err)?;
        target.begin_pass(&device, cmd);
        mesh.record(&device, cmd, projection * view);
        renderer
            .record(&device, allocator, cmd, &camera)
            .map_err(err)?;
        target.end_pass(&device, cmd);
    }
    host.submit_and_wait()
}

/// Draws three animated frames with validation on and writes the last to `embed.png`.
fn run() -> HostResult<bool> {
    let mut host = Host::new(true)?;
    let target = HostTarget::new(
        &mut host,
        TargetKind::RenderPass,
        DepthKind::ReversedInfinite,
        vk::SampleCountFlags::TYPE_4,
        WIDTH,
        HEIGHT,
    )?;
    let mut vertices = tilted_plane(
        DVec3::new(0.0, -0.8, 0.0),
        DVec3::new(0.2, 1.0, 0.3),
        2.5,
        [0.2, 0.4, 0.8],
    );
    vertices.extend(cube(DVec3::ZERO, 0.6, true));
    let mesh = MeshPipeline::new(&mut host, &target, &vertices)?;
    let cache_info = vk::PipelineCacheCreateInfo::default();
    // SAFETY: valid create info; the host owns the cache and destroys it after the renderer.
    let cache = unsafe { host.device().create_pipeline_cache(&cache_info, None) }
        .map_err(|e| format!("vkCreatePipelineCache failed: {e}"))?;
    let mut renderer = renderer_for(&mut host, &target, cache)?;
    let scene = Scene::new(ellipsoids(0.0).map_err(|e| e.to_string())?);
    for frame in 0..3 {
        record_frame(&mut host, &target, &mesh, &mut renderer, frame, &scene)?;
    }
    write_png(Path::new("embed.png"), WIDTH, HEIGHT, &target.read_rgba()?)?;
    println!("wrote embed.png ({WIDTH}x{HEIGHT}, 4x MSAA resolved)");

    let device = host.device().clone();
    // SAFETY: every frame was waited for; the renderer destroys only what it created.
    unsafe {
        renderer.destroy(&device, host.allocator_mut());
        device.destroy_pipeline_cache(cache, None);
    }
    mesh.destroy(&mut host);
    target.destroy(&mut host);
    let messages = host.messages();
    for message in &messages {
        eprintln!("validation: {message}");
    }
    println!("{} validation message(s)", messages.len());
    Ok(messages.is_empty())
}

/// Times 20,000 ellipsoids over the host's plane at 1280x720 with 1 and 4 samples per pixel
/// (validation off): median submit-to-fence time of 15 frames after 3 warm-up frames each.
fn run_bench() -> HostResult<bool> {
    const W: u32 = 1280;
    const H: u32 = 720;
    let mut host = Host::new(false)?;
    let scene = random_cloud(20_000, 5, 2.0, 0.12);
    let (view, projection) = view_and_projection(W, H);
    let camera = Camera::from_view_projection(view, projection, W, H).map_err(|e| e.to_string())?;
    let mut medians = Vec::new();
    for samples in [vk::SampleCountFlags::TYPE_1, vk::SampleCountFlags::TYPE_4] {
        let target = HostTarget::new(
            &mut host,
            TargetKind::RenderPass,
            DepthKind::ReversedInfinite,
            samples,
            W,
            H,
        )?;
        let plane = tilted_plane(
            DVec3::new(0.0, -0.8, 0.0),
            DVec3::new(0.2, 1.0, 0.3),
            2.5,
            [0.2, 0.4, 0.8],
        );
        let mesh = MeshPipeline::new(&mut host, &target, &plane)?;
        let mut renderer = renderer_for(&mut host, &target, vk::PipelineCache::null())?;
        let device = host.device().clone();
        let err = |e: ellipsoid_splat::Error| e.to_string();
        let mut times = Vec::new();
        for frame in 0..18u32 {
            let cmd = host.begin()?;
            let allocator = host.allocator_mut();
            // SAFETY: as in `record_frame`.
            unsafe {
                renderer
                    .begin_frame(&device, allocator, frame % FRAMES_IN_FLIGHT)
                    .map_err(err)?;
                if frame == 0 {
                    renderer
                        .upload(&device, allocator, cmd, &scene)
                        .map_err(err)?;
                }
                renderer
                    .record_prepass(&device, allocator, cmd, &camera)
                    .map_err(err)?;
                target.begin_pass(&device, cmd);
                mesh.record(&device, cmd, projection * view);
                renderer
                    .record(&device, allocator, cmd, &camera)
                    .map_err(err)?;
                target.end_pass(&device, cmd);
            }
            let start = Instant::now();
            host.submit_and_wait()?;
            if frame >= 3 {
                times.push(start.elapsed().as_secs_f64() * 1e3);
            }
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        println!(
            "{samples:?}: median {median:.1} ms per frame ({} frames)",
            times.len()
        );
        medians.push(median);
        // SAFETY: every frame was waited for.
        unsafe { renderer.destroy(&device, host.allocator_mut()) };
        mesh.destroy(&mut host);
        target.destroy(&mut host);
    }
    println!(
        "4x MSAA with per-sample shading costs {:.2}x the single-sample frame",
        medians[1] / medians[0]
    );
    Ok(true)
}
