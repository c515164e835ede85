//! Renders through the command line that need more than an error path.

use std::process::Command;

/// A colour-only render at the largest image side allocates no normal or ID target (it once
/// failed allocating a 4 GiB normal target nobody asked for) and writes exactly the one file.
#[test]
fn largest_colour_only_render_allocates_only_what_it_writes() {
    let dir = std::env::temp_dir().join(format!("ellipsoid-splat-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.png");
    let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args([
            "render",
            "--scene",
            "random:50",
            "--width",
            "16384",
            "--height",
            "16384",
        ])
        .arg("--output")
        .arg(&out)
        .output()
        .expect("the binary runs");
    let written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        run.status.success(),
        "exit {:?}: {}",
        run.status.code(),
        String::from_utf8_lossy(&run.stderr)
    );
    assert_eq!(written, vec![std::ffi::OsString::from("big.png")]);
    // A 16384 x 16384 PNG, even of an almost uniform background, is megabytes.
    assert!(size > 1 << 20, "big.png has {size} bytes");
}
