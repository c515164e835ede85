//! The Rust API's frame of a scene file, for the Python tests to compare with byte for byte:
//! loads `SCENE` with the loaders, renders it with `OffscreenRenderer` and the camera given,
//! and writes `OUT.color` (RGBA8), `OUT.depth` (f32), `OUT.normal` (3 x f32) and `OUT.id`
//! (u32), raw little-endian, row 0 at the top.
//!
//! ```sh
//! rust_frame SCENE OUT ex,ey,ez tx,ty,tz ux,uy,uz FOV_Y NEAR WIDTH HEIGHT
//! ```

use std::path::Path;

use ellipsoid_splat::{Camera, ContextOptions, OffscreenRenderer, Outputs, Projection};
use ellipsoid_splat_loaders::{load, LoadOptions};
use glam::DVec3;

fn vec3(text: &str) -> DVec3 {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.parse().expect("a number"))
        .collect();
    DVec3::new(v[0], v[1], v[2])
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    assert_eq!(
        args.len(),
        9,
        "usage: rust_frame SCENE OUT EYE TARGET UP FOV_Y NEAR W H"
    );
    let scene = load(Path::new(&args[0]), &LoadOptions::default())
        .expect("scene")
        .scene;
    let camera = Camera::new(
        vec3(&args[2]),
        vec3(&args[3]),
        vec3(&args[4]),
        Projection::Perspective {
            fov_y_deg: args[5].parse().expect("fov"),
        },
        args[6].parse().expect("near"),
        args[7].parse().expect("width"),
        args[8].parse().expect("height"),
    )
    .expect("camera");
    let mut renderer = OffscreenRenderer::new(&ContextOptions::default()).expect("device");
    let frame = renderer
        .render(&scene, &camera, Outputs::ALL)
        .expect("frame");
    let out = &args[1];
    let write = |ext: &str, bytes: Vec<u8>| std::fs::write(format!("{out}.{ext}"), bytes).unwrap();
    write("color", frame.color.iter().flatten().copied().collect());
    write(
        "depth",
        frame.depth.iter().flat_map(|v| v.to_le_bytes()).collect(),
    );
    write(
        "normal",
        frame
            .normal
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect(),
    );
    write(
        "id",
        frame.id.iter().flat_map(|v| v.to_le_bytes()).collect(),
    );
    renderer.finish().expect("clean shutdown");
}
