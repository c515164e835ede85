//! `render` split between the processes of a communicator: every process checks the flags,
//! opens its device, reads its share of the scene (its byte range or records of the file:
//! [`load_share`]) and draws it with the camera framing the whole scene (bounds reduced over
//! the processes); the frames are composited at rank 0, which writes the images as
//! one-process `render` writes them. Each step that can fail on one process is agreed on
//! ([`agree`]) before any process waits on another.

use std::time::{Duration, Instant};

use glam::DVec3;
use mpi::collective::SystemOperation;
use mpi::traits::*;

use ellipsoid_splat::{supersample, Frame, Scene};
use ellipsoid_splat_loaders::{load_share, LoadedShare, Split};
use ellipsoid_splat_mpi::render_composited;
use ellipsoid_splat_tool::camera_setup;
use ellipsoid_splat_tool::cli::{RenderArgs, RenderPlan, SceneSpec};
use ellipsoid_splat_tool::mpi_flags::check_distributable;
use ellipsoid_splat_tool::output::{self, Image};
use ellipsoid_splat_tool::render_device;
use ellipsoid_splat_tool::scene_io;

use crate::agree::agree;
use crate::error::Result;
use crate::exchange::MpiExchange;

/// The rank that writes the images.
const ROOT: i32 = 0;

/// The plan of `args`, checked: the root also checks the output files it will write.
fn checked_plan(args: &RenderArgs, at_root: bool) -> Result<RenderPlan> {
    check_distributable(args)?;
    Ok(if at_root {
        args.check()?
    } else {
        RenderPlan {
            scene: args.check_scene()?,
            outputs: args.outputs(),
        }
    })
}

/// This process's share of the scene: of a file, its part (every process reading together);
/// of a generated scene, its range of the glyphs (each makes the whole).
fn read_share<C: Communicator>(
    comm: &C,
    args: &RenderArgs,
    scene: &SceneSpec,
) -> Result<LoadedShare> {
    let mut options = args.load.options();
    // One bar per process would garble a terminal.
    options.progress = false;
    let (rank, size) = (comm.rank() as usize, comm.size() as usize);
    let mut share = match scene {
        SceneSpec::File(path) => load_share(path, &options, &MpiExchange::new(comm))?,
        generated => {
            let made = scene_io::load(generated, &options)
                .and_then(|loaded| Ok(LoadedShare::of_whole(loaded, rank, size)?));
            agree(comm, made.map_err(Into::into))?
        }
    };
    args.load.color_mode().apply(&mut share.scene.ellipsoids);
    Ok(share)
}

/// The bounds of every process's `part` together (`None` when all are empty): exact, as
/// minima and maxima are.
fn whole_bounds<C: Communicator>(comm: &C, part: &Scene) -> Option<(DVec3, DVec3)> {
    let (lo, hi) = part
        .bounds()
        .unwrap_or((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)));
    let (mut low, mut high) = ([0.0f64; 3], [0.0f64; 3]);
    comm.all_reduce_into(&lo.to_array()[..], &mut low[..], SystemOperation::min());
    comm.all_reduce_into(&hi.to_array()[..], &mut high[..], SystemOperation::max());
    (low[0] <= high[0]).then(|| (DVec3::from(low), DVec3::from(high)))
}

/// The least and greatest of every process's `seconds`, in milliseconds.
fn spread<C: Communicator>(comm: &C, seconds: f64) -> (f64, f64) {
    let (mut least, mut most) = (0.0f64, 0.0f64);
    comm.all_reduce_into(&seconds, &mut least, SystemOperation::min());
    comm.all_reduce_into(&seconds, &mut most, SystemOperation::max());
    (least * 1e3, most * 1e3)
}

/// Writes every image `args` asks for of `frame` (drawn `k` times larger), as `render` does.
fn write_images(args: &RenderArgs, plan: &RenderPlan, frame: &Frame, k: u32) -> Result<()> {
    let frame = if k > 1 {
        supersample::box_filter(frame, k)?
    } else {
        frame.clone()
    };
    for image in Image::all_in(plan.outputs) {
        if let Some(path) = args.file(image) {
            output::write_image(&frame, image, path)?;
        }
    }
    Ok(())
}

/// This process's CPU time so far (user and system, every thread), where Linux's
/// `/proc/self/stat` gives it: what reading cost apart from waiting for a core, on a machine
/// shared with other work.
fn cpu_time() -> Option<Duration> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // After the command's name in parentheses, fields 3, 4, ...: utime and stime are the 14th
    // and 15th, in clock ticks of 1/100 s (Linux's USER_HZ).
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k)?.parse::<u64>().ok();
    Some(Duration::from_millis((ticks(11)? + ticks(12)?) * 10))
}

/// Runs `render` with `args` on this process of `comm`.
pub fn run<C: Communicator>(comm: &C, args: &RenderArgs) -> Result<()> {
    let start = Instant::now();
    let at_root = comm.rank() == ROOT;
    let plan = agree(comm, checked_plan(args, at_root))?;
    let device = render_device::offscreen_renderer(args).map_err(Into::into);
    let mut renderer = agree(comm, device)?;

    let (reading, cpu) = (Instant::now(), cpu_time());
    let share = read_share(comm, args, &plan.scene)?;
    let (fastest, slowest) = spread(comm, reading.elapsed().as_secs_f64());
    // -1 where a process cannot tell.
    let cpu = cpu
        .zip(cpu_time())
        .map_or(-1.0, |(before, after)| (after - before).as_secs_f64());
    let (least_cpu, most_cpu) = spread(comm, cpu);
    let sphere = whole_bounds(comm, &share.scene).map(Scene::sphere_around);
    let k = args.supersample;
    let cameras = camera_setup::camera_around(args, sphere).and_then(|camera| {
        let drawn = supersample::supersampled_camera(&camera, k)?;
        Ok((camera, drawn))
    });
    let (camera, drawn) = agree(comm, cameras.map_err(Into::into))?;
    if at_root {
        for note in &share.notes {
            eprintln!("{}: {note}", args.scene);
        }
        if share.split == Split::Whole && matches!(plan.scene, SceneSpec::File(_)) {
            eprintln!(
                "{}: read whole by every process (this format's records cannot be found \
                 without reading what comes before them), each keeping its range",
                args.scene
            );
        }
        if let Some(sphere) = sphere {
            if let Some(warning) = camera_setup::nothing_in_view_around(args, &camera, sphere) {
                eprintln!("warning: {warning}");
            }
        }
    }

    let done = render_composited(
        comm,
        ROOT,
        &mut renderer,
        &share.scene,
        &share.indices,
        &drawn,
        plan.outputs,
    )?;
    agree(
        comm,
        renderer.context().check_validation().map_err(Into::into),
    )?;
    let (_, drawing) = spread(comm, done.draw_seconds);
    let (_, compositing) = spread(comm, done.composite_seconds);
    let written = match &done.frame {
        Some(frame) => write_images(args, &plan, frame, k),
        None => Ok(()),
    };
    agree(comm, written)?;
    if at_root {
        let cpu = if least_cpu >= 0.0 {
            format!(", CPU {least_cpu:.0} to {most_cpu:.0} ms")
        } else {
            String::new()
        };
        println!(
            "wrote {} ({}x{}, {} ellipsoids over {} process{}) in {:.0} ms: reading the shares \
             {:.0} to {:.0} ms ({}{cpu}), drawing {:.1} ms and compositing {:.1} ms (the \
             slowest process's)",
            args.output.display(),
            args.width,
            args.height,
            share.total,
            comm.size(),
            if comm.size() == 1 { "" } else { "es" },
            start.elapsed().as_secs_f64() * 1e3,
            fastest,
            slowest,
            match share.split {
                Split::Lines => "by lines",
                Split::Records => "by records",
                Split::Whole => "each whole",
            },
            drawing,
            compositing
        );
    }
    Ok(())
}
