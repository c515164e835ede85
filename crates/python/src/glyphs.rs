//! Glyphs from NumPy arrays (already shaped and typed by the Python half): centres with
//! semi-axes and quaternions, or symmetric positive definite tensors.

use ellipsoid_splat::Ellipsoid;
use glam::{DMat3, DQuat, DVec3};
use numpy::{PyReadonlyArray2, PyReadonlyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

/// The glyph arrays of one scene, borrowed from NumPy without a copy.
pub struct GlyphArrays<'py> {
    pub centers: PyReadonlyArray2<'py, f64>,
    pub radii: Option<PyReadonlyArray2<'py, f64>>,
    pub rotations: Option<PyReadonlyArray2<'py, f64>>,
    pub colors: Option<PyReadonlyArray2<'py, f64>>,
    pub tensors: Option<PyReadonlyArray3<'py, f64>>,
}

fn shape_error(name: &str, shape: &[usize], want: &str) -> pyo3::PyErr {
    PyValueError::new_err(format!("{name} has shape {shape:?}, expected {want}"))
}

impl GlyphArrays<'_> {
    /// The ellipsoids, one per row; an invalid one is a `ValueError` naming its index.
    pub fn ellipsoids(&self) -> PyResult<Vec<Ellipsoid>> {
        let centers = self.centers.as_array();
        let n = centers.nrows();
        if centers.ncols() != 3 {
            return Err(shape_error("centers", centers.shape(), "(N, 3)"));
        }
        let rows = |name: &str, array: &numpy::ndarray::ArrayView2<f64>, cols: usize| {
            if array.nrows() != n || array.ncols() != cols {
                Err(shape_error(name, array.shape(), &format!("({n}, {cols})")))
            } else {
                Ok(())
            }
        };
        let radii = self.radii.as_ref().map(|a| a.as_array());
        let rotations = self.rotations.as_ref().map(|a| a.as_array());
        let colors = self.colors.as_ref().map(|a| a.as_array());
        let tensors = self.tensors.as_ref().map(|a| a.as_array());
        if let Some(r) = &radii {
            rows("radii", r, 3)?;
        }
        if let Some(q) = &rotations {
            rows("rotations", q, 4)?;
        }
        if let Some(c) = &colors {
            rows("colors", c, 3)?;
        }
        if let Some(t) = &tensors {
            if t.shape() != [n, 3, 3] {
                return Err(shape_error("tensors", t.shape(), &format!("({n}, 3, 3)")));
            }
        }
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let center = DVec3::new(centers[[i, 0]], centers[[i, 1]], centers[[i, 2]]);
            let color = colors
                .as_ref()
                .map(|c| [c[[i, 0]] as f32, c[[i, 1]] as f32, c[[i, 2]] as f32]);
            let ellipsoid = match (&tensors, &radii) {
                (Some(t), _) => {
                    let m = DMat3::from_cols_array_2d(&[
                        [t[[i, 0, 0]], t[[i, 1, 0]], t[[i, 2, 0]]],
                        [t[[i, 0, 1]], t[[i, 1, 1]], t[[i, 2, 1]]],
                        [t[[i, 0, 2]], t[[i, 1, 2]], t[[i, 2, 2]]],
                    ]);
                    Ellipsoid::from_tensor(center, m, color)
                }
                (None, Some(r)) => {
                    let rotation = rotations.as_ref().map_or(DQuat::IDENTITY, |q| {
                        DQuat::from_xyzw(q[[i, 1]], q[[i, 2]], q[[i, 3]], q[[i, 0]])
                    });
                    Ellipsoid::new(
                        center,
                        DVec3::new(r[[i, 0]], r[[i, 1]], r[[i, 2]]),
                        rotation,
                        color,
                    )
                }
                (None, None) => {
                    return Err(PyValueError::new_err("radii or tensors must be given"));
                }
            };
            out.push(ellipsoid.map_err(|e| PyValueError::new_err(format!("glyph {i}: {e}")))?);
        }
        Ok(out)
    }
}
