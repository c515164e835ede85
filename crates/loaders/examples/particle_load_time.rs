//! How long a LAMMPS dump takes to load: writes three frames of N ellipsoids (default
//! 100,000; 15 columns, atoms in a scrambled order) to a file in DIR, opens it as a trajectory
//! and prints the time of the opening (read and scan) and of each frame's parse. A benchmark,
//! run by `scripts/trajectory-figures.sh`:
//!
//! ```sh
//! cargo run --release -p ellipsoid-splat-loaders --example particle_load_time -- DIR [N]
//! ```

use std::path::PathBuf;
use std::time::Instant;

use ellipsoid_splat_loaders::{LoadOptions, Trajectory};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().ok_or("usage: particle_load_time DIR [N]")?);
    let n: usize = match args.next() {
        Some(text) => text.parse().map_err(|e| format!("N: {e}"))?,
        None => 100_000,
    };
    let mut text = String::with_capacity(n * 3 * 80);
    for frame in 0..3 {
        text.push_str(&format!(
            "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{n}\nITEM: BOX BOUNDS pp pp pp\n\
             0 100\n0 100\n0 100\nITEM: ATOMS id type x y z vx vy vz shapex shapey shapez \
             quatw quati quatj quatk\n",
            frame * 1000
        ));
        for i in 0..n {
            // A prime stride: ids in a scrambled order, as several processors write them.
            let id = (i * 7919) % n + 1;
            let f = i as f64 * 0.001 + frame as f64;
            text.push_str(&format!(
                "{id} {} {:.6} {:.6} {:.6} 0.1 -0.2 0.3 3 1 1 {:.6} {:.6} 0.25 -0.5\n",
                id % 2 + 1,
                f % 100.0,
                (f * 3.0) % 100.0,
                (f * 7.0) % 100.0,
                f.cos(),
                f.sin(),
            ));
        }
    }
    std::fs::create_dir_all(&dir)?;
    let path = dir.join("load-time.lammpstrj");
    std::fs::write(&path, &text)?;
    let started = Instant::now();
    let trajectory = Trajectory::open(&path, &LoadOptions::default())?;
    println!(
        "open ({} MB read and scanned): {:.1} ms",
        text.len() / 1_000_000,
        started.elapsed().as_secs_f64() * 1e3
    );
    for index in 0..trajectory.len() {
        let started = Instant::now();
        let frame = trajectory.frame(index)?;
        println!(
            "frame {} ({} ellipsoids): {:.1} ms",
            index + 1,
            frame.scene.len(),
            started.elapsed().as_secs_f64() * 1e3
        );
    }
    std::fs::remove_file(&path)?;
    Ok(())
}
