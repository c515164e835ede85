//! Bad scene files and bad arguments through the command line: exit status 1 and one line
//! naming the file or flag and the reason -- never a panic or an abort; `--skip-invalid`
//! renders the rest and says how many records it dropped. Argument mistakes are found before
//! the scene is built or the device is touched.

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::{Command, Output};

fn scratch(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ellipsoid-splat-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn render(scene: &PathBuf, extra: &[&str]) -> Output {
    let out = scene.with_extension("out.png");
    Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args([
            "render",
            "--validation",
            "--width",
            "64",
            "--height",
            "48",
            "--scene",
        ])
        .arg(scene)
        .arg("--output")
        .arg(&out)
        .args(extra)
        .output()
        .expect("the binary runs")
}

#[test]
fn malformed_files_exit_with_a_named_error() {
    let cases: [(&str, &[u8], &str); 5] = [
        ("bad.csv", b"x,y,z,rx,ry,rz,qw,qx,qy,qz\n0,0,0,1,1,-1,1,0,0,0\n", "bad.csv:2:rz"),
        ("bad.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nend_header\n", "bad.ply"),
        ("bad.nii", &[0u8; 100], "bad.nii:0:"),
        ("bad.pdb", b"ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\nANISOU    1  N   ALA A   1     2406   1892x  1614    198    519   -328       N\n", "bad.pdb:2:"),
        ("empty.cif", b"", "empty.cif:0:"),
    ];
    for (name, bytes, expected) in cases {
        let path = scratch(name, bytes);
        let output = render(&path, &[]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{name}: {stderr}");
        assert!(!stderr.contains("panicked"), "{name} panicked: {stderr}");
        let error = stderr
            .lines()
            .find(|l| l.starts_with("error: "))
            .unwrap_or_default();
        assert!(
            error.contains(expected),
            "{name}: expected {expected:?} in {error:?}"
        );
    }
}

#[test]
fn skip_invalid_renders_the_rest_and_counts() {
    let csv = b"x,y,z,rx,ry,rz,qw,qx,qy,qz\n0,0,0,1,1,1,1,0,0,0\n2,0,0,1,nan,1,1,0,0,0\n4,0,0,1,1,1,1,0,0,0\n";
    let path = scratch("skip.csv", csv);
    let failed = render(&path, &[]);
    assert_eq!(failed.status.code(), Some(1));
    let output = render(&path, &["--skip-invalid"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stderr}");
    assert!(stderr.contains("skipped 1 invalid row"), "{stderr}");
    assert!(stdout.contains("2 ellipsoids"), "{stdout}");
}

/// Runs the binary with `args`.
fn run<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args(args)
        .output()
        .expect("the binary runs")
}

/// Runs `render` with `args` on a small scene, and a device that does not exist: an argument
/// error must come first, before any device is looked for.
fn render_args<S: AsRef<OsStr>>(args: &[S]) -> Output {
    let mut all: Vec<&OsStr> = ["render", "--device", "no-such-device"]
        .iter()
        .map(OsStr::new)
        .collect();
    all.extend(args.iter().map(AsRef::as_ref));
    run(&all)
}

/// The `error: ` line of a run that must fail with `status`, having checked that it did not
/// panic or abort and wrote nothing to stdout.
fn error_line(output: &Output, status: i32, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(status), "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what} panicked: {stderr}");
    assert!(
        output.stdout.is_empty(),
        "{what}: stdout {:?}",
        output.stdout
    );
    stderr
        .lines()
        .find(|l| l.starts_with("error: "))
        .unwrap_or_else(|| panic!("{what}: no error line in {stderr}"))
        .to_string()
}

fn assert_names(error: &str, expected: &[&str], what: &str) {
    for e in expected {
        assert!(error.contains(e), "{what}: expected {e:?} in {error:?}");
    }
}

#[test]
fn absurd_scene_counts_are_refused_before_allocating() {
    for (scene, count) in [
        ("random:999999999999", "999999999999"),
        ("random:4294967296", "4294967296"),
        ("random:99999999999999999999999", "99999999999999999999999"),
        ("tensor-field:2000", "8000000000"),
        (
            "tensor-field:99999999999999999999999",
            "99999999999999999999999^3",
        ),
    ] {
        let output = render_args(&["--scene", scene]);
        let error = error_line(&output, 1, scene);
        assert_names(
            &error,
            &["--scene", scene, count, "4294967295", "u32", "48 bytes"],
            scene,
        );
    }
    let error = error_line(&render_args(&["--scene", "tensor-field:2000"]), 1, "N");
    assert_names(&error, &["at most 1625"], "tensor-field side");
}
