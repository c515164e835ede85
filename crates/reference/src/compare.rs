//! Error of a GPU frame against the float64 reference (`docs/design.md` §9.2): coverage, depth,
//! normal and instance-ID errors, and bounds to check them against.

use std::fmt;

use glam::DVec3;

use crate::reference::ReferenceFrame;
use ellipsoid_splat::{Error, Result};
use ellipsoid_splat::{Frame, NO_INSTANCE};

/// How far a GPU frame is from the reference.
///
/// Depth and normal errors are taken over the *compared* pixels: covered in both frames, not
/// ambiguous, and showing the same instance. A pixel counts as covered when its instance ID is
/// not [`NO_INSTANCE`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Pixels in the frame.
    pub pixels: usize,
    /// Pixels the reference covers (ambiguous ones included).
    pub covered_pixels: usize,
    /// Pixels the reference marks ambiguous (centre within a hair of a discontinuity, or a
    /// depth tie); they are left out of every comparison below.
    pub ambiguous_pixels: usize,
    /// Non-ambiguous pixels covered in exactly one of the two frames.
    pub coverage_mismatch: usize,
    /// `coverage_mismatch / max(covered_pixels, 1)`.
    pub coverage_mismatch_fraction: f64,
    /// Pixels the depth and normal statistics are taken over.
    pub compared_pixels: usize,
    /// 99th percentile of the relative view-depth error `|gpu - ref| / ref`.
    pub depth_rel_p99: f64,
    /// Largest relative view-depth error.
    pub depth_rel_max: f64,
    /// 99th percentile of the view-depth error in float32 ULPs at the reference depth.
    pub depth_ulp_p99: f64,
    /// 99th percentile of the angle between GPU and reference normals, in degrees.
    pub normal_deg_p99: f64,
    /// Largest normal angle error, in degrees.
    pub normal_deg_max: f64,
    /// Non-ambiguous pixels covered in both frames with different instance IDs.
    pub id_mismatch: usize,
    /// `id_mismatch / max(covered_pixels, 1)`.
    pub id_mismatch_fraction: f64,
    /// 99th percentile of [`FLOOR_FACTOR`] times the reference's float32 depth floor
    /// ([`ReferenceFrame::depth_floor`]): the relative depth error float32 cannot avoid here.
    pub depth_floor_p99: f64,
    /// 99th percentile of [`FLOOR_FACTOR`] times the float32 normal floor, in degrees.
    pub normal_floor_p99: f64,
    /// Relative depth error with each pixel's error divided by how far its float32 floor
    /// exceeds the strict bound (`max(1, FLOOR_FACTOR floor / 1e-6)`); equal to the raw error
    /// wherever the problem is well conditioned. The bounds are checked on these.
    pub depth_cond_p99: f64,
    /// Largest floor-scaled relative depth error.
    pub depth_cond_max: f64,
    /// Normal angle error scaled the same way against the strict 0.01 degree bound.
    pub normal_cond_p99: f64,
    /// Largest floor-scaled normal angle error, in degrees.
    pub normal_cond_max: f64,
}

/// How many times its float32 floor a pixel's error may be before the excess counts against a
/// bound. The floor is a first-order estimate of one rounding of the inputs; 2 allows for the
/// arithmetic on top of it. Where the floor is below the strict bound (every well-conditioned
/// pixel) it changes nothing.
pub const FLOOR_FACTOR: f64 = 2.0;

/// Largest acceptable errors; [`ErrorStats::check`] compares against them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Bound on [`ErrorStats::coverage_mismatch_fraction`].
    pub coverage_fraction: f64,
    /// Bound on [`ErrorStats::depth_rel_p99`].
    pub depth_rel_p99: f64,
    /// Bound on [`ErrorStats::depth_rel_max`].
    pub depth_rel_max: f64,
    /// Bound on [`ErrorStats::normal_deg_p99`].
    pub normal_deg_p99: f64,
    /// Bound on [`ErrorStats::normal_deg_max`].
    pub normal_deg_max: f64,
    /// Bound on [`ErrorStats::id_mismatch_fraction`].
    pub id_mismatch_fraction: f64,
}

impl Bounds {
    /// The accuracy the exact renderer must reach.
    pub const STRICT: Bounds = Bounds {
        coverage_fraction: 1e-3,
        depth_rel_p99: 1e-6,
        depth_rel_max: 1e-4,
        normal_deg_p99: 0.01,
        normal_deg_max: 0.5,
        id_mismatch_fraction: 1e-3,
    };
}

/// Measures `gpu` against `reference`; errors when their sizes differ.
pub fn compare(gpu: &Frame, reference: &ReferenceFrame) -> Result<ErrorStats> {
    check_sizes(gpu, reference)?;
    let pixels = reference.len();
    let mut stats = ErrorStats {
        pixels,
        ..ErrorStats::default()
    };
    let mut depth_rel = Vec::new();
    let mut depth_ulp = Vec::new();
    let mut normal_deg = Vec::new();
    let mut depth_floor = Vec::new();
    let mut normal_floor = Vec::new();
    let mut depth_cond = Vec::new();
    let mut normal_cond = Vec::new();
    let strict = Bounds::STRICT;
    for k in 0..pixels {
        let ref_id = reference.id[k];
        let gpu_id = gpu.id[k];
        let ref_hit = ref_id != NO_INSTANCE;
        let gpu_hit = gpu_id != NO_INSTANCE;
        if ref_hit {
            stats.covered_pixels += 1;
        }
        if reference.ambiguous[k] {
            stats.ambiguous_pixels += 1;
            continue;
        }
        if ref_hit != gpu_hit {
            stats.coverage_mismatch += 1;
            continue;
        }
        if !ref_hit {
            continue;
        }
        if ref_id != gpu_id {
            stats.id_mismatch += 1;
            continue;
        }
        let want = reference.depth[k];
        let error = (gpu.depth[k] as f64 - want).abs();
        let relative = or_infinite(error / want.abs());
        depth_rel.push(relative);
        depth_ulp.push(or_infinite(error / f32_ulp(want)));
        let [x, y, z] = gpu.normal[k];
        let got = DVec3::new(x as f64, y as f64, z as f64);
        let angle = or_infinite(angle_deg(got, reference.normal[k]));
        normal_deg.push(angle);
        let floor_d = FLOOR_FACTOR * reference.depth_floor[k];
        let floor_n = FLOOR_FACTOR * reference.normal_floor_deg[k];
        depth_floor.push(floor_d);
        normal_floor.push(floor_n);
        depth_cond.push(relative / (floor_d / strict.depth_rel_p99).max(1.0));
        normal_cond.push(angle / (floor_n / strict.normal_deg_p99).max(1.0));
    }
    let covered = stats.covered_pixels.max(1) as f64;
    stats.coverage_mismatch_fraction = stats.coverage_mismatch as f64 / covered;
    stats.id_mismatch_fraction = stats.id_mismatch as f64 / covered;
    stats.compared_pixels = depth_rel.len();
    stats.depth_rel_max = maximum(&depth_rel);
    stats.depth_rel_p99 = percentile(&mut depth_rel, 0.99);
    stats.depth_ulp_p99 = percentile(&mut depth_ulp, 0.99);
    stats.normal_deg_max = maximum(&normal_deg);
    stats.normal_deg_p99 = percentile(&mut normal_deg, 0.99);
    stats.depth_floor_p99 = percentile(&mut depth_floor, 0.99);
    stats.normal_floor_p99 = percentile(&mut normal_floor, 0.99);
    stats.depth_cond_max = maximum(&depth_cond);
    stats.depth_cond_p99 = percentile(&mut depth_cond, 0.99);
    stats.normal_cond_max = maximum(&normal_cond);
    stats.normal_cond_p99 = percentile(&mut normal_cond, 0.99);
    Ok(stats)
}

fn check_sizes(gpu: &Frame, reference: &ReferenceFrame) -> Result<()> {
    if (gpu.width, gpu.height) != (reference.width, reference.height) {
        return Err(Error::invalid(
            "frame comparison",
            format!(
                "GPU frame is {}x{} but the reference is {}x{}",
                gpu.width, gpu.height, reference.width, reference.height
            ),
        ));
    }
    let n = reference.len();
    let lengths = [
        ("GPU depth", gpu.depth.len()),
        ("GPU normal", gpu.normal.len()),
        ("GPU id", gpu.id.len()),
        ("reference depth", reference.depth.len()),
        ("reference normal", reference.normal.len()),
        ("reference id", reference.id.len()),
        ("reference ambiguous", reference.ambiguous.len()),
        ("reference depth floor", reference.depth_floor.len()),
        ("reference normal floor", reference.normal_floor_deg.len()),
    ];
    for (name, len) in lengths {
        if len != n {
            return Err(Error::invalid(
                "frame comparison",
                format!("{name} has {len} pixels, expected {n}"),
            ));
        }
    }
    Ok(())
}

/// NaN errors (a NaN depth or normal from the GPU) count as infinitely wrong, so no bound
/// passes them and sorting stays total.
fn or_infinite(error: f64) -> f64 {
    if error.is_nan() {
        f64::INFINITY
    } else {
        error
    }
}

/// Spacing of float32 values at `x`: `2^(e - 23)` for `x` in `[2^e, 2^(e+1))`, floored at the
/// subnormal spacing.
fn f32_ulp(x: f64) -> f64 {
    let exponent = ((x.abs().to_bits() >> 52) & 0x7ff) as i32 - 1023;
    2f64.powi(exponent.max(-126) - 23)
}

/// Angle between two vectors in degrees; `atan2(|a x b|, a . b)` stays accurate at tiny angles
/// where `acos` of the dot product loses everything.
fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

fn maximum(values: &[f64]) -> f64 {
    values.iter().copied().fold(0.0, f64::max)
}

/// Nearest-rank percentile (`p` in (0, 1]) of `values`, sorting them; 0 when empty.
fn percentile(values: &mut [f64], p: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_unstable_by(f64::total_cmp);
    let rank = (p * values.len() as f64).ceil() as usize;
    values[rank.clamp(1, values.len()) - 1]
}

impl ErrorStats {
    /// `Ok` when every statistic is within `bounds`; otherwise a message naming each broken
    /// bound with the measured value. Depth and normal errors are checked after scaling by the
    /// float32 floor (the `*_cond_*` fields), which leaves well-conditioned pixels unchanged.
    pub fn check(&self, bounds: &Bounds) -> Result<(), String> {
        let checks = [
            (
                "coverage mismatch fraction",
                self.coverage_mismatch_fraction,
                bounds.coverage_fraction,
            ),
            (
                "depth relative error p99 (beyond float32 floor)",
                self.depth_cond_p99,
                bounds.depth_rel_p99,
            ),
            (
                "depth relative error max (beyond float32 floor)",
                self.depth_cond_max,
                bounds.depth_rel_max,
            ),
            (
                "normal angle p99 (deg, beyond float32 floor)",
                self.normal_cond_p99,
                bounds.normal_deg_p99,
            ),
            (
                "normal angle max (deg, beyond float32 floor)",
                self.normal_cond_max,
                bounds.normal_deg_max,
            ),
            (
                "instance ID mismatch fraction",
                self.id_mismatch_fraction,
                bounds.id_mismatch_fraction,
            ),
        ];
        let broken: Vec<String> = checks
            .iter()
            .filter(|(_, measured, bound)| measured.is_nan() || measured > bound)
            .map(|(name, measured, bound)| format!("{name} {measured:.3e} > {bound:.3e}"))
            .collect();
        if broken.is_empty() {
            Ok(())
        } else {
            Err(broken.join("; "))
        }
    }
}

impl fmt::Display for ErrorStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} px, {} covered, {} ambiguous, {} compared | coverage mismatch {} ({:.2e}) | \
             depth rel p99 {:.2e} max {:.2e}, p99 {:.2} ulp (f32 floor {:.1e}; beyond it p99 \
             {:.2e} max {:.2e}) | normal p99 {:.2e} max {:.2e} deg (f32 floor {:.1e}; beyond it \
             p99 {:.2e} max {:.2e}) | id mismatch {} ({:.2e})",
            self.pixels,
            self.covered_pixels,
            self.ambiguous_pixels,
            self.compared_pixels,
            self.coverage_mismatch,
            self.coverage_mismatch_fraction,
            self.depth_rel_p99,
            self.depth_rel_max,
            self.depth_ulp_p99,
            self.depth_floor_p99,
            self.depth_cond_p99,
            self.depth_cond_max,
            self.normal_deg_p99,
            self.normal_deg_max,
            self.normal_floor_p99,
            self.normal_cond_p99,
            self.normal_cond_max,
            self.id_mismatch,
            self.id_mismatch_fraction,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `w x h` pair of frames where both see nothing.
    fn blank(w: u32, h: u32) -> (Frame, ReferenceFrame) {
        let n = (w * h) as usize;
        let gpu = Frame {
            width: w,
            height: h,
            color: vec![[0; 4]; n],
            depth: vec![f32::INFINITY; n],
            device_depth: vec![1.0; n],
            normal: vec![[0.0; 3]; n],
            id: vec![NO_INSTANCE; n],
        };
        let reference = ReferenceFrame {
            width: w,
            height: h,
            depth: vec![f64::INFINITY; n],
            normal: vec![DVec3::ZERO; n],
            id: vec![NO_INSTANCE; n],
            ambiguous: vec![false; n],
            depth_floor: vec![0.0; n],
            normal_floor_deg: vec![0.0; n],
            layers: vec![0; n],
        };
        (gpu, reference)
    }

    fn set_ref(r: &mut ReferenceFrame, k: usize, id: u32, depth: f64, normal: DVec3) {
        r.id[k] = id;
        r.depth[k] = depth;
        r.normal[k] = normal;
    }

    fn set_gpu(g: &mut Frame, k: usize, id: u32, depth: f32, normal: [f32; 3]) {
        g.id[k] = id;
        g.depth[k] = depth;
        g.normal[k] = normal;
    }

    #[test]
    fn every_statistic_on_a_hand_made_frame() {
        let (mut gpu, mut reference) = blank(3, 2);
        // 0: both miss.
        // 1: same instance, depth one float32 ULP off (2^-21 at 4), normal 45 degrees off.
        set_ref(&mut reference, 1, 0, 4.0, DVec3::Z);
        set_gpu(&mut gpu, 1, 0, 4.0 + 2f32.powi(-21), [1.0, 0.0, 1.0]);
        // 2: reference hit, GPU miss.
        set_ref(&mut reference, 2, 1, 2.0, DVec3::Z);
        // 3: GPU hit, reference miss.
        set_gpu(&mut gpu, 3, 1, 2.0, [0.0, 0.0, 1.0]);
        // 4: both hit, different instances (their depths are not compared).
        set_ref(&mut reference, 4, 1, 3.0, DVec3::Z);
        set_gpu(&mut gpu, 4, 2, 30.0, [0.0, 0.0, 1.0]);
        // 5: ambiguous reference hit that the GPU misses: ignored.
        set_ref(&mut reference, 5, 2, 3.0, DVec3::Z);
        reference.ambiguous[5] = true;

        let s = compare(&gpu, &reference).unwrap();
        assert_eq!(s.pixels, 6);
        assert_eq!(s.covered_pixels, 4);
        assert_eq!(s.ambiguous_pixels, 1);
        assert_eq!(s.coverage_mismatch, 2);
        assert_eq!(s.coverage_mismatch_fraction, 0.5);
        assert_eq!(s.compared_pixels, 1);
        assert_eq!(s.depth_rel_p99, 2f64.powi(-23));
        assert_eq!(s.depth_rel_max, 2f64.powi(-23));
        assert_eq!(s.depth_ulp_p99, 1.0);
        assert!(
            (s.normal_deg_p99 - 45.0).abs() < 1e-12,
            "{}",
            s.normal_deg_p99
        );
        assert!((s.normal_deg_max - 45.0).abs() < 1e-12);
        assert_eq!(s.id_mismatch, 1);
        assert_eq!(s.id_mismatch_fraction, 0.25);

        let message = s.check(&Bounds::STRICT).unwrap_err();
        for name in [
            "coverage",
            "normal angle p99",
            "normal angle max",
            "instance ID",
        ] {
            assert!(message.contains(name), "{message}");
        }
        assert!(!message.contains("depth"), "{message}");
        assert!(message.contains("5.000e-1 > 1.000e-3"), "{message}");
        assert!(!s.to_string().contains('\n'));
    }

    #[test]
    fn percentiles_are_nearest_rank() {
        let (mut gpu, mut reference) = blank(10, 10);
        // Pixel k has relative depth error (k + 1) / 1024, exact in float32 at depth 1.
        for k in 0..100 {
            set_ref(&mut reference, k, 7, 1.0, DVec3::X);
            set_gpu(
                &mut gpu,
                k,
                7,
                1.0 + (k + 1) as f32 / 1024.0,
                [1.0, 0.0, 0.0],
            );
        }
        let s = compare(&gpu, &reference).unwrap();
        assert_eq!(s.compared_pixels, 100);
        assert_eq!(s.depth_rel_p99, 99.0 / 1024.0);
        assert_eq!(s.depth_rel_max, 100.0 / 1024.0);
        // One ULP at 1.0 is 2^-23: 99/1024 = 99 * 2^13 ULP.
        assert_eq!(s.depth_ulp_p99, 99.0 * 8192.0);
        assert_eq!(s.normal_deg_max, 0.0);
        assert!(s.check(&Bounds::STRICT).unwrap_err().contains("depth"));

        assert_eq!(percentile(&mut [], 0.99), 0.0);
        assert_eq!(percentile(&mut [3.0], 0.99), 3.0);
        assert_eq!(percentile(&mut [2.0, 1.0], 0.5), 1.0);
    }

    #[test]
    fn identical_frames_pass_strict_bounds() {
        let (mut gpu, mut reference) = blank(4, 4);
        for k in [0, 5, 6, 15] {
            set_ref(&mut reference, k, k as u32, 1.5, DVec3::Y);
            set_gpu(&mut gpu, k, k as u32, 1.5, [0.0, 1.0, 0.0]);
        }
        let s = compare(&gpu, &reference).unwrap();
        assert_eq!(s.covered_pixels, 4);
        assert_eq!(s.compared_pixels, 4);
        assert_eq!(s.check(&Bounds::STRICT), Ok(()));
    }

    #[test]
    fn nan_from_the_gpu_breaks_the_bounds() {
        let (mut gpu, mut reference) = blank(1, 1);
        set_ref(&mut reference, 0, 0, 1.0, DVec3::Y);
        set_gpu(&mut gpu, 0, 0, f32::NAN, [f32::NAN; 3]);
        let s = compare(&gpu, &reference).unwrap();
        assert_eq!(s.depth_rel_max, f64::INFINITY);
        assert_eq!(s.normal_deg_max, f64::INFINITY);
        assert!(s.check(&Bounds::STRICT).is_err());
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let (gpu, _) = blank(3, 2);
        let (_, reference) = blank(2, 3);
        let err = compare(&gpu, &reference).unwrap_err();
        assert!(err.to_string().contains("3x2"), "{err}");
        let (mut gpu, reference) = blank(2, 2);
        gpu.depth.pop();
        assert!(compare(&gpu, &reference).is_err());
    }

    #[test]
    fn ulp_of_float32() {
        assert_eq!(f32_ulp(1.0), 2f64.powi(-23));
        assert_eq!(f32_ulp(1.999), 2f64.powi(-23));
        assert_eq!(f32_ulp(4.0), 2f64.powi(-21));
        assert_eq!(f32_ulp(0.75), 2f64.powi(-24));
        assert_eq!(f32_ulp(1e-40), 2f64.powi(-149));
    }
}
