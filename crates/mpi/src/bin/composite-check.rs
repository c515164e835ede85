//! The compositing check the tests run under `mpirun -n N`: for each case every rank draws its
//! share of one scene and the frames are composited at rank 0, which also draws the whole
//! scene alone and compares the two bit for bit (colour, view and device depth, normal,
//! global IDs). Cases: glyphs split at random, by space (slabs along x), exact duplicates on
//! different ranks (ties: the lower index must win), one rank with nothing, a glyph cut by the
//! near plane, an orthographic camera, and reversed depth (the ties and reversed depth
//! composited at the last rank, the others at rank 0). Validation is on. The root prints one
//! line a case (`case NAME: match, N pixels shown, most bytes sent by a rank B`) and exits 1
//! on any mismatch; any rank's error ends every rank with status 1.
//!
//! With `--fail-rank R`, rank R's share holds a glyph float32 cannot store: every rank must
//! get an error (R its own, the others naming R), print it as `rank K stopped: ERROR` and
//! exit with status 0; a rank left waiting would keep `mpirun` from ending.
//!
//! Not part of the library: a test driver (`tests/mpirun.rs`), and an example of the API.

use std::process::ExitCode;

use glam::DVec3;
use mpi::traits::*;

use ellipsoid_splat::Projection;
use ellipsoid_splat::{
    Camera, ContextOptions, DepthConvention, Ellipsoid, OffscreenRenderer, Outputs, Scene,
};
use ellipsoid_splat_mpi::render_composited;

/// SplitMix64: a fixed, well-spread hash of a glyph index (the same on every rank).
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A uniform number in [0, 1) from `mix` of `seed`.
fn unit(seed: u64) -> f64 {
    (mix(seed) >> 11) as f64 / (1u64 << 53) as f64
}

/// `n` randomly placed, sized and turned ellipsoids in a cube of side 12 (the same on every
/// rank: a hash of the index, not a random generator's state).
fn cloud(n: usize) -> Result<Scene, ellipsoid_splat::Error> {
    let glyphs = (0..n as u64)
        .map(|i| {
            let u = |k: u64| unit(i * 16 + k);
            let center = DVec3::new(u(0), u(1), u(2)) * 12.0 - 6.0;
            let radii = DVec3::new(u(3), u(4), u(5)) * 0.45 + 0.15;
            let q = glam::DQuat::from_xyzw(u(6) - 0.5, u(7) - 0.5, u(8) - 0.5, u(9) - 0.5 + 1e-3);
            let color = [u(10) as f32, u(11) as f32, u(12) as f32];
            Ellipsoid::new(center, radii, q.normalize(), Some(color))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Scene::new(glyphs))
}

/// The rank a glyph (its index and itself) goes to.
type Owner = Box<dyn Fn(usize, &Ellipsoid) -> i32>;

struct Case {
    name: &'static str,
    /// Where the frame is composited: rank 0, or the last rank (an extra, folded one when the
    /// count is not a power of two).
    at_last_rank: bool,
    scene: Scene,
    camera: Camera,
    /// The rank each glyph goes to.
    owner: Owner,
}

fn cases(size: i32) -> Result<Vec<Case>, Box<dyn std::error::Error>> {
    let (w, h) = (160, 120);
    let cloud = cloud(3000)?;
    let perspective = |eye: DVec3, near: f64| {
        Camera::new(
            eye,
            DVec3::ZERO,
            DVec3::Y,
            Projection::Perspective { fov_y_deg: 45.0 },
            near,
            w,
            h,
        )
    };
    let far_eye = DVec3::new(4.0, 6.0, 30.0);
    // Exact duplicates: glyph i and i + n are the same ellipsoid, on different ranks.
    let mut doubled = cloud.ellipsoids[..1500].to_vec();
    doubled.extend_from_slice(&cloud.ellipsoids[..1500]);
    let n = 1500;
    // The near plane through the middle of glyph 0 (the eye looks at it from 8 units).
    let cut = cloud.ellipsoids[0];
    let cut_eye = cut.center + DVec3::new(0.0, 0.0, 8.0);
    let cut_camera = Camera::new(
        cut_eye,
        cut.center,
        DVec3::Y,
        Projection::Perspective { fov_y_deg: 60.0 },
        8.0,
        w,
        h,
    )?;
    let xs: Vec<f64> = cloud.ellipsoids.iter().map(|e| e.center.x).collect();
    let (lo, hi) = xs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    let random = move |i: usize, _: &Ellipsoid| (mix(i as u64) % size as u64) as i32;
    Ok(vec![
        Case {
            name: "random",
            at_last_rank: false,
            scene: cloud.clone(),
            camera: perspective(far_eye, 5.0)?,
            owner: Box::new(random),
        },
        Case {
            name: "space",
            at_last_rank: false,
            scene: cloud.clone(),
            camera: perspective(far_eye, 5.0)?,
            owner: Box::new(move |_, e| {
                (((e.center.x - lo) / (hi - lo + 1e-9)) * size as f64) as i32
            }),
        },
        Case {
            name: "ties",
            at_last_rank: true,
            scene: Scene::new(doubled),
            camera: perspective(far_eye, 5.0)?,
            owner: Box::new(move |i, _| ((i % n) as i32 + i32::from(i >= n)) % size),
        },
        Case {
            name: "one-empty",
            at_last_rank: false,
            scene: cloud.clone(),
            camera: perspective(far_eye, 5.0)?,
            // The last rank gets nothing (with one rank: everything, as ever).
            owner: Box::new(move |i, _| {
                if size == 1 {
                    0
                } else {
                    (mix(i as u64) % (size - 1) as u64) as i32
                }
            }),
        },
        Case {
            name: "near-cut",
            at_last_rank: false,
            scene: cloud.clone(),
            camera: cut_camera,
            owner: Box::new(random),
        },
        Case {
            name: "orthographic",
            at_last_rank: false,
            scene: cloud.clone(),
            camera: Camera::new(
                far_eye,
                DVec3::ZERO,
                DVec3::Y,
                Projection::Orthographic { height: 20.0 },
                5.0,
                w,
                h,
            )?,
            owner: Box::new(random),
        },
        Case {
            name: "reversed-depth",
            at_last_rank: true,
            scene: cloud,
            camera: perspective(far_eye, 5.0)?.with_depth(DepthConvention::REVERSED_INFINITE)?,
            owner: Box::new(random),
        },
    ])
}

fn main() -> ExitCode {
    let Some(universe) = mpi::initialize() else {
        eprintln!("composite-check: MPI was initialised already");
        return ExitCode::FAILURE;
    };
    let world = universe.world();
    match run(&world) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            // No abort: the ranks fail together (render_composited's all-reduce), and a rank
            // that exits with an error makes mpirun end the others. One write, so the
            // processes' lines do not interleave.
            let line = format!("composite-check: rank {}: {e}\n", world.rank());
            let _ = std::io::Write::write_all(&mut std::io::stderr(), line.as_bytes());
            ExitCode::FAILURE
        }
    }
}

fn run<C: Communicator>(world: &C) -> Result<bool, Box<dyn std::error::Error>> {
    let (rank, size) = (world.rank(), world.size());
    let mut renderer = OffscreenRenderer::new(&ContextOptions::validated())?;
    let args: Vec<String> = std::env::args().collect();
    if let Some(failing) = args.iter().position(|a| a == "--fail-rank") {
        let failing: i32 = args
            .get(failing + 1)
            .and_then(|r| r.parse().ok())
            .ok_or("--fail-rank needs a rank")?;
        let mut part = cloud(100)?;
        if rank == failing {
            // Semi-axes float32 rounds to 0: the upload refuses the glyph (and the whole
            // scene's bounds, which every rank's placement comes from, stay sound).
            part.ellipsoids[7].radii = DVec3::splat(1e-50);
        }
        let ids: Vec<u32> = (0..100).collect();
        let camera = cases(size)?.remove(0).camera;
        let error =
            match render_composited(world, 0, &mut renderer, &part, &ids, &camera, Outputs::ALL) {
                Ok(_) => return Err("the failing rank's error did not reach this rank".into()),
                Err(error) => error,
            };
        let expected = match &error {
            ellipsoid_splat_mpi::Error::Renderer(_) => rank == failing,
            ellipsoid_splat_mpi::Error::OtherRank { rank: named } => *named == failing,
            _ => false,
        };
        if !expected {
            return Err(format!("rank {rank} got the wrong error: {error}").into());
        }
        let line = format!("rank {rank} stopped: {error}\n");
        std::io::Write::write_all(&mut std::io::stdout(), line.as_bytes())?;
        return Ok(true);
    }
    let mut all_match = true;
    for case in cases(size)? {
        let mine: Vec<usize> = case
            .scene
            .ellipsoids
            .iter()
            .enumerate()
            .filter(|&(i, e)| (case.owner)(i, e).clamp(0, size - 1) == rank)
            .map(|(i, _)| i)
            .collect();
        let part = Scene::new(mine.iter().map(|&i| case.scene.ellipsoids[i]).collect());
        let ids: Vec<u32> = mine.iter().map(|&i| i as u32).collect();
        let root = if case.at_last_rank { size - 1 } else { 0 };
        let done = render_composited(
            world,
            root,
            &mut renderer,
            &part,
            &ids,
            &case.camera,
            Outputs::ALL,
        )?;
        let mut most = 0u64;
        world.all_reduce_into(
            &done.traffic.bytes,
            &mut most,
            mpi::collective::SystemOperation::max(),
        );
        if let Some(composited) = done.frame {
            renderer.upload(&case.scene)?;
            let (whole, _) = renderer.render_views(
                case.camera.width,
                case.camera.height,
                &[case.camera],
                Outputs::ALL,
            )?;
            let differing = (0..whole.len())
                .filter(|&p| {
                    whole.color[p] != composited.color[p]
                        || whole.depth[p].to_bits() != composited.depth[p].to_bits()
                        || whole.device_depth[p].to_bits() != composited.device_depth[p].to_bits()
                        || whole.normal[p].map(f32::to_bits)
                            != composited.normal[p].map(f32::to_bits)
                        || whole.id[p] != composited.id[p]
                })
                .count();
            let shown = whole
                .id
                .iter()
                .filter(|&&id| id != ellipsoid_splat::NO_INSTANCE)
                .count();
            let verdict = if differing == 0 {
                "match".to_string()
            } else {
                format!("MISMATCH in {differing} pixels")
            };
            println!(
                "case {}: {verdict}, {shown} pixels shown, most bytes sent by a rank {most}",
                case.name
            );
            all_match &= differing == 0 && shown > 0;
        }
    }
    renderer.context().check_validation()?;
    Ok(all_match)
}
