//! Trajectories through the command line: the same frame from a LAMMPS dump, extended XYZ and
//! Ellipsoid CSV draws the same picture, `render --frames` writes one numbered image per
//! frame with the camera of the first, and `--movie` encodes them.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const LAMMPS: &str = "data/samples/gay-berne.lammpstrj";
const XYZ: &str = "data/samples/gay-berne.extxyz";
const CSV: &str = "data/samples/gay-berne-frame1.csv";

/// The repository's root (the samples' paths are relative to it).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "ellipsoid-splat-frames-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `render` with validation at 128 x 96 and `args`, from the repository's root.
fn render(args: &[&str], files: &[(&str, &Path)]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"));
    command
        .current_dir(root())
        .args(["render", "--validation", "--width", "128", "--height", "96"])
        .args(args);
    for (flag, path) in files {
        command.arg(flag).arg(path);
    }
    let run = command.output().expect("the binary runs");
    assert!(
        run.status.success(),
        "{args:?}: exit {:?}: {}",
        run.status.code(),
        String::from_utf8_lossy(&run.stderr)
    );
    run
}

fn pixels(path: &Path) -> Vec<u8> {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
        .into_raw()
}

/// The depth samples of an EXR file, as bits (the file's bytes may differ for the same
/// samples: its tiles are compressed in parallel and written in the order they finish).
fn depth_bits(path: &Path) -> Vec<u32> {
    exr::prelude::read_first_flat_layer_from_file(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .layer_data
        .channel_data
        .list[0]
        .sample_data
        .values_as_f32()
        .map(f32::to_bits)
        .collect()
}

/// The first frame of the sample trajectory, read from each of its three files, gives the
/// same colour, depth and ID images bit for bit (the camera frames each scene alike only if
/// the scenes are the same to the last bit too).
#[test]
fn one_frame_in_three_formats_draws_one_picture() {
    let dir = scratch("formats");
    let mut images = Vec::new();
    for (name, scene) in [("lammps", LAMMPS), ("xyz", XYZ), ("csv", CSV)] {
        let color = dir.join(format!("{name}.png"));
        let depth = dir.join(format!("{name}.exr"));
        let id = dir.join(format!("{name}-id.png"));
        render(
            &["--scene", scene],
            &[("--output", &color), ("--depth", &depth), ("--id", &id)],
        );
        images.push((name, pixels(&color), depth_bits(&depth), pixels(&id)));
    }
    let (_, color, depth, id) = &images[2];
    let drawn = id.chunks(4).filter(|p| p != &[255; 4]).count();
    assert!(drawn > 128 * 96 / 10, "only {drawn} pixels show a glyph");
    for (name, c, d, i) in &images[..2] {
        assert!(c == color, "{name}: colour differs from the CSV's");
        assert!(d == depth, "{name}: depth differs from the CSV's");
        assert!(i == id, "{name}: IDs differ from the CSV's");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--frames 1:5:2` writes frames 1, 3 and 5 and nothing else; frame 1's image is the
/// single-frame render's; the particles move, so frames differ; and frame 5 is drawn with the
/// first frame's camera (as `--save-scene` prints it), not one framing frame 5.
#[test]
fn frames_go_to_numbered_files_with_the_first_frames_camera() {
    let dir = scratch("sequence");
    let pattern = dir.join("frame_%02d.png");
    render(
        &["--scene", LAMMPS, "--frames", "1:5:2"],
        &[("--output", &pattern)],
    );
    let mut written: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["frame_01.png", "frame_03.png", "frame_05.png"]);

    let single = dir.join("single.png");
    let saved = dir.join("frame1.csv");
    render(
        &["--scene", CSV],
        &[("--output", &single), ("--save-scene", &saved)],
    );
    assert!(pixels(&dir.join("frame_01.png")) == pixels(&single));
    assert!(pixels(&dir.join("frame_01.png")) != pixels(&dir.join("frame_05.png")));

    // The first line of the saved scene: `# camera: --eye ... --target ...`.
    let text = std::fs::read_to_string(&saved).unwrap();
    let flags: Vec<&str> = text
        .lines()
        .next()
        .and_then(|l| l.split("camera: ").nth(1))
        .expect("the camera comment")
        .split_whitespace()
        .collect();
    // It names the image size too, which `render` here already gives.
    assert_eq!(flags[..4], ["--width", "128", "--height", "96"]);
    let flags = &flags[4..];
    let fifth = dir.join("fifth.png");
    let mut args = vec!["--scene", LAMMPS, "--frames", "5"];
    args.extend(flags);
    render(&args, &[("--output", &fifth)]);
    // A frame range of one frame still numbers its file.
    assert!(pixels(&dir.join("frame_05.png")) == pixels(&dir.join("fifth_0005.png")));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--movie` hands every frame to ffmpeg: the movie holds as many frames as were drawn, and
/// no colour images are written beside it.
#[test]
fn a_movie_holds_every_frame() {
    let dir = scratch("movie");
    let movie = dir.join("run.mp4");
    let run = render(
        &["--scene", LAMMPS, "--frames", "all", "--fps", "10"],
        &[("--movie", &movie), ("--output", &dir.join("c.png"))],
    );
    let said = String::from_utf8_lossy(&run.stdout);
    // The sample has 8 frames.
    let frames = 8;
    assert!(said.starts_with("wrote 8 frames "), "{said}");
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args(["-show_entries", "stream=nb_read_frames,width,height"])
        .args(["-of", "csv=p=0"])
        .arg(&movie)
        .output()
        .expect("ffprobe (Debian's ffmpeg, scripts/setup.sh) runs");
    let fields = String::from_utf8_lossy(&probe.stdout).trim().to_string();
    assert_eq!(fields, format!("128,96,{frames}"));
    let files: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(files.len(), 1, "only the movie is written");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A frame the loader refuses (frame 3 of the sample, a non-number in its first atom's x)
/// stops the run with an error naming the frame and its timestep; the frames before it are
/// written, none after; with a movie, no movie and no partial file is left.
#[test]
fn a_bad_frame_stops_the_run_naming_it() {
    let dir = scratch("bad-frame");
    let text = std::fs::read_to_string(root().join(LAMMPS)).unwrap();
    let mut frames: Vec<String> = text.split("ITEM: TIMESTEP").map(str::to_string).collect();
    let header = "ITEM: ATOMS id type x y z shapex shapey shapez quatw quati quatj quatk\n";
    let at = frames[3].find(header).expect("frame 3's atoms") + header.len();
    let mut fields: Vec<&str> = frames[3][at..].lines().next().unwrap().split(' ').collect();
    fields[2] = "x?";
    let line_end = at + frames[3][at..].find('\n').unwrap();
    frames[3] = format!(
        "{}{}{}",
        &frames[3][..at],
        fields.join(" "),
        &frames[3][line_end..]
    );
    let bad = dir.join("bad.lammpstrj");
    std::fs::write(&bad, frames.join("ITEM: TIMESTEP")).unwrap();
    let bad = bad.to_str().unwrap();
    for movie in [false, true] {
        let mut command = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"));
        command
            .args(["render", "--validation", "--width", "64", "--height", "48"])
            .args(["--scene", bad, "--frames", "all", "--output"])
            .arg(dir.join("f_%d.png"));
        if movie {
            command.arg("--movie").arg(dir.join("run.mp4"));
        }
        let run = command.output().expect("the binary runs");
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            stderr.contains("bad.lammpstrj:") && stderr.contains("frame 3 (timestep 1000), x"),
            "{stderr}"
        );
        let mut written: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name != "bad.lammpstrj")
            .collect();
        written.sort();
        if movie {
            assert!(written.is_empty(), "{written:?}");
        } else {
            assert_eq!(written, ["f_1.png", "f_2.png"]);
            for name in written {
                std::fs::remove_file(dir.join(name)).unwrap();
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
