//! Antialiased frames against the reference: each pixel's exact count of covered samples,
//! over the very sample positions the GPU uses, and the error of the resolved pixels in
//! samples.
//!
//! The positions are cells of a K x K grid in each pixel, `((s + 0.5) / K, (t + 0.5) / K)`:
//! all K^2 cells for `--supersample K`, and for 4x multisampling the four cells of the
//! 4 x 4 grid where the Vulkan standard positions lie. The reference drawn K times larger
//! answers every cell at once.
//!
//! A resolved pixel is compared through its light: the glyphs are drawn unlit and white over
//! the background (the caller sets the material), so a pixel's linear light is
//! `bg + f (1 - bg)` with `f` the covered fraction of its samples.

use std::fmt;

use ellipsoid_splat::Camera;
use ellipsoid_splat::Scene;
use ellipsoid_splat::{Error, Result};
use ellipsoid_splat::{Frame, NO_INSTANCE};

use crate::reference::{render_reference, ReferenceFrame};

/// Where a pixel's samples lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplePattern {
    /// The Vulkan standard positions of 4x multisampling.
    Standard4,
    /// Every cell of a K x K grid (`--supersample K`).
    Grid(u32),
}

impl SamplePattern {
    /// Side of the grid the positions lie on.
    pub fn grid(self) -> u32 {
        match self {
            SamplePattern::Standard4 => 4,
            SamplePattern::Grid(k) => k,
        }
    }

    /// The cells `(s, t)` of the grid holding a sample.
    pub fn cells(self) -> Vec<(u32, u32)> {
        match self {
            SamplePattern::Standard4 => vec![(1, 0), (3, 1), (0, 2), (2, 3)],
            SamplePattern::Grid(k) => (0..k * k).map(|n| (n % k, n / k)).collect(),
        }
    }
}

/// The reference's answer per pixel: covered samples, and whether any sample lies within
/// float32 rounding of a silhouette (such pixels are not compared).
#[derive(Clone, Debug)]
pub struct ReferenceCoverage {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub samples: u32,
    /// Covered samples of each pixel, row-major.
    pub covered: Vec<u32>,
    /// Some sample of the pixel is ambiguous in the reference.
    pub ambiguous: Vec<bool>,
}

/// The reference's coverage of `scene` seen by `camera`, at `pattern`'s positions.
pub fn reference_coverage(
    scene: &Scene,
    camera: &Camera,
    pattern: SamplePattern,
) -> Result<ReferenceCoverage> {
    let k = pattern.grid();
    let (Some(width), Some(height)) = (camera.width.checked_mul(k), camera.height.checked_mul(k))
    else {
        return Err(Error::invalid("sample pattern", "the image size overflows"));
    };
    let big = Camera {
        width,
        height,
        ..*camera
    };
    let reference = render_reference(scene, &big)?;
    coverage_from(&reference, camera, pattern)
}

/// The coverage at `pattern`'s positions of the pixels of `camera`, read from `reference`, the
/// reference drawn `pattern.grid()` times larger (several patterns on one grid share it).
/// Errors when `reference` has another size.
pub fn coverage_from(
    reference: &ReferenceFrame,
    camera: &Camera,
    pattern: SamplePattern,
) -> Result<ReferenceCoverage> {
    let k = pattern.grid();
    if (reference.width as u64, reference.height as u64)
        != (
            camera.width as u64 * k as u64,
            camera.height as u64 * k as u64,
        )
    {
        return Err(Error::invalid(
            "reference coverage",
            format!(
                "a {}x{} reference cannot give the {k} x {k} grid of a {}x{} image",
                reference.width, reference.height, camera.width, camera.height
            ),
        ));
    }
    let cells = pattern.cells();
    let pixels = camera.width as usize * camera.height as usize;
    let (mut covered, mut ambiguous) = (Vec::with_capacity(pixels), Vec::with_capacity(pixels));
    for j in 0..camera.height {
        for i in 0..camera.width {
            let at = |&(s, t): &(u32, u32)| reference.index(k * i + s, k * j + t);
            covered.push(
                cells
                    .iter()
                    .filter(|c| reference.id[at(c)] != NO_INSTANCE)
                    .count() as u32,
            );
            ambiguous.push(cells.iter().any(|c| reference.ambiguous[at(c)]));
        }
    }
    Ok(ReferenceCoverage {
        width: camera.width,
        height: camera.height,
        samples: cells.len() as u32,
        covered,
        ambiguous,
    })
}

/// How far a resolved frame's coverage is from the reference's, in samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CoverageStats {
    /// Pixels compared (not ambiguous).
    pub compared: usize,
    /// Of those, pixels the reference covers at any sample.
    pub covered: usize,
    /// Of those, pixels the reference covers partly (the antialiased ones).
    pub partly_covered: usize,
    /// Pixels whose lit samples differ from the reference's count by half a sample or more.
    pub wrong: usize,
    /// Mean absolute error over the partly covered pixels, in samples.
    pub mean_error: f64,
    /// Largest absolute error, in samples.
    pub max_error: f64,
}

impl fmt::Display for CoverageStats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} px compared, {} partly covered, {} wrong; error mean {:.3} max {:.2} samples",
            self.compared, self.partly_covered, self.wrong, self.mean_error, self.max_error
        )
    }
}

pub use ellipsoid_splat::supersample::srgb_to_linear;

/// Compares `resolved` (unlit white glyphs over the background) with the reference's coverage.
/// The background's light is read from a pixel the reference leaves wholly uncovered.
pub fn compare_coverage(resolved: &Frame, reference: &ReferenceCoverage) -> Result<CoverageStats> {
    if (resolved.width, resolved.height) != (reference.width, reference.height)
        || resolved.color.len() != reference.covered.len()
    {
        return Err(Error::invalid(
            "coverage comparison",
            format!(
                "a {}x{} frame against a {}x{} reference",
                resolved.width, resolved.height, reference.width, reference.height
            ),
        ));
    }
    let background = (0..reference.covered.len())
        .find(|&k| reference.covered[k] == 0 && !reference.ambiguous[k])
        .map(|k| srgb_to_linear(resolved.color[k][0]))
        .ok_or_else(|| Error::invalid("coverage comparison", "no background pixel"))?;
    let samples = reference.samples as f64;
    let mut stats = CoverageStats::default();
    let mut sum = 0.0;
    for k in 0..reference.covered.len() {
        if reference.ambiguous[k] {
            continue;
        }
        let light = srgb_to_linear(resolved.color[k][0]);
        let lit = samples * (light - background) / (1.0 - background);
        let covered = reference.covered[k];
        let error = (lit - covered as f64).abs();
        stats.compared += 1;
        stats.wrong += (error >= 0.5) as usize;
        stats.max_error = stats.max_error.max(error);
        stats.covered += (covered > 0) as usize;
        if covered > 0 && covered < reference.samples {
            stats.partly_covered += 1;
            sum += error;
        }
    }
    stats.mean_error = sum / stats.partly_covered.max(1) as f64;
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ellipsoid_splat::Ellipsoid;
    use glam::{DQuat, DVec3};

    /// One sphere filling part of a small view.
    fn sphere_view() -> (Scene, Camera) {
        let sphere = Ellipsoid::new(DVec3::ZERO, DVec3::splat(1.0), DQuat::IDENTITY, None).unwrap();
        let camera =
            Camera::look_at(DVec3::new(0.0, 0.0, 6.0), DVec3::ZERO, 40.0, 0.1, 24, 16).unwrap();
        (Scene::new(vec![sphere]), camera)
    }

    /// The standard 4x positions and the 4 x 4 grid read from one reference drawn 4 times
    /// larger: each pixel's standard samples are among its grid's, and fully inside or
    /// outside pixels agree.
    #[test]
    fn patterns_on_one_grid_share_a_reference() {
        let (scene, camera) = sphere_view();
        let big = Camera {
            width: camera.width * 4,
            height: camera.height * 4,
            ..camera
        };
        let reference = render_reference(&scene, &big).unwrap();
        let standard = coverage_from(&reference, &camera, SamplePattern::Standard4).unwrap();
        let grid = coverage_from(&reference, &camera, SamplePattern::Grid(4)).unwrap();
        assert_eq!(
            standard.covered,
            reference_coverage(&scene, &camera, SamplePattern::Standard4)
                .unwrap()
                .covered
        );
        assert_eq!((standard.samples, grid.samples), (4, 16));
        for (s, g) in standard.covered.iter().zip(&grid.covered) {
            assert!(s <= g && g - s <= 12, "{s} of 4 against {g} of 16");
            if *g == 16 {
                assert_eq!(*s, 4);
            }
            if *g == 0 {
                assert_eq!(*s, 0);
            }
        }
        assert!(grid.covered.contains(&16) && grid.covered.contains(&0));
    }

    #[test]
    fn a_reference_of_another_size_is_refused() {
        let (scene, camera) = sphere_view();
        let reference = render_reference(&scene, &camera).unwrap();
        let error = coverage_from(&reference, &camera, SamplePattern::Grid(2)).unwrap_err();
        assert!(error.to_string().contains("24x16 reference"), "{error}");
    }
}
