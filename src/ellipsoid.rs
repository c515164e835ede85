//! One ellipsoid: centre, semi-axes, orientation and colour, in float64 on the CPU.
//!
//! The surface is `{ c + R diag(radii) p : |p| = 1 }`: `p` is the point in *parameter space*,
//! where the ellipsoid is the unit sphere (Gumhold 2003). Everything the renderer and the
//! reference renderer compute goes through that map.

use glam::{DMat3, DQuat, DVec3};

use crate::error::{Error, Result};

/// An ellipsoid in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Centre in world coordinates.
    pub center: DVec3,
    /// Semi-axis lengths along the local x, y, z axes; all finite and > 0.
    pub radii: DVec3,
    /// Unit quaternion rotating the local axes into world axes.
    pub rotation: DQuat,
    /// Display (sRGB) colour in [0, 1]; shading happens in linear light.
    pub color: [f32; 3],
}

impl Ellipsoid {
    /// An ellipsoid from centre, semi-axes and rotation; the quaternion is normalised.
    /// Without `color`, the glyph is coloured by its shape (see [`shape_color`]).
    pub fn new(
        center: DVec3,
        radii: DVec3,
        rotation: DQuat,
        color: Option<[f32; 3]>,
    ) -> Result<Self> {
        if !center.is_finite() {
            return Err(Error::invalid(
                "ellipsoid centre",
                format!("not finite: {center}"),
            ));
        }
        if !radii.is_finite() || radii.min_element() <= 0.0 {
            return Err(Error::invalid(
                "ellipsoid radii",
                format!("must be finite and > 0, got {radii}"),
            ));
        }
        let len = rotation.length();
        if !len.is_finite() || len < 1e-12 {
            return Err(Error::invalid(
                "ellipsoid rotation",
                format!("quaternion must be finite and non-zero, got {rotation}"),
            ));
        }
        let rotation = rotation / len;
        let color = match color {
            Some(c) => {
                if c.iter().any(|v| !v.is_finite() || *v < 0.0 || *v > 1.0) {
                    return Err(Error::invalid(
                        "ellipsoid colour",
                        format!("components must be in [0, 1], got {c:?}"),
                    ));
                }
                c
            }
            None => shape_color(radii),
        };
        Ok(Self {
            center,
            radii,
            rotation,
            color,
        })
    }

    /// An ellipsoid from a symmetric positive-definite `T` with `E = {c + T p : |p| = 1}`.
    /// The semi-axes are `T`'s eigenvalues and the axes its eigenvectors.
    pub fn from_tensor(center: DVec3, t: DMat3, color: Option<[f32; 3]>) -> Result<Self> {
        let cols = [t.x_axis, t.y_axis, t.z_axis];
        if cols.iter().any(|c| !c.is_finite()) {
            return Err(Error::invalid("tensor", "has a non-finite entry"));
        }
        let asym = (t - t.transpose())
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let scale = t.to_cols_array().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if asym > 1e-9 * scale.max(f64::MIN_POSITIVE) {
            return Err(Error::invalid("tensor", "is not symmetric"));
        }
        let (values, vectors) = symmetric_eigen(t);
        if values.min_element() <= 0.0 {
            return Err(Error::invalid(
                "tensor",
                format!("is not positive definite (eigenvalues {values})"),
            ));
        }
        Self::new(center, values, DQuat::from_mat3(&vectors), color)
    }

    /// Rotation matrix whose columns are the local axes in world space.
    pub fn axes(&self) -> DMat3 {
        DMat3::from_quat(self.rotation)
    }

    /// Map from parameter space to world offsets: `R diag(radii)`.
    pub fn to_world(&self) -> DMat3 {
        self.axes() * DMat3::from_diagonal(self.radii)
    }

    /// Map from world offsets to parameter space: `diag(1/radii) R^T`.
    pub fn to_parameter(&self) -> DMat3 {
        DMat3::from_diagonal(self.radii.recip()) * self.axes().transpose()
    }

    /// Radius of the smallest sphere about the centre that contains the ellipsoid.
    pub fn bounding_radius(&self) -> f64 {
        self.radii.max_element()
    }
}

/// Colour by shape after Westin's measures, as in Gumhold's tensor figure:
/// linear (cigar) red, planar (pancake) green, spherical blue; brightest channel scaled to 1.
pub fn shape_color(radii: DVec3) -> [f32; 3] {
    let mut l = radii.to_array();
    l.sort_by(|a, b| b.total_cmp(a));
    let sum = l[0] + l[1] + l[2];
    let linear = (l[0] - l[1]) / sum;
    let planar = 2.0 * (l[1] - l[2]) / sum;
    let spherical = 3.0 * l[2] / sum;
    let peak = linear.max(planar).max(spherical);
    [
        (linear / peak) as f32,
        (planar / peak) as f32,
        (spherical / peak) as f32,
    ]
}

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations, in float64.
/// Returns eigenvalues and a right-handed rotation whose columns are the eigenvectors.
pub fn symmetric_eigen(m: DMat3) -> (DVec3, DMat3) {
    let mut a = m.to_cols_array_2d();
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..32 {
        let off = a[0][1].powi(2) + a[0][2].powi(2) + a[1][2].powi(2);
        let diag = a[0][0].powi(2) + a[1][1].powi(2) + a[2][2].powi(2);
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // Rotation angle that zeroes a[p][q] (Golub & Van Loan, symmetric Schur).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            for (k, (apk, aqk)) in row_p.into_iter().zip(row_q).enumerate() {
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for row in v.iter_mut() {
                let vp = row[p];
                let vq = row[q];
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // `v` holds eigenvectors as columns in row-major layout; convert to glam's column-major.
    let mut vectors = DMat3::from_cols_array_2d(&v).transpose();
    if vectors.determinant() < 0.0 {
        vectors.z_axis = -vectors.z_axis;
    }
    (DVec3::new(a[0][0], a[1][1], a[2][2]), vectors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_reconstructs_tensor() {
        let r = DMat3::from_quat(DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0));
        let d = DMat3::from_diagonal(DVec3::new(3.0, 0.5, 1e-3));
        let t = r * d * r.transpose();
        let e = Ellipsoid::from_tensor(DVec3::ZERO, t, None).unwrap();
        let back = e.to_world() * e.axes().transpose();
        for (x, y) in back.to_cols_array().iter().zip(t.to_cols_array()) {
            assert!((x - y).abs() < 1e-12, "{back} vs {t}");
        }
    }

    #[test]
    fn tensor_not_positive_definite_is_rejected() {
        let t = DMat3::from_diagonal(DVec3::new(1.0, -1.0, 1.0));
        let err = Ellipsoid::from_tensor(DVec3::ZERO, t, None).unwrap_err();
        assert!(err.to_string().contains("positive definite"), "{err}");
    }

    #[test]
    fn shape_colours_follow_westin() {
        let cigar = shape_color(DVec3::new(10.0, 1.0, 1.0));
        let pancake = shape_color(DVec3::new(5.0, 5.0, 1.0));
        let ball = shape_color(DVec3::new(1.0, 1.0, 1.0));
        assert!(cigar[0] == 1.0 && cigar[1] < 0.5 && cigar[2] < 0.5);
        assert!(pancake[1] == 1.0 && pancake[0] < 0.5 && pancake[2] < 0.5);
        assert_eq!(ball, [0.0, 0.0, 1.0]);
    }
}
