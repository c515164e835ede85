//! Glyphs from NumPy arrays (already shaped by the Python half, float32 or float64): centres
//! with semi-axes and quaternions, or symmetric positive definite tensors.

use ellipsoid_splat::Ellipsoid;
use glam::{DMat3, DQuat, DVec3};
use numpy::ndarray::{ArrayView, Dimension, Ix2, Ix3, NdIndex};
use numpy::PyReadonlyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A float64 or float32 array, borrowed from NumPy as it is: float32 is read (and widened)
/// value by value, never copied into a float64 array first.
pub enum Floats<'py, D: Dimension> {
    F64(PyReadonlyArray<'py, f64, D>),
    F32(PyReadonlyArray<'py, f32, D>),
}

/// A (N, k) array of either precision.
pub type Floats2<'py> = Floats<'py, Ix2>;
/// A (N, 3, 3) array of either precision.
pub type Floats3<'py> = Floats<'py, Ix3>;

impl<'py, D: Dimension> FromPyObject<'py> for Floats<'py, D> {
    fn extract_bound(ob: &Bound<'py, PyAny>) -> PyResult<Self> {
        if let Ok(array) = ob.extract::<PyReadonlyArray<'py, f64, D>>() {
            return Ok(Self::F64(array));
        }
        ob.extract::<PyReadonlyArray<'py, f32, D>>().map(Self::F32)
    }
}

impl<D: Dimension> Floats<'_, D> {
    /// The array's values, without a copy.
    pub fn view(&self) -> View<'_, D> {
        match self {
            Self::F64(a) => View::F64(a.as_array()),
            Self::F32(a) => View::F32(a.as_array()),
        }
    }

    /// The address of the array's first value: the NumPy array's own buffer (the test hook
    /// that shows float32 input arrives uncopied compares it with NumPy's).
    pub fn address(&self) -> usize {
        match self {
            Self::F64(a) => a.as_array().as_ptr() as usize,
            Self::F32(a) => a.as_array().as_ptr() as usize,
        }
    }
}

/// A borrowed float64 or float32 array.
pub enum View<'a, D: Dimension> {
    F64(ArrayView<'a, f64, D>),
    F32(ArrayView<'a, f32, D>),
}

impl<D: Dimension> View<'_, D> {
    pub fn shape(&self) -> &[usize] {
        match self {
            Self::F64(a) => a.shape(),
            Self::F32(a) => a.shape(),
        }
    }

    /// The value at `index` as float64 (the caller checked the shape).
    #[inline]
    pub fn at<I: NdIndex<D>>(&self, index: I) -> f64 {
        match self {
            Self::F64(a) => a[index],
            Self::F32(a) => a[index] as f64,
        }
    }
}

impl View<'_, Ix2> {
    /// Row `i`'s first three values.
    #[inline]
    pub fn vec3(&self, i: usize) -> DVec3 {
        DVec3::new(self.at([i, 0]), self.at([i, 1]), self.at([i, 2]))
    }

    /// Row `i` of a (N, 4) quaternion array (w, x, y, z).
    #[inline]
    pub fn quat(&self, i: usize) -> DQuat {
        DQuat::from_xyzw(
            self.at([i, 1]),
            self.at([i, 2]),
            self.at([i, 3]),
            self.at([i, 0]),
        )
    }

    /// Row `i` of a (N, 3) colour array.
    #[inline]
    pub fn color(&self, i: usize) -> [f32; 3] {
        [
            self.at([i, 0]) as f32,
            self.at([i, 1]) as f32,
            self.at([i, 2]) as f32,
        ]
    }
}

/// The glyph arrays of one scene, borrowed from NumPy without a copy.
pub struct GlyphArrays<'py> {
    pub centers: Floats2<'py>,
    pub radii: Option<Floats2<'py>>,
    pub rotations: Option<Floats2<'py>>,
    pub colors: Option<Floats2<'py>>,
    pub tensors: Option<Floats3<'py>>,
}

pub fn shape_error(name: &str, shape: &[usize], want: &str) -> PyErr {
    PyValueError::new_err(format!("{name} has shape {shape:?}, expected {want}"))
}

/// `ValueError` unless `array` is (`rows`, `cols`).
pub fn check_rows(name: &str, array: &View<'_, Ix2>, rows: usize, cols: usize) -> PyResult<()> {
    if array.shape() != [rows, cols] {
        Err(shape_error(
            name,
            array.shape(),
            &format!("({rows}, {cols})"),
        ))
    } else {
        Ok(())
    }
}

impl GlyphArrays<'_> {
    /// The data addresses of the arrays (0 for those not given), in argument order.
    pub fn addresses(&self) -> Vec<usize> {
        let two = |a: &Option<Floats2>| a.as_ref().map_or(0, Floats::address);
        vec![
            self.centers.address(),
            two(&self.radii),
            two(&self.rotations),
            two(&self.colors),
            self.tensors.as_ref().map_or(0, Floats::address),
        ]
    }

    /// The ellipsoids, one per row; an invalid one is a `ValueError` naming its index.
    pub fn ellipsoids(&self) -> PyResult<Vec<Ellipsoid>> {
        let centers = self.centers.view();
        let n = centers.shape()[0];
        check_rows("centers", &centers, n, 3)?;
        let radii = self.radii.as_ref().map(Floats::view);
        let rotations = self.rotations.as_ref().map(Floats::view);
        let colors = self.colors.as_ref().map(Floats::view);
        let tensors = self.tensors.as_ref().map(Floats::view);
        if let Some(r) = &radii {
            check_rows("radii", r, n, 3)?;
        }
        if let Some(q) = &rotations {
            check_rows("rotations", q, n, 4)?;
        }
        if let Some(c) = &colors {
            check_rows("colors", c, n, 3)?;
        }
        if let Some(t) = &tensors {
            if t.shape() != [n, 3, 3] {
                return Err(shape_error("tensors", t.shape(), &format!("({n}, 3, 3)")));
            }
        }
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let center = centers.vec3(i);
            let color = colors.as_ref().map(|c| c.color(i));
            let ellipsoid = match (&tensors, &radii) {
                (Some(t), _) => {
                    let m = DMat3::from_cols_array_2d(&[
                        [t.at([i, 0, 0]), t.at([i, 1, 0]), t.at([i, 2, 0])],
                        [t.at([i, 0, 1]), t.at([i, 1, 1]), t.at([i, 2, 1])],
                        [t.at([i, 0, 2]), t.at([i, 1, 2]), t.at([i, 2, 2])],
                    ]);
                    Ellipsoid::from_tensor(center, m, color)
                }
                (None, Some(r)) => {
                    let rotation = rotations.as_ref().map_or(DQuat::IDENTITY, |q| q.quat(i));
                    Ellipsoid::new(center, r.vec3(i), rotation, color)
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

/// The fields an update gives for its glyphs, copied out of NumPy (rows in the order of the
/// update's indices) so that they can be applied with the GIL released.
#[derive(Default)]
pub struct Changes {
    pub centers: Option<Vec<DVec3>>,
    pub radii: Option<Vec<DVec3>>,
    pub rotations: Option<Vec<DQuat>>,
    pub colors: Option<Vec<[f32; 3]>>,
}

impl Changes {
    /// The given arrays' rows, each array checked to be (`rows`, k).
    pub fn new(
        rows: usize,
        centers: Option<Floats2<'_>>,
        radii: Option<Floats2<'_>>,
        rotations: Option<Floats2<'_>>,
        colors: Option<Floats2<'_>>,
    ) -> PyResult<Self> {
        fn take<T>(
            name: &str,
            array: Option<Floats2<'_>>,
            rows: usize,
            cols: usize,
            row: impl Fn(&View<'_, Ix2>, usize) -> T,
        ) -> PyResult<Option<Vec<T>>> {
            let Some(array) = array else {
                return Ok(None);
            };
            let view = array.view();
            check_rows(name, &view, rows, cols)?;
            Ok(Some((0..rows).map(|i| row(&view, i)).collect()))
        }
        Ok(Self {
            centers: take("centers", centers, rows, 3, |v, i| v.vec3(i))?,
            radii: take("radii", radii, rows, 3, |v, i| v.vec3(i))?,
            rotations: take("rotations", rotations, rows, 4, |v, i| v.quat(i))?,
            colors: take("colors", colors, rows, 3, |v, i| v.color(i))?,
        })
    }

    /// Glyph `old` with row `k`'s given fields; `shape_colors`: a glyph without a given
    /// colour is coloured by its (new) shape, as an upload without colours colours it.
    /// The fields not given keep their values exactly (the rotation is not normalised again).
    pub fn apply(
        &self,
        old: &Ellipsoid,
        k: usize,
        shape_colors: bool,
    ) -> ellipsoid_splat::Result<Ellipsoid> {
        let pick = |given: &Option<Vec<DVec3>>, kept: DVec3| given.as_ref().map_or(kept, |v| v[k]);
        let rotation = self.rotations.as_ref().map(|q| q[k]);
        let color = match &self.colors {
            Some(c) => Some(c[k]),
            None if shape_colors => None,
            None => Some(old.color),
        };
        let mut new = Ellipsoid::new(
            pick(&self.centers, old.center),
            pick(&self.radii, old.radii),
            rotation.unwrap_or(old.rotation),
            color,
        )?;
        if rotation.is_none() {
            new.rotation = old.rotation;
        }
        Ok(new)
    }
}
