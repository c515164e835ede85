//! In situ from C (feature `mpi`): `examples/insitu_mpi.c`, built with `mpicc` against the
//! installed library (`scripts/install-capi.sh`) and run under `mpirun` with 1 to 4
//! processes, composites over `MPI_COMM_WORLD` and over a communicator it split itself, and
//! its root finds each frame bit-identical to the frame it draws alone through the same ABI
//! (validation on: any message fails the call). A rank whose glyph is bad stops every rank
//! with named errors, none waiting; MPI not initialised is a named error, not a crash.

use std::ffi::CStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use ellipsoid_splat_capi::*;

/// `command`'s output, which must succeed without a word from the validation layer.
fn run(command: &mut Command, what: &str) -> String {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    checked(&output, what)
}

fn checked(output: &Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "{what} failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    // The layer's own log catches what no messenger heard.
    for text in [&stdout[..], &stderr[..]] {
        assert!(
            !text.contains("Validation Error") && !text.contains("Validation Warning"),
            "{what}: the validation layer spoke:\n{text}"
        );
    }
    stdout
}

/// The example, built against the C libraries of this profile with the `mpi` feature.
fn example() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let root = root.canonicalize().unwrap();
    let profile = std::env::current_exe()
        .unwrap()
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .to_path_buf();
    let work = profile.join("capi-insitu");
    let prefix = work.join("install");
    std::fs::create_dir_all(&work).unwrap();
    // `cargo test` builds only the Rust library of this crate: build the C libraries too.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut build = Command::new(cargo);
    build
        .args(["build", "--quiet", "-p", "ellipsoid-splat-capi", "--lib"])
        .args(["--features", "mpi", "--manifest-path"])
        .arg(root.join("Cargo.toml"));
    if profile.file_name().is_some_and(|p| p == "release") {
        build.arg("--release");
    }
    run(&mut build, "cargo build (the C libraries, feature mpi)");
    // Installed at once: another test may build the libraries without the feature later.
    run(
        Command::new("bash")
            .arg(root.join("scripts/install-capi.sh"))
            .arg("--prebuilt")
            .arg(&profile)
            .arg(&prefix),
        "scripts/install-capi.sh",
    );
    let flags = run(
        Command::new("pkg-config")
            .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
            .args(["--cflags", "--libs", "ellipsoid_splat"]),
        "pkg-config",
    );
    let binary = work.join("insitu_mpi");
    run(
        Command::new("mpicc")
            .args(["-std=c11", "-Wall", "-Wextra", "-Wpedantic", "-Werror"])
            .arg(root.join("crates/capi/examples/insitu_mpi.c"))
            .args(flags.split_whitespace())
            .arg(format!("-Wl,-rpath,{}", prefix.join("lib").display()))
            .arg("-o")
            .arg(&binary),
        "mpicc (examples/insitu_mpi.c)",
    );
    binary
}

/// `mpirun` of `binary` with `ranks` processes, ended after two minutes (a rank left waiting
/// would otherwise hang the test).
fn mpirun(binary: &Path, ranks: u32, args: &[&str]) -> Output {
    Command::new("timeout")
        .args(["120", "mpirun", "--oversubscribe", "--allow-run-as-root"])
        .args(["-n", &ranks.to_string()])
        .arg(binary)
        .args(args)
        .output()
        .expect("timeout and mpirun (Debian's openmpi-bin, scripts/setup.sh) run")
}

#[test]
fn the_c_example_composites_what_one_process_draws_and_failures_stop_every_rank() {
    let binary = example();
    for ranks in 1..=4 {
        let what = format!("{ranks} ranks");
        let out = checked(&mpirun(&binary, ranks, &[]), &what);
        let cases: Vec<&str> = out.lines().filter(|l| l.starts_with("case ")).collect();
        assert_eq!(cases.len(), 2, "{what}:\n{out}");
        for line in cases {
            assert!(line.contains(": match, "), "{what}: {line}");
        }
    }
    // The failing rank is the extra one folded into another (crates/mpi's own test fails the
    // root and a swapping rank too; the layers above share its agreement).
    for failing in ["2"] {
        let what = format!("failing rank {failing}");
        let out = checked(&mpirun(&binary, 3, &["--fail-rank", failing]), &what);
        for rank in ["0", "1", "2"] {
            let line = out
                .lines()
                .find(|l| l.starts_with(&format!("rank {rank} stopped: ")))
                .unwrap_or_else(|| panic!("{what}: no line of rank {rank}:\n{out}"));
            let expected = if rank == failing {
                "invalid glyph 7".to_string()
            } else {
                format!("rank {failing} failed")
            };
            assert!(line.contains(&expected), "{what}: {line}");
        }
    }
}

#[test]
fn without_mpi_initialised_the_call_is_a_named_error() {
    // This test process never initialises MPI.
    let mut camera = std::mem::MaybeUninit::<EsCamera>::uninit();
    let (eye, target, up) = ([0.0, 0.0, 5.0], [0.0; 3], [0.0, 1.0, 0.0]);
    // SAFETY: valid arrays and a writable camera.
    let status = unsafe {
        es_camera_look_at(
            eye.as_ptr(),
            target.as_ptr(),
            up.as_ptr(),
            45.0,
            0.1,
            32,
            24,
            camera.as_mut_ptr(),
        )
    };
    assert_eq!(status, EsStatus::Success);
    // SAFETY: the renderer is null (refused later); no glyphs; the camera was written.
    let status = unsafe {
        es_offscreen_render_composited(
            std::ptr::null_mut(),
            0,
            0,
            std::ptr::null(),
            std::ptr::null(),
            0,
            camera.as_ptr(),
            std::ptr::null(),
        )
    };
    assert_eq!(status, EsStatus::ErrorInvalidArgument);
    // SAFETY: the library keeps a valid C string per thread.
    let message = unsafe { CStr::from_ptr(es_last_error()) }.to_string_lossy();
    assert!(
        message.contains("es_offscreen_render_composited") && message.contains("not initialised"),
        "{message}"
    );
}
