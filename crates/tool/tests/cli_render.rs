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

/// Renders `scene` at 96 x 64 with validation and `extra` flags; returns the RGBA8 pixels.
fn render_pixels(dir: &std::path::Path, name: &str, scene: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args(["render", "--validation", "--width", "96", "--height", "64"])
        .args(["--scene", scene])
        .args(extra)
        .arg("--output")
        .arg(&out)
        .output()
        .expect("the binary runs");
    assert!(
        run.status.success(),
        "{name}: exit {:?}: {}",
        run.status.code(),
        String::from_utf8_lossy(&run.stderr)
    );
    image::open(&out).expect("a PNG").to_rgba8().into_raw()
}

/// Largest difference of any channel of any pixel.
fn max_difference(a: &[u8], b: &[u8]) -> u8 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// `--color principal` gives each glyph the absolute components of its long axis's world
/// direction: the picture equals that of the same glyphs with those colours, worked out by
/// hand, written into the file.
#[test]
fn principal_colours_are_the_long_axes_directions() {
    use glam::{DQuat, DVec3};
    let dir =
        std::env::temp_dir().join(format!("ellipsoid-splat-principal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Long axis (local x, y or z) turned to a known unit direction; its colour is |direction|.
    let third = 1.0 / 3.0;
    let glyphs = [
        (
            -4.0,
            DVec3::new(2.0, 0.6, 0.8),
            DVec3::X,
            DVec3::new(third, 2.0 * third, 2.0 * third),
        ),
        (
            0.0,
            DVec3::new(0.5, 2.0, 0.8),
            DVec3::Y,
            DVec3::new(0.6, 0.0, -0.8),
        ),
        (
            4.0,
            DVec3::new(0.6, 0.8, 2.0),
            DVec3::Z,
            DVec3::new(-0.8, 0.6, 0.0),
        ),
    ];
    let header = "x,y,z,rx,ry,rz,qw,qx,qy,qz,r,g,b\n";
    let (mut grey, mut by_hand) = (header.to_string(), header.to_string());
    for (x, radii, long, direction) in glyphs {
        let q = DQuat::from_rotation_arc(long, direction);
        let row = format!(
            "{x},0,0,{},{},{},{},{},{},{}",
            radii.x, radii.y, radii.z, q.w, q.x, q.y, q.z
        );
        let colour = direction.abs();
        grey += &format!("{row},0.5,0.5,0.5\n");
        by_hand += &format!("{row},{},{},{}\n", colour.x, colour.y, colour.z);
    }
    let grey_csv = dir.join("grey.csv");
    let by_hand_csv = dir.join("by-hand.csv");
    std::fs::write(&grey_csv, grey).unwrap();
    std::fs::write(&by_hand_csv, by_hand).unwrap();
    let camera = ["--eye", "0.5,1.5,10", "--target", "0,0,0"];
    let path = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let principal = [&camera[..], &["--color", "principal"]].concat();
    let recoloured = render_pixels(&dir, "principal", &path(&grey_csv), &principal);
    let expected = render_pixels(&dir, "by-hand", &path(&by_hand_csv), &camera);
    let file = render_pixels(&dir, "file", &path(&grey_csv), &camera);
    std::fs::remove_dir_all(&dir).unwrap();
    // The corner is background.
    let background = &recoloured[..4];
    let covered = recoloured.chunks(4).filter(|p| p != &background).count();
    assert!(covered > 500, "the glyphs cover only {covered} pixels");
    // The same colour can round differently in the last bit on its way to 8 bits.
    let difference = max_difference(&recoloured, &expected);
    assert!(
        difference <= 1,
        "differs by {difference} from the colours by hand"
    );
    assert!(
        max_difference(&recoloured, &file) > 60,
        "--color principal left the file's grey"
    );
}

/// The default is the scene's own colouring, which for the tensor field is by shape: the
/// default picture is exactly `--color shape`'s, and other modes change it.
#[test]
fn the_default_colours_are_the_scenes_own() {
    let dir = std::env::temp_dir().join(format!("ellipsoid-splat-default-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = "tensor-field:4";
    let default = render_pixels(&dir, "default", scene, &[]);
    let file = render_pixels(&dir, "file", scene, &["--color", "file"]);
    let shape = render_pixels(&dir, "shape", scene, &["--color", "shape"]);
    let uniform = render_pixels(&dir, "uniform", scene, &["--color", "uniform"]);
    let weighted = render_pixels(&dir, "principal-fa", scene, &["--color", "principal-fa"]);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(default, file);
    assert_eq!(default, shape);
    assert!(max_difference(&default, &uniform) > 60);
    assert!(max_difference(&default, &weighted) > 60);
    // Uniform grey: every pixel but the (blue-grey) background is grey, highlights included
    // (they are white).
    let background = &uniform[..4];
    assert!(background[2] > background[0], "the corner is background");
    let grey = |p: &[u8]| p[0] == p[1] && p[1] == p[2];
    assert!(uniform.chunks(4).all(|p| grey(p) || p == background));
    assert!(uniform.chunks(4).filter(|p| grey(p)).count() > 500);
}

/// `--supersample 3` writes an image of the asked size whose every pixel is the mean, in
/// linear light, of the 3 x 3 block of the same view drawn at three times the size.
#[test]
fn supersampling_is_the_box_filter_of_the_larger_picture() {
    let dir = std::env::temp_dir().join(format!("es-supersample-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = "random:40";
    let camera = ["--eye", "0,0,60", "--target", "0,0,0"];
    let small = render_pixels(
        &dir,
        "small",
        scene,
        &[&camera[..], &["--supersample", "3"]].concat(),
    );
    let out = dir.join("big.png");
    let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args([
            "render",
            "--validation",
            "--width",
            "288",
            "--height",
            "192",
        ])
        .args(["--scene", scene])
        .args(camera)
        .arg("--output")
        .arg(&out)
        .output()
        .expect("the binary runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let big = image::open(&out).unwrap().to_rgba8();
    let linear = |b: u8| {
        let c = b as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let srgb_byte = |v: f64| {
        let c = if v <= 0.0031308 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (c * 255.0).round() as u8
    };
    let mut edges = 0;
    for j in 0..64u32 {
        for i in 0..96u32 {
            for c in 0..3 {
                let block: Vec<f64> = (0..9)
                    .map(|n| linear(big.get_pixel(3 * i + n % 3, 3 * j + n / 3)[c]))
                    .collect();
                let mean = block.iter().sum::<f64>() / 9.0;
                let shown = small[4 * (j * 96 + i) as usize + c];
                // The larger picture is the very samples the filter averaged: the result is
                // the block's mean encoded to the nearest sRGB byte, exactly.
                assert_eq!(
                    shown,
                    srgb_byte(mean),
                    "pixel ({i},{j}) channel {c}: the block's mean is {mean}"
                );
                edges += (c == 0 && block.iter().any(|&v| (v - block[0]).abs() > 0.05)) as usize;
            }
        }
    }
    assert!(edges > 100, "only {edges} pixels mix their samples");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sample count the device does not offer (64: no device in this project's reach offers it)
/// is a named error listing what it does offer.
#[test]
fn a_sample_count_the_device_lacks_is_named() {
    let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args([
            "render",
            "--samples",
            "64",
            "--width",
            "16",
            "--height",
            "16",
        ])
        .arg("--output")
        .arg(std::env::temp_dir().join(format!("es-samples-{}.png", std::process::id())))
        .output()
        .expect("the binary runs");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("--samples") && stderr.contains("this device offers 1"),
        "{stderr}"
    );
}

/// `--intrinsics`, `--jitter` and `--viewport` render what their contract says: the camera
/// they describe sends the ray through pixel centre (i + 0.5, j + 0.5) along
/// ((i + 0.5 + dx - cx) / fx, (j + 0.5 + dy - cy) / fy, 1) in the camera frame (x right, y
/// down, z forward), and the written ID and depth images hold, inside the viewport, the
/// float64 reference's picture of that camera (no coverage or ID mismatch off ambiguous
/// pixels, depth p99 within 1e-6) and background outside.
#[test]
fn camera_flags_render_the_reference_picture() {
    use clap::Parser;
    use ellipsoid_splat_tool::camera_setup::camera_for;
    use ellipsoid_splat_tool::cli::{Cli, Command as Tool};
    use ellipsoid_splat_tool::scene_io::load_colored;
    let dir = std::env::temp_dir().join(format!("ellipsoid-splat-camera-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (fx, fy, cx, cy, dx, dy) = (150.0, 165.0, 58.0, 71.0, 0.31, -0.27);
    let (x0, y0, w, h) = (23u32, 9u32, 140u32, 110u32);
    let args: Vec<String> = [
        "render",
        "--scene",
        "random:800",
        "--width",
        "180",
        "--height",
        "130",
        "--eye",
        "4,5,19",
        "--target",
        "0,0,0",
        "--near",
        "2",
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([
        "--intrinsics".into(),
        format!("{fx},{fy},{cx},{cy}"),
        "--jitter".into(),
        format!("{dx},{dy}"),
        "--viewport".into(),
        format!("{x0},{y0},{w},{h}"),
    ])
    .collect();
    let id_path = dir.join("id.png");
    let depth_path = dir.join("depth.exr");
    let run = Command::new(env!("CARGO_BIN_EXE_ellipsoid-splat"))
        .args(&args)
        .arg("--validation")
        .arg("--output")
        .arg(dir.join("colour.png"))
        .arg("--id")
        .arg(&id_path)
        .arg("--depth")
        .arg(&depth_path)
        .output()
        .expect("the binary runs");
    assert!(
        run.status.success(),
        "exit {:?}: {}",
        run.status.code(),
        String::from_utf8_lossy(&run.stderr)
    );
    let ids: Vec<u32> = image::open(&id_path)
        .unwrap()
        .to_rgba8()
        .into_raw()
        .chunks(4)
        .map(|p| u32::from_le_bytes([p[0], p[1], p[2], p[3]]))
        .collect();
    let depth_image = exr::prelude::read_first_flat_layer_from_file(&depth_path).unwrap();
    let depths: Vec<f32> = depth_image.layer_data.channel_data.list[0]
        .sample_data
        .values_as_f32()
        .collect();
    std::fs::remove_dir_all(&dir).unwrap();

    // The camera the flags describe, and its contract.
    let parsed =
        Cli::try_parse_from(std::iter::once("ellipsoid-splat".to_string()).chain(args)).unwrap();
    let Some(Tool::Render(render)) = parsed.command else {
        panic!("not a render");
    };
    let plan = render.check().unwrap();
    let scene = load_colored(&plan.scene, &render.load).unwrap().scene;
    let camera = camera_for(&render, &scene).unwrap();
    assert_eq!((camera.width, camera.height), (w, h));
    assert_eq!(camera.viewport_origin, [x0, y0]);
    let basis = camera.basis();
    for (i, j) in [(0u32, 0u32), (139, 0), (70, 55), (3, 109)] {
        let ray = camera.ray(i, j);
        let x = (i as f64 + 0.5 + dx - cx) / fx;
        let y = (j as f64 + 0.5 + dy - cy) / fy;
        let want = basis.forward + x * basis.right - y * basis.up;
        assert!((ray.direction - want).length() < 1e-12, "({i}, {j})");
        assert_eq!(ray.origin, camera.eye);
    }

    // The written images against the reference.
    let reference =
        ellipsoid_splat_reference::reference::render_reference(&scene, &camera).unwrap();
    let (mut covered, mut compared, mut errors) = (0, 0, Vec::new());
    for j in 0..130u32 {
        for i in 0..180u32 {
            let k = (j * 180 + i) as usize;
            let inside = (x0..x0 + w).contains(&i) && (y0..y0 + h).contains(&j);
            if !inside {
                assert_eq!(ids[k], u32::MAX, "({i}, {j}) lies outside the viewport");
                assert_eq!(
                    depths[k],
                    f32::INFINITY,
                    "({i}, {j}) lies outside the viewport"
                );
                continue;
            }
            let r = reference.index(i - x0, j - y0);
            covered += (reference.id[r] != u32::MAX) as usize;
            if reference.ambiguous[r] {
                continue;
            }
            assert_eq!(ids[k], reference.id[r], "({i}, {j})");
            if reference.id[r] != u32::MAX {
                compared += 1;
                let want = reference.depth[r];
                errors.push((depths[k] as f64 - want).abs() / want);
            }
        }
    }
    assert!(
        covered > 2_000 && compared > 1_500,
        "{covered} covered, {compared} compared"
    );
    errors.sort_by(f64::total_cmp);
    let p99 = errors[errors.len() * 99 / 100];
    assert!(p99 <= 1e-6, "depth p99 {p99:e}");
}

/// `--save-scene` writes what is drawn: the saved file, drawn with the camera flags on its
/// first line, gives the same pixels as the scene it was saved from.
#[test]
fn a_saved_scene_draws_the_same_frame_with_its_camera_flags() {
    let dir = std::env::temp_dir().join(format!("ellipsoid-splat-saved-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let saved = dir.join("liquid.csv");
    let saved_flag = saved.to_str().unwrap().to_string();
    let original = render_pixels(
        &dir,
        "original",
        "md-liquid:300",
        &["--save-scene", &saved_flag],
    );
    let text = std::fs::read_to_string(&saved).unwrap();
    let camera = text
        .lines()
        .next()
        .and_then(|line| line.strip_prefix("# camera: "))
        .expect("the camera comment comes first")
        .to_string();
    let words: Vec<&str> = camera.split_whitespace().collect();
    assert!(
        words.contains(&"--eye") && words.contains(&"--near"),
        "{camera}"
    );
    assert_eq!(words[..4], ["--width", "96", "--height", "64"], "{camera}");
    // The image size is `render_pixels`' own.
    let flags = &words[4..];
    let again = render_pixels(&dir, "again", &saved_flag, flags);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(original.len(), again.len());
    let differ = original.iter().zip(&again).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "{differ} channel values differ");
}
