//! Cameras as Python users give them: eye, target, up and a vertical field of view, or
//! pinhole intrinsics `K` (3 x 3, pixels) with OpenCV extrinsics `world_to_camera` (4 x 4:
//! x right, y down, z forward).

use ellipsoid_splat::{Camera, Intrinsics, Projection};
use glam::{DMat3, DVec3};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyValueError;
use pyo3::PyResult;

use crate::errors::renderer_error;

/// What the Python half passes for a camera, copied out of NumPy (so that the camera can be
/// made with the GIL released, beside the scene it frames).
pub struct CameraArgs {
    pub eye: Option<[f64; 3]>,
    pub target: Option<[f64; 3]>,
    pub up: [f64; 3],
    pub fov_y: f64,
    pub intrinsics: Option<[[f64; 3]; 3]>,
    pub world_to_camera: Option<[[f64; 4]; 4]>,
    pub width: u32,
    pub height: u32,
    pub near: Option<f64>,
}

/// The near plane the command line takes by default: half the eye's distance to the scene's
/// bounding sphere, or a thousandth of its radius from inside it.
fn default_near(eye: DVec3, sphere: (DVec3, f64)) -> f64 {
    let (centre, radius) = sphere;
    let distance = (centre - eye).length();
    if distance > radius {
        0.5 * (distance - radius)
    } else {
        1e-3 * radius
    }
}

/// The `R x C` matrix `array` holds, or a `ValueError` naming `name`.
pub fn matrix<const R: usize, const C: usize>(
    name: &str,
    array: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<Option<[[f64; C]; R]>> {
    let Some(array) = array else {
        return Ok(None);
    };
    let view = array.as_array();
    if view.shape() != [R, C] {
        return Err(PyValueError::new_err(format!(
            "{name} has shape {:?}, expected ({R}, {C})",
            view.shape()
        )));
    }
    let mut out = [[0.0; C]; R];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, value) in row.iter_mut().enumerate() {
            *value = view[[i, j]];
        }
    }
    Ok(Some(out))
}

impl CameraArgs {
    /// The camera; `sphere` is the scene's bounding sphere (for the framing defaults).
    pub fn camera(&self, sphere: (DVec3, f64)) -> PyResult<Camera> {
        let (width, height) = (self.width, self.height);
        let camera = match (&self.intrinsics, &self.world_to_camera) {
            (Some(k), Some(pose)) => {
                let k = |[i, j]: [usize; 2]| k[i][j];
                let pose = |[i, j]: [usize; 2]| pose[i][j];
                if k([0, 1]) != 0.0
                    || k([1, 0]) != 0.0
                    || [k([2, 0]), k([2, 1]), k([2, 2])] != [0.0, 0.0, 1.0]
                {
                    return Err(PyValueError::new_err(
                        "intrinsics must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)",
                    ));
                }
                let rotation = DMat3::from_cols_array_2d(&[
                    [pose([0, 0]), pose([1, 0]), pose([2, 0])],
                    [pose([0, 1]), pose([1, 1]), pose([2, 1])],
                    [pose([0, 2]), pose([1, 2]), pose([2, 2])],
                ]);
                let t = DVec3::new(pose([0, 3]), pose([1, 3]), pose([2, 3]));
                let orthonormal = (rotation * rotation.transpose() - DMat3::IDENTITY)
                    .to_cols_array()
                    .iter()
                    .all(|v| v.abs() < 1e-6);
                if !orthonormal || rotation.determinant() < 0.0 || !t.is_finite() {
                    return Err(PyValueError::new_err(
                        "world_to_camera must be [R | t] with R a rotation (orthonormal, \
                         determinant +1) and t finite",
                    ));
                }
                if [pose([3, 0]), pose([3, 1]), pose([3, 2]), pose([3, 3])] != [0.0, 0.0, 0.0, 1.0]
                {
                    return Err(PyValueError::new_err(
                        "world_to_camera's last row must be [0, 0, 0, 1]",
                    ));
                }
                // Camera axes in world coordinates are the rows of R; the centre is -R^T t.
                let to_world = rotation.transpose();
                let eye = -(to_world * t);
                let forward = to_world * DVec3::Z;
                let down = to_world * DVec3::Y;
                let near = self.near.unwrap_or_else(|| default_near(eye, sphere));
                let projection = Projection::PerspectiveIntrinsics(Intrinsics {
                    fx: k([0, 0]),
                    fy: k([1, 1]),
                    cx: k([0, 2]),
                    cy: k([1, 2]),
                });
                Camera::new(eye, eye + forward, -down, projection, near, width, height)
            }
            (None, None) => {
                let framing =
                    Camera::framing(sphere.0, sphere.1, width, height).map_err(renderer_error)?;
                let eye = self.eye.map_or(framing.eye, DVec3::from_array);
                let target = self.target.map_or(framing.target, DVec3::from_array);
                let near = self.near.unwrap_or_else(|| default_near(eye, sphere));
                Camera::new(
                    eye,
                    target,
                    DVec3::from_array(self.up),
                    Projection::Perspective {
                        fov_y_deg: self.fov_y,
                    },
                    near,
                    width,
                    height,
                )
            }
            _ => {
                return Err(PyValueError::new_err(
                    "intrinsics and world_to_camera go together",
                ))
            }
        };
        camera.map_err(renderer_error)
    }
}
