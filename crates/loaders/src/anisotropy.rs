//! Fractional anisotropy of an ellipsoid's semi-axes, the diffusion-MRI measure of how far a
//! tensor is from isotropic: 0 for a sphere, approaching 1 for a needle.
//!
//! The semi-axes are taken as the eigenvalues, as the NIfTI loader builds its glyphs (semi-axes
//! = the diffusion tensor's eigenvalues times one factor per volume, which FA ignores), so FA of
//! a tensor glyph is the tensor's own FA. For other glyphs it is FA of the glyph's matrix
//! `R diag(radii) R^T`: for a thermal ellipsoid (semi-axes `c sqrt(lambda)` of `U`) that is FA of
//! `U^(1/2)`, for a Gaussian splat (semi-axes in standard deviations) FA of the square root of
//! the covariance.

use glam::DVec3;

/// Fractional anisotropy of the eigenvalues `l`:
/// `sqrt(1/2) sqrt((l1-l2)^2 + (l2-l3)^2 + (l3-l1)^2) / sqrt(l1^2 + l2^2 + l3^2)`. Computed from
/// the differences, so three equal values give exactly 0; in [0, 1] for non-negative `l`; 0
/// when `l` is 0.
pub fn fractional_anisotropy(l: DVec3) -> f64 {
    let norm2 = l.length_squared();
    if norm2 == 0.0 {
        return 0.0;
    }
    let differences = (l.x - l.y).powi(2) + (l.y - l.z).powi(2) + (l.z - l.x).powi(2);
    (0.5 * differences / norm2).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The other common form, `sqrt(3/2) |l - mean| / |l|`, to check against.
    fn from_the_mean(l: DVec3) -> f64 {
        let mean = (l.x + l.y + l.z) / 3.0;
        (1.5 * (l - DVec3::splat(mean)).length_squared() / l.length_squared()).sqrt()
    }

    #[test]
    fn a_sphere_has_none() {
        for r in [1e-6, 1.0, 3.5, 1e6] {
            assert_eq!(fractional_anisotropy(DVec3::splat(r)), 0.0, "{r}");
        }
        assert_eq!(fractional_anisotropy(DVec3::ZERO), 0.0);
    }

    #[test]
    fn a_needle_approaches_one() {
        // Semi-axes (a, 1, 1): FA = (a - 1) / sqrt(a^2 + 2).
        for a in [2.0, 10.0, 1e3, 1e6] {
            let fa = fractional_anisotropy(DVec3::new(a, 1.0, 1.0));
            let expected = (a - 1.0) / (a * a + 2.0).sqrt();
            assert!((fa - expected).abs() < 1e-14, "{a}: {fa} vs {expected}");
        }
        let ten = fractional_anisotropy(DVec3::new(1.0, 10.0, 1.0));
        assert!((ten - 9.0 / 102f64.sqrt()).abs() < 1e-14, "{ten}");
        assert!(fractional_anisotropy(DVec3::new(1.0, 1.0, 1e6)) > 1.0 - 1e-5);
        // A flat disc (a, a, 0) is 1/sqrt(2), whatever a.
        let disc = fractional_anisotropy(DVec3::new(4.0, 4.0, 0.0));
        assert!((disc - 0.5f64.sqrt()).abs() < 1e-15, "{disc}");
    }

    #[test]
    fn matches_the_form_with_the_mean_and_ignores_scale() {
        for l in [
            DVec3::new(3.0, 0.5, 1e-3),
            DVec3::new(1.7e-3, 0.3e-3, 0.2e-3),
            DVec3::new(2.0, 2.0, 1.0),
        ] {
            let fa = fractional_anisotropy(l);
            assert!((fa - from_the_mean(l)).abs() < 1e-14, "{l}");
            assert!((fractional_anisotropy(l * 123.0) - fa).abs() < 1e-14, "{l}");
            assert!((0.0..=1.0).contains(&fa), "{l}: {fa}");
        }
    }
}
