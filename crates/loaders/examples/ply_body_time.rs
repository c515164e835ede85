//! Why `ply.rs` reads binary bodies itself: N reference 3D Gaussian Splatting splats (default
//! 100,000; 62 float properties, little-endian) read in memory by `parse_ply` (header through
//! ply-rs-bw, body at fixed offsets into ellipsoids) and by ply-rs-bw's generic reader (one
//! property map per record, no ellipsoids yet), the two interleaved ROUNDS times (default 7)
//! so that both see the same machine load. Prints each reader's median and the ratio. Run by
//! `scripts/ply-body-figure.sh`:
//!
//! ```sh
//! cargo run --release -p ellipsoid-splat-loaders --example ply_body_time -- [N] [ROUNDS]
//! ```

use std::path::Path;
use std::time::Instant;

use ellipsoid_splat_loaders::ply::parse_ply;
use ellipsoid_splat_loaders::LoadOptions;
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::DefaultElement;

/// The property names of the reference implementation's files, in its order.
fn reference_properties() -> Vec<String> {
    let mut names: Vec<String> = ["x", "y", "z", "nx", "ny", "nz"].map(String::from).to_vec();
    names.extend((0..3).map(|i| format!("f_dc_{i}")));
    names.extend((0..45).map(|i| format!("f_rest_{i}")));
    names.push("opacity".into());
    names.extend((0..3).map(|i| format!("scale_{i}")));
    names.extend((0..4).map(|i| format!("rot_{i}")));
    names
}

/// A binary little-endian file of `n` splats, all valid and all kept.
fn reference_file(n: usize) -> Vec<u8> {
    let properties = reference_properties();
    let mut out = format!("ply\nformat binary_little_endian 1.0\nelement vertex {n}\n");
    for name in &properties {
        out += &format!("property float {name}\n");
    }
    out += "end_header\n";
    let mut bytes = out.into_bytes();
    bytes.reserve(n * properties.len() * 4);
    for i in 0..n {
        let t = i as f32 * 1e-6;
        for name in &properties {
            let v: f32 = match name.as_str() {
                "x" => t.sin(),
                "y" => t.cos(),
                "z" => t,
                "scale_0" | "scale_1" | "scale_2" => -4.0,
                "rot_0" => 1.0,
                "rot_1" => t,
                "opacity" => 2.0,
                _ => 0.1,
            };
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes
}

fn median(mut seconds: Vec<f64>) -> f64 {
    seconds.sort_by(f64::total_cmp);
    seconds[seconds.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut number = |default: usize| -> Result<usize, String> {
        match args.next() {
            Some(text) => text.parse().map_err(|e| format!("'{text}': {e}")),
            None => Ok(default),
        }
    };
    let n = number(100_000)?;
    let rounds = number(7)?.max(1);
    let bytes = reference_file(n);
    let file = Path::new("reference.ply");
    let options = LoadOptions::default();
    let (mut ours, mut generic) = (Vec::new(), Vec::new());
    for _ in 0..rounds {
        let started = Instant::now();
        let loaded = parse_ply(&bytes, file, &options)?;
        ours.push(started.elapsed().as_secs_f64());
        assert_eq!(loaded.scene.len(), n);
        drop(loaded);

        let started = Instant::now();
        let ply = Parser::<DefaultElement>::new().read_ply(&mut bytes.as_slice())?;
        generic.push(started.elapsed().as_secs_f64());
        assert_eq!(ply.payload["vertex"].len(), n);
    }
    let (ours, generic) = (median(ours), median(generic));
    println!(
        "{n} splats ({:.1} MB), median of {rounds} interleaved rounds: parse_ply {:.1} ms \
         (ellipsoids), ply-rs-bw read_ply {:.1} ms (property maps only): {:.0}x",
        bytes.len() as f64 / 1e6,
        ours * 1e3,
        generic * 1e3,
        generic / ours
    );
    Ok(())
}
