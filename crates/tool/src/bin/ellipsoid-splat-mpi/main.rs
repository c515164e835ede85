//! `ellipsoid-splat-mpi render ...`: one-process `render`'s flags, run by every process of
//! `mpirun -n N`: each reads its own share of the scene file (the lines starting in its byte
//! range of CSV, LAMMPS dump and extended XYZ text; its range of binary PLY records) and draws
//! it, and rank 0 composites the frames and writes the images -- bit for bit those one process
//! writes. A process that fails makes every process print `ellipsoid-splat-mpi: rank K: ERROR`
//! (the failing one its own error, the others naming it) and exit with status 1.
//!
//! Built with the tool's feature `mpi` (`cargo build --release -p ellipsoid-splat-tool
//! --features mpi`); see docs/mpi.md.

mod agree;
mod error;
mod exchange;
mod render;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use mpi::traits::*;

use ellipsoid_splat_tool::cli::RenderArgs;

/// `ellipsoid-splat render` under mpirun: each process reads and draws its share of the scene,
/// rank 0 writes the composited images.
#[derive(Debug, Parser)]
#[command(name = "ellipsoid-splat-mpi", version, about)]
struct MpiCli {
    #[command(subcommand)]
    command: MpiCommand,
}

#[derive(Debug, Subcommand)]
enum MpiCommand {
    /// Render a scene split between the processes (the flags of `ellipsoid-splat render`, but
    /// --frames, --movie, --save-scene, --samples, --per-sample-shading and --viewport).
    Render(Box<RenderArgs>),
}

fn main() -> ExitCode {
    // Bad flags end every process alike, before MPI starts.
    let MpiCommand::Render(args) = MpiCli::parse().command;
    // A panic (a bug) must not leave the other processes waiting in an exchange: this one ends
    // at once, and mpirun ends the others.
    let report = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        report(info);
        std::process::abort();
    }));
    let Some(universe) = mpi::initialize() else {
        eprintln!("ellipsoid-splat-mpi: MPI was initialised already");
        return ExitCode::FAILURE;
    };
    let world = universe.world();
    match render::run(&world, &args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One write, so that the processes' lines do not interleave.
            let line = format!("ellipsoid-splat-mpi: rank {}: {e}\n", world.rank());
            let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
            ExitCode::FAILURE
        }
    }
}
