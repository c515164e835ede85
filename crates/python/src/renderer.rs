//! The renderer object: one Vulkan device kept between calls, the uploaded scene, frames as
//! NumPy arrays. The GPU works with the GIL released.

use std::time::Instant;

use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::{Camera, ContextOptions, OffscreenRenderer, Outputs, Scene};
use glam::DVec3;
use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyReadonlyArray2, PyReadonlyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::camera::CameraArgs;
use crate::errors::renderer_error;
use crate::glyphs::GlyphArrays;
use crate::plan::{plan_dict, plan_mode, plan_name};

/// The renderer behind a raw pointer, so its work can run with the GIL released: the object
/// is `unsendable` and borrowed mutably for the call, so no other thread touches it.
struct Detached(*mut OffscreenRenderer);
// SAFETY: see above: exclusive for the call's duration, on the calling thread's behalf.
unsafe impl Send for Detached {}

impl Detached {
    /// The renderer, for the rest of the call.
    ///
    /// # Safety
    /// The pointer came from a live `&mut OffscreenRenderer` that outlives the returned borrow.
    unsafe fn into_mut<'a>(self) -> &'a mut OffscreenRenderer {
        // SAFETY: caller contract.
        unsafe { &mut *self.0 }
    }
}

/// A Vulkan renderer kept alive between calls (`ellipsoid_splat.Renderer` wraps it).
#[pyclass(unsendable, module = "ellipsoid_splat._native")]
pub struct Renderer {
    renderer: OffscreenRenderer,
    /// The uploaded scene's bounding sphere (the cameras' framing defaults).
    sphere: Option<(DVec3, f64)>,
    count: usize,
}

/// A rendered frame's four outputs and the Rust-side time of the frame in milliseconds.
type FrameArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    f64,
);

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (validation=false, device=None, plan="measure"))]
    fn new(py: Python<'_>, validation: bool, device: Option<String>, plan: &str) -> PyResult<Self> {
        let mode = plan_mode(plan)?;
        let mut options = if validation {
            ContextOptions::validated()
        } else {
            ContextOptions::default()
        };
        options.device = device;
        let mut renderer = py
            .allow_threads(|| OffscreenRenderer::new(&options))
            .map_err(renderer_error)?;
        let mut settings = *renderer.settings();
        settings.plan = mode;
        renderer.set_settings(settings);
        Ok(Self {
            renderer,
            sphere: None,
            count: 0,
        })
    }

    /// Uploads the glyphs (arrays shaped and typed by the Python half); returns their count
    /// and the Rust-side milliseconds (building the ellipsoids and uploading them).
    #[pyo3(signature = (centers, radii, rotations, colors, tensors))]
    fn upload(
        &mut self,
        py: Python<'_>,
        centers: PyReadonlyArray2<'_, f64>,
        radii: Option<PyReadonlyArray2<'_, f64>>,
        rotations: Option<PyReadonlyArray2<'_, f64>>,
        colors: Option<PyReadonlyArray2<'_, f64>>,
        tensors: Option<PyReadonlyArray3<'_, f64>>,
    ) -> PyResult<(usize, f64)> {
        let start = Instant::now();
        let arrays = GlyphArrays {
            centers,
            radii,
            rotations,
            colors,
            tensors,
        };
        let scene = Scene::new(arrays.ellipsoids()?);
        let sphere = scene
            .bounding_sphere()
            .ok_or_else(|| PyValueError::new_err("centers is empty: nothing to render"))?;
        let detached = Detached(&mut self.renderer);
        // SAFETY: `self` is borrowed mutably for the call and outlives it.
        py.allow_threads(move || unsafe { detached.into_mut() }.upload(&scene))
            .map_err(renderer_error)?;
        self.check_validation()?;
        self.sphere = Some(sphere);
        self.count = arrays.centers.as_array().nrows();
        Ok((self.count, start.elapsed().as_secs_f64() * 1e3))
    }

    /// Renders the uploaded glyphs: colour (H, W, 4) uint8 sRGB, depth (H, W) float32 view
    /// depth (+inf where nothing is hit), normal (H, W, 3) float32, id (H, W) uint32
    /// (0xFFFFFFFF where nothing is hit), and the Rust-side milliseconds of the frame.
    #[pyo3(signature = (eye, target, up, fov_y, intrinsics, world_to_camera, width, height, near, supersample))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &mut self,
        py: Python<'py>,
        eye: Option<[f64; 3]>,
        target: Option<[f64; 3]>,
        up: [f64; 3],
        fov_y: f64,
        intrinsics: Option<PyReadonlyArray2<'py, f64>>,
        world_to_camera: Option<PyReadonlyArray2<'py, f64>>,
        width: u32,
        height: u32,
        near: Option<f64>,
        supersample: u32,
    ) -> PyResult<FrameArrays<'py>> {
        let sphere = self
            .sphere
            .ok_or_else(|| PyValueError::new_err("nothing uploaded: call upload first"))?;
        let args = CameraArgs {
            eye,
            target,
            up,
            fov_y,
            intrinsics,
            world_to_camera,
            width,
            height,
            near,
        };
        let camera: Camera = args.camera(sphere)?;
        // K x K samples per pixel: the same view K times larger, box-filtered (as the tool's
        // `--supersample`).
        let drawn = if supersample == 1 {
            camera
        } else {
            supersampled_camera(&camera, supersample).map_err(renderer_error)?
        };
        let detached = Detached(&mut self.renderer);
        let (frame, ms) = py
            .allow_threads(move || {
                let start = Instant::now();
                // SAFETY: `self` is borrowed mutably for the call and outlives it.
                let frame = unsafe { detached.into_mut() }.render_uploaded(&drawn, Outputs::ALL);
                let frame = frame.and_then(|(frame, _)| match supersample {
                    1 => Ok(frame),
                    k => box_filter(&frame, k),
                });
                frame.map(|frame| (frame, start.elapsed().as_secs_f64() * 1e3))
            })
            .map_err(renderer_error)?;
        self.check_validation()?;
        let (h, w) = (frame.height as usize, frame.width as usize);
        let shaped = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
        let color = Array::from_shape_vec((h, w, 4), frame.color.into_iter().flatten().collect())
            .map_err(shaped)?
            .into_pyarray(py);
        let depth = Array::from_shape_vec((h, w), frame.depth)
            .map_err(shaped)?
            .into_pyarray(py);
        let normal = Array::from_shape_vec((h, w, 3), frame.normal.into_iter().flatten().collect())
            .map_err(shaped)?
            .into_pyarray(py);
        let id = Array::from_shape_vec((h, w), frame.id)
            .map_err(shaped)?
            .into_pyarray(py);
        Ok((
            color.into_any(),
            depth.into_any(),
            normal.into_any(),
            id.into_any(),
            ms,
        ))
    }

    /// With validation on: fails with the layer's first message if it said anything.
    fn check_validation(&self) -> PyResult<()> {
        self.renderer
            .context()
            .check_validation()
            .map_err(renderer_error)
    }

    /// How the frame plan chooses its path, by name (`plan_mode`'s names).
    #[getter]
    fn plan(&self) -> &'static str {
        plan_name(self.renderer.settings().plan)
    }

    /// Sets how the frame plan chooses its path; an unknown name changes nothing.
    #[setter]
    fn set_plan(&mut self, plan: &str) -> PyResult<()> {
        let mut settings = *self.renderer.settings();
        settings.plan = plan_mode(plan)?;
        self.renderer.set_settings(settings);
        Ok(())
    }

    /// The plan of the last frame drawn, as a dict, or `None` before the first.
    #[getter]
    fn last_plan<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.renderer
            .last_plan()
            .map(|plan| plan_dict(py, plan))
            .transpose()
    }

    /// What the plan learned on this device, as bytes.
    fn plan_wisdom<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.renderer.plan_wisdom())
    }

    /// Takes in what a renderer on the same device and driver learned; refused bytes raise
    /// `ValueError` with the library's reason and change nothing.
    fn load_plan_wisdom(&mut self, data: &[u8]) -> PyResult<()> {
        self.renderer.load_plan_wisdom(data).map_err(renderer_error)
    }

    /// How many glyphs are uploaded.
    #[getter]
    fn count(&self) -> usize {
        self.count
    }

    /// The device's name.
    #[getter]
    fn device(&self) -> String {
        self.renderer.context().info().name.clone()
    }
}
