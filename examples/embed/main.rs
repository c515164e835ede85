//! Embedding the ellipsoid renderer in a foreign Vulkan engine.
//!
//! `host.rs` is a stand-in for the engine: its own instance, device, allocator, render target
//! and mesh pipeline, written against `ash` alone. This driver draws the host's meshes (a tilted
//! plane and a cube) into a 4x MSAA render-pass target with reversed infinite depth and writes
//! `embed.png`; it then draws the same scene into every other target flavour (dynamic rendering,
//! standard depth, single sample) as a check. Exits non-zero on any validation message.
//!
//! Run with `cargo run --release --example embed`.

mod host;

use std::path::Path;
use std::process::ExitCode;

use ash::vk;
use glam::{DMat4, DVec3};
use host::{
    cube, reversed_infinite_perspective, standard_finite_perspective, tilted_plane, write_png,
    DepthKind, Host, HostResult, HostTarget, MeshPipeline, TargetKind,
};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 480;

fn main() -> ExitCode {
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Draws every target flavour; returns whether all drew and validation stayed silent.
fn run() -> HostResult<bool> {
    let mut host = Host::new(true)?;
    let mut ok = true;
    for kind in [TargetKind::RenderPass, TargetKind::Dynamic] {
        for depth in [DepthKind::ReversedInfinite, DepthKind::StandardFinite] {
            for samples in [vk::SampleCountFlags::TYPE_4, vk::SampleCountFlags::TYPE_1] {
                let rgba = draw(&mut host, kind, depth, samples)?;
                let showcase = kind == TargetKind::RenderPass
                    && depth == DepthKind::ReversedInfinite
                    && samples == vk::SampleCountFlags::TYPE_4;
                if showcase {
                    write_png(Path::new("embed.png"), WIDTH, HEIGHT, &rgba)?;
                    println!("wrote embed.png");
                }
                // The camera looks at the cube: the centre pixel must not be the clear colour.
                let centre = ((HEIGHT / 2 * WIDTH + WIDTH / 2) * 4) as usize;
                let pixel = &rgba[centre..centre + 4];
                let drew = pixel != [0, 0, 0, 255];
                println!("{kind:?} {depth:?} {samples:?}: centre pixel {pixel:?}");
                ok &= drew;
            }
        }
    }
    let messages = host.messages();
    for message in &messages {
        eprintln!("validation: {message}");
    }
    println!("{} validation message(s)", messages.len());
    Ok(ok && messages.is_empty())
}

/// One frame: create a target and a mesh pipeline, record, submit, read back, clean up.
fn draw(
    host: &mut Host,
    kind: TargetKind,
    depth: DepthKind,
    samples: vk::SampleCountFlags,
) -> HostResult<Vec<u8>> {
    let target = HostTarget::new(host, kind, depth, samples, WIDTH, HEIGHT)?;
    let mut vertices = tilted_plane(
        DVec3::new(0.0, -0.8, 0.0),
        DVec3::new(0.2, 1.0, 0.3),
        2.5,
        [0.2, 0.4, 0.8],
    );
    vertices.extend(cube(DVec3::ZERO, 0.6, true));
    let mesh = MeshPipeline::new(host, &target, &vertices)?;

    let fov_y = 50f64.to_radians();
    let aspect = f64::from(WIDTH) / f64::from(HEIGHT);
    let projection = match depth {
        DepthKind::ReversedInfinite => reversed_infinite_perspective(fov_y, aspect, 0.1),
        DepthKind::StandardFinite => standard_finite_perspective(fov_y, aspect, 0.1, 100.0),
    };
    let view = DMat4::look_at_rh(DVec3::new(3.0, 2.2, 4.0), DVec3::ZERO, DVec3::Y);

    let cmd = host.begin()?;
    target.begin_pass(host.device(), cmd);
    mesh.record(host.device(), cmd, projection * view);
    // The embedded ellipsoid renderer records its draw here, into the same pass.
    target.end_pass(host.device(), cmd);
    host.submit_and_wait()?;
    let rgba = target.read_rgba()?;

    mesh.destroy(host);
    target.destroy(host);
    Ok(rgba)
}
