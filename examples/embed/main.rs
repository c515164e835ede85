//! Embedding ellipsoid-splat in a host Vulkan engine.
//!
//! The engine is `ellipsoid-splat-test-host` (`crates/test-host`), written against `ash` alone:
//! its own instance and device (with the renderer's required features enabled), allocator, a 4x
//! multisampled render pass with a resolve attachment, a pipeline cache and a mesh pipeline.
//! This program draws the engine's meshes (a tilted plane and a cube) and ellipsoids cutting
//! through them in the same subpass, over three animated frames in two frame slots, resolves,
//! and writes `embed.png`. It exits non-zero on any validation message.
//!
//! ```sh
//! cargo run --release --example embed            # validation on, writes embed.png
//! cargo run --release --example embed -- --bench # cost of 4x MSAA against 1 sample
//! ```

use std::path::Path;
use std::process::ExitCode;
use std::time::Instant;

use ash::vk;
use ellipsoid_splat::{
    Camera, Ellipsoid, EllipsoidRenderer, HostDevice, Pass, RendererOptions, Scene, Settings,
    Target,
};
use ellipsoid_splat_loaders::random_cloud;
use ellipsoid_splat_test_host::{
    cube, reversed_infinite_perspective, tilted_plane, write_png, DepthKind, Host, HostTarget,
    MeshPipeline, MeshVertex, TargetKind,
};
use glam::{DMat4, DQuat, DVec3};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;
/// The renderer may be a frame ahead of the GPU (this host waits every frame anyway).
const FRAMES_IN_FLIGHT: u32 = 2;
/// How many of [`ellipsoids`] form the animated ring.
const RING: usize = 24;

fn main() -> ExitCode {
    let bench = std::env::args().any(|a| a == "--bench");
    match if bench { run_bench() } else { run() } {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The host's view of a `target`: looking at the cube from above and to the side, with a
/// reversed-Z, infinite-far-plane projection.
fn view_and_projection(target: &HostTarget) -> (DMat4, DMat4) {
    let view = DMat4::look_at_rh(DVec3::new(3.0, 2.2, 4.0), DVec3::ZERO, DVec3::Y);
    let extent = target.extent();
    let aspect = f64::from(extent.width) / f64::from(extent.height);
    let projection = reversed_infinite_perspective(50f64.to_radians(), aspect, 0.1);
    (view, projection)
}

/// The host's meshes: a blue tilted plane and, if asked, a cube with a grey per face.
fn meshes(with_cube: bool) -> Vec<MeshVertex> {
    let normal = DVec3::new(0.2, 1.0, 0.3);
    let mut vertices = tilted_plane(DVec3::new(0.0, -0.8, 0.0), normal, 2.5, [0.2, 0.4, 0.8]);
    if with_cube {
        vertices.extend(cube(DVec3::ZERO, 0.6, true));
    }
    vertices
}

/// A ring of [`RING`] ellipsoids turned by `turn` through the plane and around the cube, and
/// one piercing the cube.
fn ellipsoids(turn: f64) -> Result<Vec<Ellipsoid>> {
    let mut out = Vec::new();
    for k in 0..RING {
        let angle = turn + k as f64 * std::f64::consts::TAU / RING as f64;
        let center = DVec3::new(1.5 * angle.cos(), -0.75, 1.5 * angle.sin());
        let rotation = DQuat::from_rotation_y(-angle) * DQuat::from_rotation_x(0.5);
        let hue = std::f32::consts::TAU * (k as f32 / RING as f32);
        let color = [0.5 + 0.5 * hue.cos(), 0.4, 0.5 + 0.5 * hue.sin()];
        let radii = DVec3::new(0.15, 0.3, 0.12);
        out.push(Ellipsoid::new(center, radii, rotation, Some(color))?);
    }
    let piercing = DQuat::from_rotation_z(0.6) * DQuat::from_rotation_y(0.3);
    let (center, radii) = (DVec3::splat(0.5), DVec3::new(0.9, 0.25, 0.25));
    out.push(Ellipsoid::new(
        center,
        radii,
        piercing,
        Some([0.95, 0.75, 0.2]),
    )?);
    Ok(out)
}

/// The renderer for the host's device, drawing into subpass 0 of `target`'s render pass.
fn renderer_for(
    host: &mut Host,
    target: &HostTarget,
    pipeline_cache: vk::PipelineCache,
    settings: Settings,
) -> Result<EllipsoidRenderer> {
    // One colour attachment (the resolve attachment is not a colour attachment).
    let mut drawn_into = Target::new(Pass::RenderPass {
        render_pass: target.render_pass(),
        subpass: 0,
        color_attachment_count: 1,
        depth_format: HostTarget::DEPTH_FORMAT,
    });
    drawn_into.samples = target.samples();
    // What this host's device enables of the renderer's features: the target's (a render
    // pass, so dynamic rendering only because the host has it anyway); not the 64-bit atomics
    // the compute splat needs.
    let mut enabled = drawn_into.required_features();
    enabled.dynamic_rendering = true;
    enabled.sample_rate_shading = true;
    let host = host.handles();
    let device = HostDevice::new(
        host.instance,
        host.physical_device,
        host.device,
        host.queue_family,
        enabled,
    );
    let mut options = RendererOptions::new(drawn_into);
    options.frames_in_flight = FRAMES_IN_FLIGHT;
    options.pipeline_cache = pipeline_cache;
    options.settings = settings;
    // SAFETY: the host's handles belong together, its device enables the features `enabled`
    // names, and the render pass and pipeline cache outlive the renderer (the callers destroy
    // both after it).
    Ok(unsafe { EllipsoidRenderer::new(&device, host.allocator, options) }?)
}

/// What a frame changes in the renderer's instances.
enum Change<'a> {
    /// A whole new scene.
    Upload(&'a Scene),
    /// Instances `0..n` replaced.
    Update(&'a [Ellipsoid]),
    /// Nothing.
    Keep,
}

/// Records frame `frame` into the host's command buffer, for the caller to submit: the
/// instance change and the culling pre-pass outside the pass, then the host's meshes and the
/// ellipsoids inside it.
fn record_frame(
    host: &mut Host,
    target: &HostTarget,
    mesh: &MeshPipeline,
    renderer: &mut EllipsoidRenderer,
    frame: u32,
    change: Change,
) -> Result<()> {
    let (view, projection) = view_and_projection(target);
    // The host's own matrices (reversed Z, infinite far plane) become the renderer's camera.
    let extent = target.extent();
    let camera = Camera::from_view_projection(view, projection, extent.width, extent.height)?;
    let cmd = host.begin()?;
    let (device, allocator) = host.device_and_allocator();
    // SAFETY: `cmd` is recording; the instance change and the pre-pass go before the pass,
    // the draw inside the host's subpass; the host waits for each frame before starting the
    // next, so the slot's earlier work is complete when it begins again.
    unsafe {
        renderer.begin_frame(device, allocator, frame % FRAMES_IN_FLIGHT)?;
        match change {
            Change::Upload(scene) => renderer.upload(device, allocator, cmd, scene)?,
            Change::Update(first) => renderer.update(device, allocator, cmd, 0, first)?,
            Change::Keep => {}
        }
        renderer.record_prepass(device, allocator, cmd, &camera)?;
        target.begin_pass(device, cmd);
        mesh.record(device, cmd, projection * view);
        renderer.record(device, allocator, cmd, &camera)?;
        target.end_pass(device, cmd);
    }
    Ok(())
}

/// Draws three animated frames with validation on and writes the last to `embed.png`.
fn run() -> Result<bool> {
    let mut host = Host::new(true)?;
    let samples = vk::SampleCountFlags::TYPE_4;
    let (kind, depth) = (TargetKind::RenderPass, DepthKind::ReversedInfinite);
    let target = HostTarget::new(&mut host, kind, depth, samples, WIDTH, HEIGHT)?;
    let mesh = MeshPipeline::new(&mut host, &target, &meshes(true))?;
    let cache_info = vk::PipelineCacheCreateInfo::default();
    // SAFETY: valid create info; the cache is destroyed below, after the renderer.
    let cache = unsafe { host.device().create_pipeline_cache(&cache_info, None) }?;
    let mut renderer = renderer_for(&mut host, &target, cache, Settings::default())?;
    let scene = Scene::new(ellipsoids(0.0)?);
    for frame in 0..3 {
        // Animate: turn the ring (instances 0..RING), keep the piercing ellipsoid.
        let ring = ellipsoids(0.1 * f64::from(frame))?;
        let change = match frame {
            0 => Change::Upload(&scene),
            _ => Change::Update(&ring[..RING]),
        };
        record_frame(&mut host, &target, &mesh, &mut renderer, frame, change)?;
        host.submit_and_wait()?;
    }
    write_png(Path::new("embed.png"), WIDTH, HEIGHT, &target.read_rgba()?)?;
    println!("wrote embed.png ({WIDTH}x{HEIGHT}, 4x MSAA resolved)");

    let (device, allocator) = host.device_and_allocator();
    // SAFETY: every frame was waited for; the renderer destroys only what it created.
    unsafe {
        renderer.destroy(device, allocator);
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

/// Times two scenes over the host's plane at 1280x720 -- 20,000 random ellipsoids, and the
/// 64,000-glyph tensor field scaled into the same view -- with 1 sample per pixel, and with 4
/// shaded once per pixel (the default) and once per sample (validation off): the three
/// interleaved frame by frame, 3 warm-up frames each, then the median submit-to-fence time of
/// 31 frames each.
fn run_bench() -> Result<bool> {
    let mut host = Host::new(false)?;
    let field = ellipsoid_splat_loaders::tensor_field(40);
    let (centre, radius) = field.bounding_sphere().ok_or("empty tensor field")?;
    let fitted = field
        .ellipsoids
        .iter()
        .map(|e| {
            let s = 2.0 / radius;
            Ellipsoid::new(
                (e.center - centre) * s,
                e.radii * s,
                e.rotation,
                Some(e.color),
            )
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let scenes = [
        (
            "20,000 random ellipsoids",
            random_cloud(20_000, 5, 2.0, 0.12),
        ),
        ("the tensor field (64,000)", Scene::new(fitted)),
    ];
    let variants = [
        ("1 sample", vk::SampleCountFlags::TYPE_1, false),
        (
            "4 samples, shaded per pixel",
            vk::SampleCountFlags::TYPE_4,
            false,
        ),
        (
            "4 samples, shaded per sample",
            vk::SampleCountFlags::TYPE_4,
            true,
        ),
    ];
    let (kind, depth) = (TargetKind::RenderPass, DepthKind::ReversedInfinite);
    for (scene_name, scene) in &scenes {
        let mut setups = Vec::new();
        for (_, samples, per_sample_shading) in variants {
            let target = HostTarget::new(&mut host, kind, depth, samples, 1280, 720)?;
            let mesh = MeshPipeline::new(&mut host, &target, &meshes(false))?;
            let settings = {
                let mut settings = Settings::default();
                settings.per_sample_shading = per_sample_shading;
                settings
            };
            let renderer = renderer_for(&mut host, &target, vk::PipelineCache::null(), settings)?;
            setups.push((target, mesh, renderer, Vec::new()));
        }
        for frame in 0..34u32 {
            for (target, mesh, renderer, times) in &mut setups {
                let change = match frame {
                    0 => Change::Upload(scene),
                    _ => Change::Keep,
                };
                record_frame(&mut host, target, mesh, renderer, frame, change)?;
                let start = Instant::now();
                host.submit_and_wait()?;
                if frame >= 3 {
                    times.push(start.elapsed().as_secs_f64() * 1e3);
                }
            }
        }
        let mut medians = Vec::new();
        for ((name, ..), (target, mesh, renderer, mut times)) in variants.into_iter().zip(setups) {
            times.sort_by(f64::total_cmp);
            let median = times[times.len() / 2];
            println!(
                "{scene_name}, {name}: median {median:.1} ms per frame ({} frames)",
                times.len()
            );
            medians.push(median);
            let (device, allocator) = host.device_and_allocator();
            // SAFETY: every frame was waited for.
            unsafe { renderer.destroy(device, allocator) };
            mesh.destroy(&mut host);
            target.destroy(&mut host);
        }
        println!(
            "{scene_name}: 4x MSAA costs {:.2}x the single-sample frame shaded per pixel, {:.2}x \
             shaded per sample",
            medians[1] / medians[0],
            medians[2] / medians[0]
        );
    }
    Ok(true)
}
