//! Bad scene files and bad arguments through the command line: exit status 1 and one line
//! naming the file or flag and the reason -- never a panic or an abort; `--skip-invalid`
//! renders the rest and says how many records it dropped. Argument mistakes are found before
//! the scene is built or the device is touched.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
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

/// A fresh directory of its own for one test.
fn scratch_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("ellipsoid-splat-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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

#[test]
fn a_scene_saved_where_it_cannot_be_written_is_refused_before_drawing() {
    let dir = scratch_dir("save-scene");
    let plain = dir.join("plain-file");
    std::fs::write(&plain, b"not a directory").unwrap();
    let below_file = plain.join("scene.csv");
    let output = render_args(&[
        OsStr::new("--scene"),
        OsStr::new("lattice:4"),
        OsStr::new("--save-scene"),
        below_file.as_os_str(),
    ]);
    let error = error_line(&output, 1, "--save-scene below a file");
    assert_names(
        &error,
        &["--save-scene", "cannot write", "plain-file"],
        "--save-scene",
    );
}

#[test]
fn output_names_must_match_what_is_written() {
    let dir = scratch_dir("extensions");
    let cases: [(&str, &str, &str); 6] = [
        ("--depth", "d.png", ".exr"),
        ("--normal", "n.PNG", ".exr"),
        ("--output", "c.exr", ".png"),
        ("--output", "colour", ".png"),
        ("--id", "i.tiff", ".exr or .png"),
        ("--depth", "d.exr.gz", ".exr"),
    ];
    for (flag, name, accepted) in cases {
        let path = dir.join(name);
        let output = render_args(&[OsStr::new(flag), path.as_os_str()]);
        let what = format!("{flag} {name}");
        let error = error_line(&output, 1, &what);
        assert_names(&error, &[flag, name, accepted], &what);
        assert!(!path.exists(), "{what}: {} was written", path.display());
    }
    // Extensions match whatever their case, and each file holds what its name says.
    let names = ["C.PNG", "D.EXR", "N.Exr", "I.Png", "J.exr"];
    let paths: Vec<PathBuf> = names.iter().map(|n| dir.join(n)).collect();
    let mut args: Vec<&OsStr> = [
        "render",
        "--validation",
        "--scene",
        "random:20",
        "--width",
        "64",
        "--height",
        "48",
    ]
    .iter()
    .map(OsStr::new)
    .collect();
    for (flag, path) in ["--output", "--depth", "--normal", "--id"]
        .iter()
        .zip(&paths)
    {
        args.extend([OsStr::new(flag), path.as_os_str()]);
    }
    let output = run(&args);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let magic = |path: &Path| std::fs::read(path).unwrap()[..4].to_vec();
    assert_eq!(magic(&paths[0]), b"\x89PNG");
    assert_eq!(magic(&paths[1]), [0x76, 0x2f, 0x31, 0x01], "EXR magic");
    assert_eq!(magic(&paths[2]), [0x76, 0x2f, 0x31, 0x01], "EXR magic");
    assert_eq!(magic(&paths[3]), b"\x89PNG");
    let output = run(&[
        OsStr::new("render"),
        OsStr::new("--scene"),
        OsStr::new("random:20"),
        OsStr::new("--width"),
        OsStr::new("64"),
        OsStr::new("--height"),
        OsStr::new("48"),
        OsStr::new("--output"),
        paths[0].as_os_str(),
        OsStr::new("--id"),
        paths[4].as_os_str(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(magic(&paths[4]), [0x76, 0x2f, 0x31, 0x01], "EXR magic");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn negative_numbers_are_values_and_reach_validation() {
    let cases: [(&[&str], &str, &str); 8] = [
        (&["--near", "-1"], "--near", "must be positive"),
        (&["--near", "-inf"], "--near", "must be positive"),
        (
            &["--eye", "-1,2,3", "--near", "-1"],
            "--near",
            "must be positive",
        ),
        (
            &["--near", "-1e-3", "--target", "-5,-5,-5"],
            "--near",
            "must be positive",
        ),
        (&["--ortho", "-2"], "--ortho", "must be positive"),
        (&["--fov-y", "-10"], "--fov-y", "between 0 and 180"),
        (&["--sigma", "-1"], "--sigma", "must be positive"),
        (
            &["--glyph-scale", "-0.5"],
            "--glyph-scale",
            "must be positive",
        ),
    ];
    for (args, flag, reason) in cases {
        let what = args.join(" ");
        let error = error_line(&render_args(args), 1, &what);
        assert_names(&error, &[flag, reason], &what);
        assert!(!error.contains("unexpected argument"), "{what}: {error}");
    }
    // A flag where a value belongs is a missing value, not a number (a usage error, status 2).
    let error = error_line(
        &render_args(&["--near", "--validation"]),
        2,
        "--near --validation",
    );
    assert_names(
        &error,
        &["--near", "value is missing"],
        "--near --validation",
    );
    // A negative pixel count is still a value of --width (a usage error, status 2).
    let output = render_args(&["--width", "-5"]);
    let error = error_line(&output, 2, "--width -5");
    assert_names(
        &error,
        &["--width", "-5", "whole number of pixels"],
        "--width -5",
    );
    // Negative coordinates are values too, and render.
    let dir = scratch_dir("negative");
    let out = dir.join("c.png");
    let output = run(&[
        OsStr::new("render"),
        OsStr::new("--validation"),
        OsStr::new("--scene"),
        OsStr::new("random:20"),
        OsStr::new("--width"),
        OsStr::new("64"),
        OsStr::new("--height"),
        OsStr::new("48"),
        OsStr::new("--eye"),
        OsStr::new("-30,-20,-40"),
        OsStr::new("--target"),
        OsStr::new("-0.5,0,0"),
        OsStr::new("--output"),
        out.as_os_str(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn unwritable_outputs_fail_before_any_gpu_work() {
    let dir = scratch_dir("unwritable");
    let plain = dir.join("plain-file");
    std::fs::write(&plain, b"not a directory").unwrap();
    let a_dir = dir.join("dir.exr");
    std::fs::create_dir_all(&a_dir).unwrap();
    let cases: [(&str, PathBuf, &str); 4] = [
        (
            "--output",
            PathBuf::from("/nonexistent/dir/x.png"),
            "does not exist",
        ),
        ("--depth", plain.join("d.exr"), "is not a directory"),
        ("--id", a_dir.clone(), "is a directory"),
        (
            "--normal",
            dir.join("missing").join("n.exr"),
            "does not exist",
        ),
    ];
    for (flag, path, reason) in &cases {
        let what = format!("{flag} {}", path.display());
        let output = render_args(&[OsStr::new(flag), path.as_os_str()]);
        let error = error_line(&output, 1, &what);
        assert_names(&error, &[flag, &path.display().to_string(), reason], &what);
    }
    // Two images into one file would overwrite one with the other.
    let same = dir.join("same.png");
    let alias = dir
        .join("..")
        .join(dir.file_name().unwrap())
        .join("same.png");
    let output = render_args(&[
        OsStr::new("--output"),
        same.as_os_str(),
        OsStr::new("--id"),
        alias.as_os_str(),
    ]);
    let error = error_line(&output, 1, "same file");
    assert_names(&error, &["--id", "--output", "same.png"], "same file");
    // The checks leave files as they were: an existing output is not truncated and a probe
    // file is not left behind when a later step (here, finding the device) fails.
    let kept = dir.join("kept.png");
    std::fs::write(&kept, b"keep").unwrap();
    let fresh = dir.join("fresh.exr");
    let output = render_args(&[
        OsStr::new("--scene"),
        OsStr::new("random:5"),
        OsStr::new("--output"),
        kept.as_os_str(),
        OsStr::new("--depth"),
        fresh.as_os_str(),
    ]);
    let error = error_line(&output, 1, "device");
    assert_names(&error, &["no-such-device"], "device");
    assert_eq!(std::fs::read(&kept).unwrap(), b"keep");
    assert!(!fresh.exists(), "the probe was left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn image_size_is_limited_with_a_named_error() {
    for (flag, value) in [
        ("--width", "16385"),
        ("--height", "16385"),
        ("--width", "100000"),
        ("--height", "0"),
        ("--width", "0"),
    ] {
        let what = format!("{flag} {value}");
        let error = error_line(&render_args(&[flag, value]), 1, &what);
        assert_names(&error, &[flag, value, "1..=16384"], &what);
    }
}

#[test]
fn antialiasing_flags_are_checked_with_named_errors() {
    for (args, reason) in [
        (&["--samples", "3"][..], "not a sample count"),
        (&["--samples", "four"][..], "not a sample count"),
        (&["--per-sample-shading"][..], "give --samples 2 or more"),
        (&["--supersample", "9"][..], "outside 1..=8"),
        (&["--supersample", "0"][..], "outside 1..=8"),
        (
            &["--supersample", "4", "--width", "5000"][..],
            "more than 16384",
        ),
        (
            &["--supersample", "two"][..],
            "not a whole number of samples",
        ),
    ] {
        let what = args.join(" ");
        let output = render_args(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_ne!(output.status.code(), Some(0), "{what}: {stderr}");
        let flag = args[0];
        assert!(
            stderr.contains(flag) && stderr.contains(reason),
            "{what}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    }
}

#[test]
fn camera_flags_are_checked_with_named_errors() {
    let cases: [(&[&str], &str, &str); 4] = [
        (&["--up", "0,0,0"], "--up", "must not be 0,0,0"),
        (
            &["--eye", "1,2,3", "--target", "1,2,3"],
            "--target",
            "same point as --eye",
        ),
        (
            &[
                "--scene",
                "random:10",
                "--eye",
                "0,100,0",
                "--target",
                "0,0,0",
            ],
            "--up",
            "parallel to the view direction",
        ),
        (&["--fov-y", "180"], "--fov-y", "between 0 and 180"),
    ];
    for (args, flag, reason) in cases {
        let what = args.join(" ");
        let error = error_line(&render_args(args), 1, &what);
        assert_names(&error, &[flag, reason], &what);
    }
    // A camera that sees nothing renders, but says so.
    let dir = scratch_dir("empty-view");
    let out = dir.join("c.png");
    for args in [["--near", "1e6"], ["--target", "1e4,0,0"]] {
        let output = run(&[
            OsStr::new("render"),
            OsStr::new("--scene"),
            OsStr::new("random:20"),
            OsStr::new("--width"),
            OsStr::new("64"),
            OsStr::new("--height"),
            OsStr::new("48"),
            OsStr::new("--eye"),
            OsStr::new("0,0,50"),
            OsStr::new(args[0]),
            OsStr::new(args[1]),
            OsStr::new("--output"),
            out.as_os_str(),
        ]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{stderr}");
        assert!(
            stderr.contains("warning: the image is empty"),
            "{args:?}: {stderr}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bench_and_stress_check_arguments_before_running() {
    let dir = scratch_dir("reports");
    let plain = dir.join("plain-file");
    std::fs::write(&plain, b"not a directory").unwrap();
    let below_file = plain.join("out");
    let cases: [(&[&OsStr], &str, &str); 7] = [
        (
            &[
                OsStr::new("bench"),
                OsStr::new("--scenes"),
                OsStr::new("nosuch"),
            ],
            "--scenes",
            "matches no scene",
        ),
        (
            &[OsStr::new("bench"), OsStr::new("--orbit"), OsStr::new("0")],
            "--orbit",
            "0.01 to 90",
        ),
        (
            &[
                OsStr::new("bench"),
                OsStr::new("--skip"),
                OsStr::new("--orbit"),
                OsStr::new("1"),
            ],
            "--orbit",
            "does not apply to --skip",
        ),
        (
            &[
                OsStr::new("bench"),
                OsStr::new("--skip"),
                OsStr::new("--methods"),
                OsStr::new("impostor"),
            ],
            "--methods",
            "does not apply to --skip",
        ),
        (
            &[OsStr::new("bench"), OsStr::new("--frames"), OsStr::new("0")],
            "--frames",
            "at least 1",
        ),
        (
            &[
                OsStr::new("bench"),
                OsStr::new("--quick"),
                OsStr::new("--out"),
                below_file.as_os_str(),
            ],
            "--out",
            "plain-file",
        ),
        (
            &[
                OsStr::new("stress"),
                OsStr::new("--quick"),
                OsStr::new("--out"),
                plain.as_os_str(),
            ],
            "--out",
            "is not a directory",
        ),
    ];
    for (args, flag, reason) in cases {
        let mut all = args.to_vec();
        all.extend([OsStr::new("--device"), OsStr::new("no-such-device")]);
        let what = format!("{args:?}");
        // `bench` and `stress` exit 2 on an error (1 means a target or bound was missed).
        let error = error_line(&run(&all), 2, &what);
        assert_names(&error, &[flag, reason], &what);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_color_mode_is_accepted_and_an_unknown_one_is_named() {
    for mode in ["file", "shape", "principal", "principal-fa", "uniform"] {
        // Accepted: the run gets as far as looking for the (missing) device.
        let output = render_args(&["--scene", "random:5", "--color", mode]);
        let error = error_line(&output, 1, mode);
        assert_names(&error, &["no-such-device"], mode);
    }
    let output = render_args(&["--color", "rainbow"]);
    let error = error_line(&output, 2, "--color rainbow");
    assert_names(&error, &["--color", "'rainbow'"], "--color rainbow");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("file, shape, principal, principal-fa, uniform"),
        "the known modes are listed: {stderr}"
    );
    // The help lists the modes with what each means.
    let help = run(&["render", "--help"]);
    let help = String::from_utf8_lossy(&help.stdout);
    for words in [
        "--color <MODE>",
        "principal-fa",
        "longest semi-axis",
        "Westin",
    ] {
        assert!(
            help.contains(words),
            "{words:?} missing from --help:\n{help}"
        );
    }
}

/// The camera flags of general cameras: a malformed value is a usage error naming the flag
/// (status 2), a value the camera contract refuses an error naming the flag and why (status
/// 1), both before the device is touched.
#[test]
fn bad_camera_flags_are_named() {
    let usage: [(&[&str], &str, &str); 6] = [
        (&["--intrinsics", "1,2,3"], "--intrinsics", "fx,fy,cx,cy"),
        (
            &["--intrinsics", "100,0,5,5"],
            "--intrinsics",
            "must be positive",
        ),
        (
            &["--intrinsics", "100,nan,5,5"],
            "--intrinsics",
            "not finite",
        ),
        (&["--jitter", "0.5"], "--jitter", "dx,dy"),
        (&["--viewport", "0,0,10"], "--viewport", "x,y,w,h"),
        (&["--viewport", "0,0,0,10"], "--viewport", "empty"),
    ];
    for (args, flag, reason) in usage {
        let what = args.join(" ");
        let error = error_line(&render_args(args), 2, &what);
        assert_names(&error, &[flag, reason], &what);
    }
    for conflict in ["--fov-y", "--ortho"] {
        let args = ["--intrinsics", "100,100,50,50", conflict, "30"];
        let what = args.join(" ");
        let error = error_line(&render_args(&args), 2, &what);
        assert_names(&error, &["--intrinsics", conflict], &what);
    }
    let refused: [(&[&str], &str, &str); 4] = [
        (
            &["--viewport", "1900,0,64,48"],
            "--viewport",
            "reaches beyond the 1920x1080 output",
        ),
        (
            &["--scene", "random:10", "--jitter", "1e9,0"],
            "--jitter",
            "pixels from the centre",
        ),
        (
            &["--scene", "random:10", "--intrinsics", "100,100,1e9,5"],
            "--intrinsics",
            "pixels from the centre",
        ),
        (
            &[
                "--scene",
                "random:10",
                "--width",
                "64",
                "--height",
                "48",
                "--jitter",
                "3000,0",
            ],
            "--jitter",
            "half images from the centre",
        ),
    ];
    for (args, flag, reason) in refused {
        let what = args.join(" ");
        let error = error_line(&render_args(args), 1, &what);
        assert_names(&error, &[flag, reason], &what);
    }
}

/// `--plan` takes only the plans there are, and says which.
#[test]
fn an_unknown_plan_is_named_with_the_choices() {
    let output = render_args(&["--scene", "random:5", "--plan", "fastest"]);
    let error = error_line(&output, 2, "--plan fastest");
    assert_names(&error, &["--plan", "'fastest'"], "--plan fastest");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("measure, estimate, draw, splat, visible-first"),
        "the plans are listed: {stderr}"
    );
    // Each known one gets as far as looking for the (missing) device.
    for plan in ["measure", "estimate", "draw", "splat", "visible-first"] {
        let output = render_args(&["--scene", "random:5", "--plan", plan]);
        let error = error_line(&output, 1, plan);
        assert_names(&error, &["no-such-device"], plan);
    }
}

/// `bench --scene`: the scene, its camera and loading flags are checked (and the scene read)
/// before the device is looked for; `bench` exits 2 on an error.
#[test]
fn bench_scene_mistakes_are_named_before_running() {
    let dir = scratch_dir("bench-scene");
    let missing = dir.join("missing.csv");
    let missing = missing.to_str().unwrap();
    let bad = scratch(
        "bench-bad.csv",
        b"x,y,z,rx,ry,rz,qw,qx,qy,qz\n0,0,0,1,1,-1,1,0,0,0\n",
    );
    let bad = bad.to_str().unwrap();
    let cases: [(&[&str], &[&str]); 7] = [
        (
            &["--scene", missing],
            &["--scene", "missing.csv", "No such file"],
        ),
        (&["--scene", bad], &["bench-bad.csv:2:rz"]),
        (
            &["--scene", "md-liquid:0"],
            &["--scene", "md-liquid:N needs N >= 1"],
        ),
        (
            &["--scene", "random:10", "--width", "0"],
            &["--width", "outside 1..=16384"],
        ),
        (
            &["--eye", "1,2,3"],
            &["--eye", "applies to the scenes of --scene"],
        ),
        (
            &["--sigma", "3"],
            &["--sigma", "applies to the scenes of --scene"],
        ),
        (
            &["--skip", "--scene", "random:10"],
            &["--scene", "does not apply to --skip"],
        ),
    ];
    for (args, expected) in cases {
        let mut all = vec!["bench", "--quick", "--device", "no-such-device", "--out"];
        let out = dir.join("out");
        all.push(out.to_str().unwrap());
        all.extend(args);
        let what = args.join(" ");
        let error = error_line(&run(&all), 2, &what);
        assert_names(&error, expected, &what);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--frames` and `--movie` mistakes are named before any device is looked for: a generated
/// scene, frame 0, a range past the file, a bad file-name pattern, a movie without frames or
/// without an extension, and a missing ffmpeg (PATH emptied).
#[test]
fn frame_range_and_movie_mistakes_are_named() {
    let dir = scratch_dir("frames");
    let trajectory = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/samples/gay-berne.lammpstrj"
    );
    let out = dir.join("f.png");
    let out = out.to_str().unwrap();
    // Clap refuses what it parses (exit 2), the tool the rest (exit 1).
    let cases: [(&[&str], i32, &[&str]); 7] = [
        // Both number to x_0001.png.
        (
            &[
                "--scene",
                trajectory,
                "--frames",
                "all",
                "--output",
                "x.png",
                "--id",
                "x_%04d.png",
            ],
            1,
            &["--id", "also the --output file"],
        ),
        (
            &["--scene", "lattice:3", "--frames", "all"],
            1,
            &["--frames", "generated"],
        ),
        (
            &["--scene", trajectory, "--frames", "0"],
            2,
            &["--frames", "numbered from 1"],
        ),
        (
            &["--scene", trajectory, "--frames", "2:99999"],
            1,
            &["--frames", "reaches past", "8 frames"],
        ),
        (
            &[
                "--scene", trajectory, "--frames", "all", "--output", "x_%s.png",
            ],
            1,
            &["--output", "%d or %0Nd"],
        ),
        (
            &["--scene", trajectory, "--movie", "m.mp4"],
            2,
            &["required arguments"],
        ),
        (
            &[
                "--scene", trajectory, "--frames", "1", "--output", out, "--movie", "m",
            ],
            1,
            &["--movie", "no extension"],
        ),
    ];
    for (args, status, expected) in cases {
        let output = render_args(args);
        let error = error_line(&output, status, &args.join(" "));
        assert_names(&error, expected, &args.join(" "));
    }
    let movie = dir.join("m.mp4");
    let output = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .env("PATH", "")
        .args([
            "render",
            "--device",
            "no-such-device",
            "--scene",
            trajectory,
        ])
        .args(["--frames", "1", "--output", out, "--movie"])
        .arg(&movie)
        .output()
        .expect("the binary runs");
    let error = error_line(&output, 1, "no ffmpeg");
    assert_names(&error, &["--movie", "ffmpeg", "not installed"], "no ffmpeg");
    assert!(!movie.exists() && !dir.join(".m.partial.mp4").exists());
}
