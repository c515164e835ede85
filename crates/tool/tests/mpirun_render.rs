//! `ellipsoid-splat-mpi render` under `mpirun` (Debian's OpenMPI, scripts/setup.sh) with 1 to 4
//! processes on this machine, each reading its own share of the scene file, against
//! one-process `ellipsoid-splat render` of the same file and flags: the colour PNG, and the
//! depth, normal and ID images decoded, bit for bit, for Ellipsoid CSV, a LAMMPS dump (ids in
//! any order, frame 1 of 8), extended XYZ and binary PLY, a file with fewer rows than
//! processes, a generated scene and a supersampled frame. A bad record in one process's share
//! stops every process within seconds, each naming the failing one and that one the file, line
//! and reason, the old output untouched; flags that cannot be split are refused by name.
//! Validation is on throughout.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's root (the samples' paths are relative to it).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "ellipsoid-splat-mpirun-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The flags of every run: validation, a small image.
const COMMON: [&str; 5] = ["--validation", "--width", "96", "--height", "72"];

/// `ellipsoid-splat-mpi render` under `mpirun -n ranks` (ended after 300 s at most), from the
/// repository's root.
fn mpirun(ranks: usize, args: &[&str]) -> Output {
    Command::new("timeout")
        .current_dir(root())
        .args([
            "300",
            "mpirun",
            "--oversubscribe",
            "--allow-run-as-root",
            "-n",
        ])
        .arg(ranks.to_string())
        .arg(env!("CARGO_BIN_EXE_ellipsoid-splat-mpi"))
        .arg("render")
        .args(COMMON)
        .args(args)
        .output()
        .expect("timeout and mpirun (Debian's openmpi-bin, scripts/setup.sh) run")
}

/// One-process `ellipsoid-splat render` with `args`.
fn one_process(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .current_dir(root())
        .arg("render")
        .args(COMMON)
        .args(args)
        .output()
        .expect("the binary runs")
}

fn succeeded(what: &str, run: &Output) {
    assert!(
        run.status.success(),
        "{what}: exit {:?}\n{}\n{}",
        run.status.code(),
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
}

/// A PNG's pixels.
fn pixels(path: &Path) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
        .into_raw()
}

/// Every channel's samples of an EXR file, as bits (its bytes may differ for the same samples:
/// its tiles are compressed in parallel and written in the order they finish).
fn samples(path: &Path) -> Vec<Vec<u32>> {
    exr::prelude::read_all_flat_layers_from_file(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| match &c.sample_data {
            exr::prelude::FlatSamples::U32(v) => v.clone(),
            other => other.values_as_f32().map(f32::to_bits).collect(),
        })
        .collect()
}

/// The four images of a render: colour and ID pixels, depth and normal samples.
#[derive(PartialEq)]
struct Images {
    color: Vec<u8>,
    depth: Vec<Vec<u32>>,
    normal: Vec<Vec<u32>>,
    id: Vec<u8>,
}

/// Renders `scene` with `flags` (by `ranks` processes, or one with `None`) into `dir` and reads
/// the images back.
fn render(dir: &Path, name: &str, ranks: Option<usize>, scene: &str, flags: &[&str]) -> Images {
    let file = |suffix: &str| dir.join(format!("{name}{suffix}")).display().to_string();
    let (color, depth, normal, id) = (
        file(".png"),
        file("-depth.exr"),
        file("-normal.exr"),
        file("-id.png"),
    );
    let mut args = vec!["--scene", scene, "--output", &color, "--depth", &depth];
    args.extend(["--normal", &normal, "--id", &id]);
    args.extend(flags);
    let run = match ranks {
        Some(n) => mpirun(n, &args),
        None => one_process(&args),
    };
    succeeded(&format!("{name} ({ranks:?} processes)"), &run);
    let images = Images {
        color: pixels(Path::new(&color)),
        depth: samples(Path::new(&depth)),
        normal: samples(Path::new(&normal)),
        id: pixels(Path::new(&id)),
    };
    let shown = images.id.chunks(4).filter(|p| p != &[255; 4]).count();
    assert!(
        shown > 96 * 72 / 20,
        "{name}: only {shown} pixels show a glyph"
    );
    images
}

/// For each of `ranks`: the images of `scene` drawn by that many processes are one process's,
/// bit for bit.
fn assert_composited_as_one(dir: &Path, name: &str, scene: &str, flags: &[&str], ranks: &[usize]) {
    let one = render(dir, &format!("{name}-one"), None, scene, flags);
    for &n in ranks {
        let many = render(dir, &format!("{name}-{n}"), Some(n), scene, flags);
        for (what, same) in [
            ("colour", many.color == one.color),
            ("depth", many.depth == one.depth),
            ("normal", many.normal == one.normal),
            ("ID", many.id == one.id),
        ] {
            assert!(
                same,
                "{name}, {n} processes: the {what} differs from one process's"
            );
        }
    }
}

#[test]
fn every_format_composited_by_1_to_4_processes_is_one_process_render() {
    let dir = scratch("formats");
    for (name, scene) in [
        ("csv", "data/samples/gay-berne-frame1.csv"),
        ("lammps", "data/samples/gay-berne.lammpstrj"),
        ("xyz", "data/samples/gay-berne.extxyz"),
        ("ply", "data/samples/splats.ply"),
    ] {
        assert_composited_as_one(&dir, name, scene, &[], &[1, 2, 3, 4]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tiny_generated_and_supersampled_scenes_composite_as_one_process() {
    let dir = scratch("cases");
    // Three rows for four processes: one reads nothing; the rows overlap (ties by index).
    let tiny = dir.join("tiny.csv");
    std::fs::write(
        &tiny,
        "x,y,z,rx,ry,rz,qw,qx,qy,qz\n0,0,0,1,0.5,0.5,1,0,0,0\n0,0,0,0.5,1,0.5,1,0,0,0\n\
         0.5,0,0,0.5,0.5,1,1,0,0,0\n",
    )
    .unwrap();
    assert_composited_as_one(&dir, "tiny", tiny.to_str().unwrap(), &[], &[4]);
    // Generated: every process makes the whole and keeps its range.
    assert_composited_as_one(
        &dir,
        "random",
        "random:3000",
        &["--color", "principal"],
        &[3],
    );
    // Drawn twice as large with a jitter, filtered at rank 0; compact instances.
    let flags = ["--supersample", "2", "--jitter", "0.25,-0.125", "--compact"];
    assert_composited_as_one(
        &dir,
        "supersampled",
        "data/samples/gay-berne.extxyz",
        &flags,
        &[3],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_record_on_one_process_stops_every_process_naming_it() {
    let dir = scratch("bad");
    // Row 330 of 400 (line 332) falls in the last of three processes' byte ranges.
    let mut text = String::from("x,y,z,rx,ry,rz,qw,qx,qy,qz\n");
    for k in 0..400 {
        let ry = if k == 330 { "-0.3" } else { "0.3" };
        text.push_str(&format!("{},{},0,0.4,{ry},0.2,1,0,0,0\n", k % 20, k / 20));
    }
    let scene = dir.join("bad.csv");
    std::fs::write(&scene, text).unwrap();
    let output = dir.join("out.png");
    std::fs::write(&output, "the old image").unwrap();
    let started = std::time::Instant::now();
    let run = mpirun(
        3,
        &[
            "--scene",
            scene.to_str().unwrap(),
            "--output",
            output.to_str().unwrap(),
        ],
    );
    let seconds = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && run.status.code() != Some(124),
        "exit {:?} (124: ended by timeout)\n{stderr}",
        run.status.code()
    );
    assert!(seconds < 60.0, "{seconds:.0} s to stop");
    let line_of = |rank: usize| {
        stderr
            .lines()
            .find(|l| l.starts_with(&format!("ellipsoid-splat-mpi: rank {rank}: ")))
            .unwrap_or_else(|| panic!("no line of rank {rank}:\n{stderr}"))
    };
    let reported = format!("{}:332:ry: non-positive radius: -0.3", scene.display());
    assert!(line_of(2).contains(&reported), "{}", line_of(2));
    for rank in [0, 1] {
        assert!(
            line_of(rank).contains("rank 2 failed reading its share of"),
            "{}",
            line_of(rank)
        );
    }
    assert_eq!(std::fs::read(&output).unwrap(), b"the old image");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn flags_that_cannot_be_split_are_refused_by_name() {
    let run = mpirun(
        2,
        &[
            "--scene",
            "data/samples/gay-berne.lammpstrj",
            "--frames",
            "all",
        ],
    );
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success(), "{stderr}");
    for rank in [0, 1] {
        let line = format!("ellipsoid-splat-mpi: rank {rank}: invalid --frames: not under MPI");
        assert!(stderr.contains(&line), "{stderr}");
    }
}
