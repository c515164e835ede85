//! Outputs are written whole or not at all: with the file size limited (`ulimit -f`), a write
//! that runs past it fails (SIGXFSZ ignored: the write returns an error) or kills the process
//! (SIGXFSZ's default) part-way through. Either way the good file that was there before is
//! still there, byte for byte; a failed write also leaves no partial file and names the file.
//! The file is the saved scene, written before any device is made: a driver's own files under
//! the limit (Mesa 25's lavapipe backs device memory with memory files, which the limit cuts
//! short) cannot fail first. The images go through the same writer; their encoders failing is
//! `output.rs`'s unit test.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("es-atomic-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `render ARGS` under a file-size limit of 4 KiB, the signal the limit raises ignored
/// (`ignore`) or left to kill the process.
fn limited_render(dir: &Path, args: &[&str], ignore: bool) -> Output {
    let trap = if ignore { "trap '' XFSZ; " } else { "" };
    let script = format!("ulimit -f 4; {trap}exec \"$0\" \"$@\"");
    Command::new("bash")
        .args([
            "-c",
            &script,
            env!("CARGO_BIN_EXE_ellipsoid-splat"),
            "render",
            "--validation",
        ])
        .args(["--scene", "lattice:6", "--width", "320", "--height", "240"])
        .args(args)
        // Nothing but the output under test may reach the limit first.
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .env("__GL_SHADER_DISK_CACHE", "0")
        .current_dir(dir)
        .output()
        .expect("bash runs")
}

fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The saved scene (over 4 KiB): a failed write keeps the old file and leaves nothing else; a
/// killed one keeps the old file beside the 4 KiB partial one.
#[test]
fn a_failed_or_killed_write_keeps_the_old_file() {
    let old = b"a good file written before";
    let (flag, file) = ("--save-scene", "scene.csv");
    {
        let dir = scratch(file);
        std::fs::write(dir.join(file), old).unwrap();
        let args = [flag, file, "--output", "colour.png"];
        let failed = limited_render(&dir, &args, true);
        let stderr = String::from_utf8_lossy(&failed.stderr);
        assert_eq!(failed.status.code(), Some(1), "{flag}: {stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            stderr.contains(file),
            "{flag}: the error names the file: {stderr}"
        );
        assert_eq!(
            std::fs::read(dir.join(file)).unwrap(),
            old,
            "{flag}: old file kept"
        );
        assert_eq!(names(&dir), [file], "{flag}: nothing else left");

        let killed = limited_render(&dir, &args, false);
        assert_eq!(killed.status.code(), None, "{flag}: killed by SIGXFSZ");
        assert_eq!(
            std::fs::read(dir.join(file)).unwrap(),
            old,
            "{flag}: old file kept"
        );
        // Killed while writing it, at the limit: its hidden partial file, of exactly 4 KiB, is
        // what is left beside it.
        let left = names(&dir);
        assert_eq!(left.len(), 2, "{flag}: {left:?}");
        let partial = left
            .iter()
            .find(|n| n.starts_with(&format!(".{file}.")) && n.ends_with(".partial"))
            .unwrap_or_else(|| panic!("{flag}: no partial file in {left:?}"));
        assert_eq!(std::fs::metadata(dir.join(partial)).unwrap().len(), 4096);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Every image kind of `render` goes through the same writer: without a limit each is
/// written, and its old contents replaced whole.
#[test]
fn every_output_kind_replaces_its_file_whole() {
    let dir = scratch("kinds");
    let files = ["c.png", "d.exr", "n.exr", "i.exr", "i.png", "s.csv"];
    for file in files {
        std::fs::write(dir.join(file), b"old").unwrap();
    }
    for (id, out) in [("i.exr", "c.png"), ("i.png", "c.png")] {
        let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
            .args([
                "render",
                "--validation",
                "--scene",
                "lattice:4",
                "--width",
                "64",
                "--height",
                "48",
            ])
            .args(["--output", out, "--depth", "d.exr", "--normal", "n.exr"])
            .args(["--id", id, "--save-scene", "s.csv"])
            .current_dir(&dir)
            .output()
            .expect("the binary runs");
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    for file in files {
        let bytes = std::fs::read(dir.join(file)).unwrap();
        assert!(bytes.len() > 100, "{file} was not replaced");
    }
    assert_eq!(
        names(&dir),
        files
            .iter()
            .copied()
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect::<Vec<_>>()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
