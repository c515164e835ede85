//! The viewer on a lost device: `ellipsoid-splat view` under Xvfb, with validation on and the
//! fault layer losing the device a few frames in (armed through `ES_FAULT_ARM`, since the
//! viewer is another process), says so and exits with an error, its window gone with it --
//! no hang, no panic, no validation message. The same run without the fault exits cleanly,
//! so the layer alone changes nothing.

mod support;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Longer than a sound run takes under load; a viewer still running then has hung.
const HANG: Duration = Duration::from_secs(180);

/// The tool beside this test in `target/<profile>` (`scripts/suite.sh` builds it first).
fn tool() -> PathBuf {
    let exe = std::env::current_exe().expect("the test executable's path");
    let profile = exe
        .parent()
        .and_then(|deps| deps.parent())
        .expect("target/<profile>/deps");
    let tool = profile.join("ellipsoid-splat");
    assert!(
        tool.exists(),
        "{} is missing: build the tool first (`cargo build --release -p ellipsoid-splat-tool`, \
         as scripts/suite.sh does)",
        tool.display()
    );
    tool
}

/// What a run of the viewer ended with.
struct Ended {
    success: bool,
    output: String,
}

/// Runs the viewer for 400 loop turns on a small generated scene, the layer armed by `arm`
/// (none: counting only), and fails the test if it is still running after [`HANG`].
fn view(arm: Option<&str>) -> Ended {
    let found = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .output()
        .is_ok_and(|o| o.status.success());
    assert!(
        found,
        "xvfb-run is missing (scripts/setup.sh installs the Debian packages xvfb and xauth)"
    );
    // Installs the layer for this process's children (VK_INSTANCE_LAYERS, VK_ADD_LAYER_PATH).
    support::layer::layer();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("viewer-lost");
    std::fs::create_dir_all(&dir).expect("the run's directory");
    let mut command = Command::new("xvfb-run");
    command
        .args(["-a", "-s", "-screen 0 640x480x24"])
        .arg(tool())
        .args(["view", "--validation", "--no-vsync", "--width", "160"])
        .args(["--height", "120", "--exit-after", "400", "random:300"])
        .current_dir(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .env_remove("ES_FAULT_ARM");
    if let Some(arm) = arm {
        command.env("ES_FAULT_ARM", arm);
    }
    let mut child = command.spawn().expect("xvfb-run starts");
    let started = Instant::now();
    loop {
        if child.try_wait().expect("the viewer's status").is_some() {
            break;
        }
        if started.elapsed() > HANG {
            let _ = child.kill();
            let output = child
                .wait_with_output()
                .expect("the killed viewer's output");
            panic!(
                "the viewer ({arm:?}) still ran after {HANG:?}: it hung\n{}\n{}",
                String::from_utf8_lossy(&output.stdout),
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let output = child.wait_with_output().expect("the viewer's output");
    Ended {
        success: output.status.success(),
        output: format!(
            "{}{}",
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        ),
    }
}

#[test]
fn the_viewer_says_the_device_is_lost_and_exits() {
    let sound = view(None);
    assert!(
        sound.success && sound.output.contains("validation messages: 0"),
        "without a fault the viewer must run cleanly under the layer:\n{}",
        sound.output
    );
    // The 60th call that can report a loss (submits, waits, queries): a few frames in.
    let lost = view(Some("device-lost:60"));
    let said = lost.output.to_lowercase();
    assert!(
        !lost.success,
        "the viewer ended well on a lost device:\n{}",
        lost.output
    );
    assert!(
        said.contains("lost"),
        "the viewer did not say the device was lost:\n{}",
        lost.output
    );
    for sign in ["panicked", "vuid", "validation error"] {
        assert!(
            !said.contains(sign),
            "`{sign}` in the viewer's output:\n{}",
            lost.output
        );
    }
}
