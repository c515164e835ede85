//! The C ABI from C and C++, as a host engine gets it: `scripts/install-capi.sh` lays out the
//! header, libraries, pkg-config file and CMake package; a C11 file built with pkg-config's
//! flags and `-Wall -Wextra -Wpedantic -Werror` links and runs; a C++ host built with CMake's
//! `find_package(ellipsoid_splat)` (`tests/cpp_host/`) draws a mesh plane, the ellipsoids
//! cutting it through a jittered projection, and a Dear ImGui window in one subpass of its own
//! render pass, on its own allocator callbacks, under the validation layer (any message fails
//! it). Its pixels are checked here: the glyphs against the float64 reference (coverage and
//! depth), the plane against the analytic plane, the ImGui window against a frame ImGui drew
//! alone. The same host checks the frame plan's calls itself (its `plan` mode).

use std::path::{Path, PathBuf};
use std::process::Command;

use ellipsoid_splat::{Camera, DepthConvention, Ellipsoid, Intrinsics, Projection, Scene};
use ellipsoid_splat_capi::EsGlyph;
use ellipsoid_splat_reference::render_reference;
use glam::{DQuat, DVec3};

const WIDTH: usize = 320;
const HEIGHT: usize = 240;
const PLANE_HALF_SIZE: f64 = 6.0;
/// The ImGui window's rectangle in the host (`host.cpp`), and a margin kept off its border.
const WINDOW: [usize; 4] = [8, 8, 150, 64];
const WINDOW_MARGIN: usize = 2;

fn run(command: &mut Command, what: &str) -> String {
    let output = command
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start: {e}"));
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "{what} failed ({}):\n{stdout}\n{stderr}",
        output.status
    );
    // The layer's own log catches what no messenger heard (before one exists, say).
    for text in [&stdout[..], &stderr[..]] {
        assert!(
            !text.contains("Validation Error") && !text.contains("Validation Warning"),
            "{what}: the validation layer spoke:\n{text}"
        );
    }
    stdout
}

/// The workspace root and the cargo profile directory the libraries were built into.
fn paths() -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let root = root.canonicalize().unwrap();
    let profile = std::env::current_exe()
        .unwrap()
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .to_path_buf();
    (root, profile)
}

/// A fixed scene of ellipsoids around the plane y = 0, many of them cut by it.
fn glyphs() -> Vec<EsGlyph> {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..40)
        .map(|_| {
            let mut v = || 2.0 * next() - 1.0;
            let center = [3.0 * v(), 1.2 * v(), 3.0 * v()];
            let radii = [
                0.3 + 0.3 * (v() + 1.0),
                0.3 + 0.3 * (v() + 1.0),
                0.2 + 0.2 * (v() + 1.0),
            ];
            let q = DQuat::from_xyzw(v(), v(), v(), v() + 1.5).normalize();
            EsGlyph {
                center,
                radii,
                rotation: [q.w, q.x, q.y, q.z],
                color: [0.9, 0.35, 0.2],
            }
        })
        .collect()
}

/// `glyphs` as the host reads them: `EsGlyph` records, field by field, padding zeroed.
fn glyph_bytes(glyphs: &[EsGlyph]) -> Vec<u8> {
    assert_eq!(std::mem::size_of::<EsGlyph>(), 96, "EsGlyph's C layout");
    let mut bytes = Vec::new();
    for g in glyphs {
        for v in g.center.iter().chain(&g.radii).chain(&g.rotation) {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        for c in g.color {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
        bytes.extend_from_slice(&[0; 4]);
    }
    bytes
}

/// The camera the host's matrices made, as `host.cpp` prints it.
fn host_camera(text: &str) -> Camera {
    let v: Vec<f64> = text
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(v.len(), 22, "camera line: {text}");
    assert_eq!(
        v[0], 2.0,
        "the jittered projection gives intrinsics: {text}"
    );
    let vec3 = |k: usize| DVec3::new(v[k], v[k + 1], v[k + 2]);
    let camera = Camera::new(
        vec3(1),
        vec3(4),
        vec3(7),
        Projection::PerspectiveIntrinsics(Intrinsics {
            fx: v[10],
            fy: v[11],
            cx: v[12],
            cy: v[13],
        }),
        v[14],
        v[16] as u32,
        v[17] as u32,
    )
    .unwrap();
    assert_eq!((v[20], v[21]), (1.0, 0.0), "reversed Z, infinite far plane");
    camera
        .with_depth(DepthConvention {
            reversed: true,
            far: None,
        })
        .unwrap()
}

/// The plane's view depth at pixel `(i, j)`, where its square is in view.
fn plane_depth(camera: &Camera, i: usize, j: usize) -> Option<f64> {
    let ray = camera.ray(i as u32, j as u32);
    let t = -ray.origin.y / ray.direction.y;
    let p = ray.origin + t * ray.direction;
    (t > camera.near && p.x.abs() <= PLANE_HALF_SIZE && p.z.abs() <= PLANE_HALF_SIZE).then_some(t)
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Shows {
    Glyph,
    Plane,
    Nothing,
}

fn in_window(i: usize, j: usize, margin: usize) -> bool {
    let [x, y, w, h] = WINDOW;
    i + margin >= x && i < x + w + margin && j + margin >= y && j < y + h + margin
}

/// What the static library needs besides itself, as pkg-config's `--static --libs` lists it
/// (its own `-l` dropped: the archive is named outright).
fn pkg_config_static(prefix: &Path) -> Vec<String> {
    let out = run(
        Command::new("pkg-config")
            .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
            .args(["--static", "--libs", "ellipsoid_splat"]),
        "pkg-config --static",
    );
    out.split_whitespace()
        .filter(|flag| *flag != "-lellipsoid_splat")
        .map(str::to_owned)
        .collect()
}

#[test]
fn a_cpp_host_draws_a_mesh_the_ellipsoids_and_imgui_in_one_render_pass() {
    let (root, profile) = paths();
    let work = profile.join("capi-host");
    let prefix = work.join("install");
    std::fs::create_dir_all(&work).unwrap();
    // `cargo test` builds only the Rust library of this crate: build the C libraries too, in
    // the same profile (cargo releases its lock while tests run).
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut build = Command::new(cargo);
    build
        .args([
            "build",
            "--quiet",
            "-p",
            "ellipsoid-splat-capi",
            "--lib",
            "--manifest-path",
        ])
        .arg(root.join("Cargo.toml"));
    if profile.file_name().is_some_and(|p| p == "release") {
        build.arg("--release");
    }
    run(&mut build, "cargo build (the C libraries)");
    run(
        Command::new("bash")
            .arg(root.join("scripts/install-capi.sh"))
            .arg("--prebuilt")
            .arg(&profile)
            .arg(&prefix),
        "scripts/install-capi.sh",
    );

    // C11 with pkg-config's flags, every warning an error; it links and runs.
    let pkg_config = |flag: &str| {
        let out = run(
            Command::new("pkg-config")
                .env("PKG_CONFIG_PATH", prefix.join("lib/pkgconfig"))
                .args([flag, "ellipsoid_splat"]),
            "pkg-config",
        );
        out.split_whitespace()
            .map(str::to_owned)
            .collect::<Vec<_>>()
    };
    let c_binary = work.join("header_c11");
    run(
        Command::new("cc")
            .args(["-std=c11", "-Wall", "-Wextra", "-Wpedantic", "-Werror"])
            .args(pkg_config("--cflags"))
            .arg(root.join("crates/capi/tests/c/header_c11.c"))
            .args(pkg_config("--libs"))
            .arg(format!("-Wl,-rpath,{}", prefix.join("lib").display()))
            .arg("-o")
            .arg(&c_binary),
        "cc (C11)",
    );
    run(&mut Command::new(&c_binary), "the C11 program");
    // The same against the static library, with what pkg-config says it needs (`--static`).
    let static_binary = work.join("header_c11_static");
    run(
        Command::new("cc")
            .args(["-std=c11", "-Wall", "-Wextra", "-Wpedantic", "-Werror"])
            .args(pkg_config("--cflags"))
            .arg(root.join("crates/capi/tests/c/header_c11.c"))
            .arg(prefix.join("lib/libellipsoid_splat.a"))
            .args(pkg_config_static(&prefix))
            .arg("-o")
            .arg(&static_binary),
        "cc (C11, static)",
    );
    run(
        &mut Command::new(&static_binary),
        "the C11 program, linked statically",
    );
    // The C example of docs/c-and-cpp.md is this file, and compiles the same way.
    let example = root.join("crates/capi/tests/c/embed.c");
    run(
        Command::new("cc")
            .args([
                "-std=c11",
                "-Wall",
                "-Wextra",
                "-Wpedantic",
                "-Werror",
                "-c",
            ])
            .args(pkg_config("--cflags"))
            .arg(&example)
            .arg("-o")
            .arg(work.join("embed.o")),
        "cc (the example of docs/c-and-cpp.md)",
    );
    let guide = std::fs::read_to_string(root.join("docs/c-and-cpp.md")).unwrap();
    let example = std::fs::read_to_string(&example).unwrap();
    assert!(
        guide.contains(&example),
        "docs/c-and-cpp.md does not hold crates/capi/tests/c/embed.c verbatim"
    );

    // The C++ host, found and built by CMake as any project would.
    let build = work.join("cpp_host");
    run(
        Command::new("cmake")
            .arg("-S")
            .arg(root.join("crates/capi/tests/cpp_host"))
            .arg("-B")
            .arg(&build)
            .arg(format!("-DCMAKE_PREFIX_PATH={}", prefix.display()))
            .arg("-DCMAKE_BUILD_TYPE=Release"),
        "cmake configure",
    );
    run(
        Command::new("cmake").arg("--build").arg(&build).arg("-j2"),
        "cmake build",
    );

    let glyphs = glyphs();
    let glyph_file = work.join("glyphs.bin");
    std::fs::write(&glyph_file, glyph_bytes(&glyphs)).unwrap();
    let host = build.join("cpp_host");
    let out_full = work.join("full");
    let out_imgui = work.join("imgui");
    let said = run(
        Command::new(&host)
            .arg(&glyph_file)
            .arg(&out_full)
            .arg("full"),
        "cpp_host full",
    );
    println!("{said}");
    run(
        Command::new(&host)
            .arg(&glyph_file)
            .arg(&out_imgui)
            .arg("imgui"),
        "cpp_host imgui",
    );
    // The frame plan through the C ABI, checked by the host itself: the paths it fixes draw
    // the same picture (bit for bit on lavapipe), the plan that measures settles on the same
    // camera, its wisdom goes to a second renderer and comes back the same, and bad settings,
    // garbage, truncated and damaged bytes are refused with a message.
    let said = run(
        Command::new(&host)
            .arg(&glyph_file)
            .arg(work.join("plan"))
            .arg("plan"),
        "cpp_host plan",
    );
    println!("{said}");
    let read = |prefix: &Path, ext: &str| std::fs::read(prefix.with_extension(ext)).unwrap();
    let rgba = read(&out_full, "rgba");
    let depth: Vec<f32> = read(&out_full, "depth")
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let imgui_alone = read(&out_imgui, "rgba");
    assert_eq!(rgba.len(), 4 * WIDTH * HEIGHT);

    // The glyphs against the reference, the plane against the analytic plane.
    let camera = host_camera(&String::from_utf8(read(&out_full, "camera")).unwrap());
    let scene = Scene::new(
        glyphs
            .iter()
            .map(|g| {
                let [w, x, y, z] = g.rotation;
                Ellipsoid::new(
                    DVec3::from_array(g.center),
                    DVec3::from_array(g.radii),
                    DQuat::from_xyzw(x, y, z, w),
                    Some(g.color),
                )
                .unwrap()
            })
            .collect(),
    );
    let reference = render_reference(&scene, &camera).unwrap();
    let expected = |i: usize, j: usize| -> (Shows, f64) {
        let k = reference.index(i as u32, j as u32);
        let glyph = reference.depth[k];
        match plane_depth(&camera, i, j) {
            Some(plane) if plane <= glyph => (Shows::Plane, plane),
            _ if glyph.is_finite() => (Shows::Glyph, glyph),
            _ => (Shows::Nothing, f64::INFINITY),
        }
    };
    let shows = |i: usize, j: usize| {
        let p = &rgba[4 * (j * WIDTH + i)..4 * (j * WIDTH + i) + 3];
        match p {
            [0, 255, 0] => Shows::Plane,
            [0, 0, 0] => Shows::Nothing,
            _ => Shows::Glyph,
        }
    };
    let (mut compared, mut mismatches, mut near_curve) = (0, Vec::new(), 0);
    let mut depth_errors = Vec::new();
    let mut counts = [0usize; 3];
    for j in 0..HEIGHT {
        for i in 0..WIDTH {
            if in_window(i, j, WINDOW_MARGIN)
                || reference.ambiguous[reference.index(i as u32, j as u32)]
            {
                continue;
            }
            let (want, view_depth) = expected(i, j);
            // Where the plane and a glyph meet, float32 depth tests decide within a pixel.
            let crosses = (j.saturating_sub(1)..(j + 2).min(HEIGHT))
                .flat_map(|y| (i.saturating_sub(1)..(i + 2).min(WIDTH)).map(move |x| (x, y)))
                .any(|(x, y)| {
                    let other = expected(x, y).0;
                    matches!(
                        (want, other),
                        (Shows::Glyph, Shows::Plane) | (Shows::Plane, Shows::Glyph)
                    )
                });
            if crosses {
                near_curve += 1;
                continue;
            }
            compared += 1;
            counts[want as usize] += 1;
            let got = shows(i, j);
            if got != want {
                mismatches.push((i, j, want, got));
                continue;
            }
            if want != Shows::Nothing {
                // Reversed Z, infinite far plane: the depth buffer holds near / view depth.
                let host_depth = camera.near / depth[j * WIDTH + i] as f64;
                depth_errors.push((host_depth - view_depth).abs() / view_depth);
            }
        }
    }
    depth_errors.sort_by(f64::total_cmp);
    let p99 = depth_errors[depth_errors.len() * 99 / 100];
    let max = *depth_errors.last().unwrap();
    println!(
        "{compared} pixels compared (glyph {}, plane {}, background {}), {near_curve} within a \
         pixel of the plane's cut skipped; {} mismatches; depth rel p99 {p99:.2e} max {max:.2e}",
        counts[0],
        counts[1],
        counts[2],
        mismatches.len()
    );
    assert!(
        counts[0] > 2000 && counts[1] > 2000 && counts[2] > 2000,
        "{counts:?}"
    );
    assert!(
        mismatches.is_empty(),
        "first mismatches: {:?}",
        &mismatches[..mismatches.len().min(10)]
    );
    assert!(p99 <= 1e-6 && max <= 1e-4, "depth p99 {p99:e}, max {max:e}");

    // The ImGui window is ImGui's alone: inside it, the frame equals the frame ImGui drew
    // without the renderer (which left the host's state as documented), and it shows text.
    let [x, y, w, h] = WINDOW;
    let mut inside = std::collections::HashSet::new();
    for j in y + WINDOW_MARGIN..y + h - WINDOW_MARGIN {
        for i in x + WINDOW_MARGIN..x + w - WINDOW_MARGIN {
            let k = 4 * (j * WIDTH + i);
            assert_eq!(
                rgba[k..k + 4],
                imgui_alone[k..k + 4],
                "ImGui's window differs at ({i}, {j})"
            );
            inside.insert(rgba[k..k + 3].to_vec());
        }
    }
    // ImGui's default font is a pixel font: its text is pure white on the window.
    let text = (y + WINDOW_MARGIN..y + h - WINDOW_MARGIN)
        .flat_map(|j| (x + WINDOW_MARGIN..x + w - WINDOW_MARGIN).map(move |i| 4 * (j * WIDTH + i)))
        .filter(|&k| rgba[k..k + 3] == [255, 255, 255])
        .count();
    assert!(
        text > 100 && inside.len() >= 3,
        "the ImGui window shows no text ({text} pixels)"
    );
}
