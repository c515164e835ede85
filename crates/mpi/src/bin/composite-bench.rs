//! What compositing costs (a benchmark, not a test): COUNT random glyphs split evenly between
//! the ranks, drawn at WIDTHxHEIGHT and composited at rank 0, FRAMES times after one warm-up
//! frame; rank 0 prints, per frame, the slowest rank's drawing time, the slowest rank's
//! compositing time (from all having drawn to the image gathered) and the most bytes a rank
//! sent, then the medians:
//!
//! ```sh
//! mpirun -n 8 target/release/composite-bench 1920x1080 1000000 [FRAMES]
//! ```

use std::process::ExitCode;

use glam::{DQuat, DVec3};
use mpi::collective::SystemOperation;
use mpi::traits::*;

use ellipsoid_splat::Projection;
use ellipsoid_splat::{Camera, ContextOptions, Ellipsoid, OffscreenRenderer, Outputs, Scene};
use ellipsoid_splat_mpi::render_composited;

/// SplitMix64 of `z`, as a number in [0, 1).
fn unit(mut z: u64) -> f64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

fn main() -> ExitCode {
    let Some(universe) = mpi::initialize() else {
        eprintln!("composite-bench: MPI was initialised already");
        return ExitCode::FAILURE;
    };
    let world = universe.world();
    match run(&world) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("composite-bench: rank {}: {e}", world.rank());
            world.abort(1)
        }
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn run<C: Communicator>(world: &C) -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: composite-bench WIDTHxHEIGHT COUNT [FRAMES]";
    let (w, h) = args
        .first()
        .and_then(|s| s.split_once('x'))
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .ok_or(usage)?;
    let count: u64 = args.get(1).and_then(|s| s.parse().ok()).ok_or(usage)?;
    let frames: usize = args
        .get(2)
        .map_or(Ok(5), |s| s.parse())
        .map_err(|_| usage)?;
    let (rank, size) = (world.rank() as u64, world.size() as u64);
    // This rank's contiguous block of the glyphs, in a cube sized for about 2 px glyphs at
    // 1080p seen whole (the benchmark's 1M-glyph cloud).
    let side = (count as f64).cbrt() * 2.0;
    let (first, last) = (count * rank / size, count * (rank + 1) / size);
    let glyphs = (first..last)
        .map(|i| {
            let u = |k: u64| unit(i * 8 + k);
            let centre = (DVec3::new(u(0), u(1), u(2)) - 0.5) * side;
            let radii = DVec3::splat(0.3) + DVec3::new(u(3), u(4), u(5)) * 0.4;
            let q = DQuat::from_xyzw(u(6) - 0.5, u(7) - 0.5, 0.3, 0.6).normalize();
            Ellipsoid::new(centre, radii, q, None)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let part = Scene::new(glyphs);
    let ids: Vec<u32> = (first as u32..last as u32).collect();
    let eye = DVec3::new(0.6, 0.5, 1.4) * side * 1.6;
    let camera = Camera::new(
        eye,
        DVec3::ZERO,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 45.0 },
        side * 0.5,
        w,
        h,
    )?;
    let mut renderer = OffscreenRenderer::new(&ContextOptions::default())?;
    let (mut draws, mut composites) = (Vec::new(), Vec::new());
    for frame in 0..=frames {
        let done = render_composited(world, 0, &mut renderer, &part, &ids, &camera, Outputs::ALL)?;
        let (mut draw, mut composite, mut bytes) = (0.0f64, 0.0f64, 0u64);
        world.all_reduce_into(&done.draw_seconds, &mut draw, SystemOperation::max());
        world.all_reduce_into(
            &done.composite_seconds,
            &mut composite,
            SystemOperation::max(),
        );
        world.all_reduce_into(&done.traffic.bytes, &mut bytes, SystemOperation::max());
        if rank == 0 && frame > 0 {
            println!(
                "frame {frame}: draw {:.1} ms, composite {:.1} ms ({:.0} % of the frame), most bytes sent by a rank {bytes} ({:.2} images)",
                draw * 1e3,
                composite * 1e3,
                100.0 * composite / (draw + composite),
                bytes as f64 / (w as f64 * h as f64 * 32.0)
            );
            draws.push(draw);
            composites.push(composite);
        }
    }
    if rank == 0 {
        let (d, c) = (median(draws), median(composites));
        println!(
            "ranks {size}, {w}x{h}, {count} glyphs: median draw {:.1} ms, composite {:.1} ms ({:.0} % of the frame)",
            d * 1e3,
            c * 1e3,
            100.0 * c / (d + c)
        );
    }
    Ok(())
}
