//! The renderer object: one Vulkan device kept between calls, the uploaded scene, frames as
//! NumPy arrays. Any thread may call it: the native state sits behind a mutex, taken with the
//! GIL released (so a thread waiting for it never holds the GIL that the thread inside needs
//! to return), and the device works with the GIL released too.

use std::sync::Mutex;
use std::time::Instant;

use ellipsoid_splat::supersample::{box_filter, supersampled_camera};
use ellipsoid_splat::{ContextOptions, Ellipsoid, FramePlan, OffscreenRenderer, Scene};
use ellipsoid_splat::{Frame, Outputs};
use glam::DVec3;
use numpy::ndarray::Array;
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use crate::camera::{matrix, CameraArgs};
use crate::errors::{no_panic, poisoned, renderer_error};
use crate::glyphs::{Changes, Floats2, Floats3, GlyphArrays};
use crate::plan::{plan_dict, plan_mode, plan_name};

/// The renderer moves between threads with its mutex: it must be `Send` (a compile-time
/// check; `Mutex<State>` is then `Sync` too, as a shared `#[pyclass]` must be).
const _: fn() = || {
    fn send<T: Send>() {}
    send::<OffscreenRenderer>();
    send::<State>();
};

/// Runs of updated glyphs at most this far apart are written in one range, the glyphs between
/// them again with their own values (one submission instead of several).
const MERGE_GAP: u32 = 256;

/// What one call at a time may use.
pub(crate) struct State {
    renderer: OffscreenRenderer,
    /// The uploaded glyphs: the fields an update does not give, and the framing sphere.
    scene: Option<Scene>,
    /// The uploaded scene's bounding sphere (the cameras' framing defaults).
    sphere: Option<(DVec3, f64)>,
    /// The upload coloured its glyphs by their shapes (no colours given).
    shape_colors: bool,
    /// The data addresses of the arrays the last upload read (a test hook).
    addresses: Vec<usize>,
}

impl State {
    /// The renderer, for a frame that uploads glyphs of its own (a composited frame's share):
    /// the scene uploaded before is forgotten, so `render_uploaded` and `update` ask for a new
    /// upload.
    #[cfg_attr(not(feature = "mpi"), allow(dead_code))]
    pub(crate) fn renderer_for_own_upload(&mut self) -> &mut OffscreenRenderer {
        self.scene = None;
        self.sphere = None;
        &mut self.renderer
    }

    /// With validation on: fails with the layer's first message if it said anything.
    pub(crate) fn check_validation(&self) -> PyResult<()> {
        self.renderer
            .context()
            .check_validation()
            .map_err(renderer_error)
    }
}

/// A Vulkan renderer kept alive between calls (`ellipsoid_splat.Renderer` wraps it). Any
/// thread may use it, one call at a time: a call waits for the one running.
#[pyclass(frozen, module = "ellipsoid_splat._native")]
pub struct Renderer {
    pub(crate) state: Mutex<State>,
}

/// A rendered frame's four outputs and the Rust-side time of the frame in milliseconds.
pub(crate) type FrameArrays<'py> = (
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    f64,
);

impl Renderer {
    /// Runs `work` on the state with the GIL released, after the calls of other threads that
    /// hold it. A panic inside becomes `DeviceError` and leaves the state poisoned: every
    /// later call raises `PoisonedError`.
    fn with_state<T: Send>(
        &self,
        py: Python<'_>,
        work: impl FnOnce(&mut State) -> PyResult<T> + Send,
    ) -> PyResult<T> {
        py.allow_threads(|| {
            no_panic(|| {
                // The guard is dropped while unwinding a panic of `work`: that poisons the lock.
                let mut state = self.state.lock().map_err(|_| poisoned())?;
                work(&mut state)
            })
        })
    }
}

/// A frame's outputs as NumPy arrays.
pub(crate) fn frame_arrays(py: Python<'_>, frame: Frame, ms: f64) -> PyResult<FrameArrays<'_>> {
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

/// A range an update writes: glyphs `first..end`, holding the update's `runs` (first index,
/// length, the offset of the run's first row in the update's rows); the glyphs between runs
/// are written again with their own values.
struct Span {
    first: u32,
    end: u32,
    runs: Vec<(u32, u32, usize)>,
}

/// The spans an update writes: its runs (first index, length; sorted, apart), those at most
/// `MERGE_GAP` apart merged.
fn spans(runs: &[(u32, u32)]) -> Vec<Span> {
    let mut spans: Vec<Span> = Vec::new();
    let mut row = 0;
    for &(first, len) in runs {
        let end = first + len;
        match spans.last_mut() {
            Some(span) if first - span.end <= MERGE_GAP => {
                span.end = end;
                span.runs.push((first, len, row));
            }
            _ => spans.push(Span {
                first,
                end,
                runs: vec![(first, len, row)],
            }),
        }
        row += len as usize;
    }
    spans
}

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
        let renderer = py.allow_threads(|| {
            no_panic(|| {
                let mut renderer = OffscreenRenderer::new(&options).map_err(renderer_error)?;
                let mut settings = *renderer.settings();
                settings.plan = mode;
                renderer.set_settings(settings);
                Ok(renderer)
            })
        })?;
        Ok(Self {
            state: Mutex::new(State {
                renderer,
                scene: None,
                sphere: None,
                shape_colors: false,
                addresses: Vec::new(),
            }),
        })
    }

    /// Uploads the glyphs (arrays shaped by the Python half, float64 or float32, read where
    /// they are); returns their count and the Rust-side milliseconds (building the ellipsoids
    /// and uploading them).
    #[pyo3(signature = (centers, radii, rotations, colors, tensors))]
    fn upload(
        &self,
        py: Python<'_>,
        centers: Floats2<'_>,
        radii: Option<Floats2<'_>>,
        rotations: Option<Floats2<'_>>,
        colors: Option<Floats2<'_>>,
        tensors: Option<Floats3<'_>>,
    ) -> PyResult<(usize, f64)> {
        let start = Instant::now();
        let arrays = GlyphArrays {
            centers,
            radii,
            rotations,
            colors,
            tensors,
        };
        // The arrays are read with the GIL held: no other Python thread changes them meanwhile.
        let (scene, addresses) =
            no_panic(|| Ok((Scene::new(arrays.ellipsoids()?), arrays.addresses())))?;
        let shape_colors = arrays.colors.is_none();
        let sphere = scene
            .bounding_sphere()
            .ok_or_else(|| PyValueError::new_err("centers is empty: nothing to render"))?;
        let count = scene.len();
        self.with_state(py, move |state| {
            // A failed upload changes nothing: the glyphs uploaded before stay, here too.
            state.renderer.upload(&scene).map_err(renderer_error)?;
            state.check_validation()?;
            state.scene = Some(scene);
            state.sphere = Some(sphere);
            state.shape_colors = shape_colors;
            state.addresses = addresses;
            Ok(())
        })?;
        Ok((count, start.elapsed().as_secs_f64() * 1e3))
    }

    /// Replaces glyphs of the uploaded scene: `runs` are (first index, length) pairs, sorted
    /// and apart (the Python half groups the indices), and the arrays given hold one row per
    /// updated glyph in the runs' order; the fields not given keep their values. Returns the
    /// Rust-side milliseconds. Nothing changes if a glyph is invalid (`ValueError` naming it).
    #[pyo3(signature = (runs, centers, radii, rotations, colors))]
    fn update(
        &self,
        py: Python<'_>,
        runs: Vec<(u32, u32)>,
        centers: Option<Floats2<'_>>,
        radii: Option<Floats2<'_>>,
        rotations: Option<Floats2<'_>>,
        colors: Option<Floats2<'_>>,
    ) -> PyResult<f64> {
        let start = Instant::now();
        let rows = runs.iter().map(|&(_, len)| len as usize).sum();
        let changes = no_panic(|| Changes::new(rows, centers, radii, rotations, colors))?;
        self.with_state(py, move |state| {
            let shape_colors = state.shape_colors;
            let scene = state
                .scene
                .as_mut()
                .ok_or_else(|| PyValueError::new_err("nothing uploaded: call upload first"))?;
            let count = scene.len() as u64;
            let mut end = 0;
            for &(first, len) in &runs {
                if len == 0 || (first as u64) < end || first as u64 + len as u64 > count {
                    return Err(PyValueError::new_err(format!(
                        "indices: runs must be sorted, apart and within the {count} glyphs \
                         uploaded, got {first}..{}",
                        first as u64 + len as u64
                    )));
                }
                end = first as u64 + len as u64;
            }
            // Every new glyph first: an invalid one changes nothing.
            let spans = spans(&runs);
            let mut written: Vec<(u32, Vec<Ellipsoid>)> = Vec::with_capacity(spans.len());
            for Span { first, end, runs } in spans {
                let mut glyphs = scene.ellipsoids[first as usize..end as usize].to_vec();
                for (run_first, len, row) in runs {
                    for j in 0..len as usize {
                        let index = run_first as usize + j;
                        let slot = &mut glyphs[index - first as usize];
                        *slot = changes
                            .apply(slot, row + j, shape_colors)
                            .map_err(|e| PyValueError::new_err(format!("glyph {index}: {e}")))?;
                    }
                }
                written.push((first, glyphs));
            }
            // Each range is written whole or not at all: the glyphs kept here follow the
            // ranges the renderer took, also when a later one fails.
            let mut done = Ok(());
            for (first, glyphs) in written {
                done = state
                    .renderer
                    .update(first, &glyphs)
                    .map_err(renderer_error);
                if done.is_err() {
                    break;
                }
                let at = first as usize;
                scene.ellipsoids[at..at + glyphs.len()].copy_from_slice(&glyphs);
            }
            state.sphere = scene.bounding_sphere();
            done?;
            state.check_validation()
        })?;
        Ok(start.elapsed().as_secs_f64() * 1e3)
    }

    /// Renders the uploaded glyphs: colour (H, W, 4) uint8 sRGB, depth (H, W) float32 view
    /// depth (+inf where nothing is hit), normal (H, W, 3) float32, id (H, W) uint32
    /// (0xFFFFFFFF where nothing is hit), and the Rust-side milliseconds of the frame.
    #[pyo3(signature = (eye, target, up, fov_y, intrinsics, world_to_camera, width, height, near, supersample))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
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
        let args = CameraArgs {
            eye,
            target,
            up,
            fov_y,
            intrinsics: matrix("intrinsics", intrinsics)?,
            world_to_camera: matrix("world_to_camera", world_to_camera)?,
            width,
            height,
            near,
        };
        let (frame, ms) = self.with_state(py, move |state| {
            let sphere = state
                .sphere
                .ok_or_else(|| PyValueError::new_err("nothing uploaded: call upload first"))?;
            let camera = args.camera(sphere)?;
            // K x K samples per pixel: the same view K times larger, box-filtered (as the
            // tool's `--supersample`).
            let drawn = if supersample == 1 {
                camera
            } else {
                supersampled_camera(&camera, supersample).map_err(renderer_error)?
            };
            let start = Instant::now();
            let (frame, _) = state
                .renderer
                .render_uploaded(&drawn, Outputs::ALL)
                .map_err(renderer_error)?;
            let frame = match supersample {
                1 => frame,
                k => box_filter(&frame, k).map_err(renderer_error)?,
            };
            let ms = start.elapsed().as_secs_f64() * 1e3;
            state.check_validation()?;
            Ok((frame, ms))
        })?;
        frame_arrays(py, frame, ms)
    }

    /// How the frame plan chooses its path, by name (`plan_mode`'s names).
    #[getter]
    fn plan(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.with_state(py, |state| Ok(plan_name(state.renderer.settings().plan)))
    }

    /// Sets how the frame plan chooses its path; an unknown name changes nothing.
    #[setter]
    fn set_plan(&self, py: Python<'_>, plan: &str) -> PyResult<()> {
        let mode = plan_mode(plan)?;
        self.with_state(py, |state| {
            let mut settings = *state.renderer.settings();
            settings.plan = mode;
            state.renderer.set_settings(settings);
            Ok(())
        })
    }

    /// The plan of the last frame drawn, as a dict, or `None` before the first.
    #[getter]
    fn last_plan<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let plan: Option<FramePlan> =
            self.with_state(py, |state| Ok(state.renderer.last_plan().copied()))?;
        plan.map(|plan| plan_dict(py, &plan)).transpose()
    }

    /// What the plan learned on this device, as bytes.
    fn plan_wisdom<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let bytes = self.with_state(py, |state| Ok(state.renderer.plan_wisdom()))?;
        Ok(PyBytes::new(py, &bytes))
    }

    /// Takes in what a renderer on the same device and driver learned; refused bytes raise
    /// `ValueError` with the library's reason and change nothing.
    fn load_plan_wisdom(&self, py: Python<'_>, data: &[u8]) -> PyResult<()> {
        self.with_state(py, |state| {
            state
                .renderer
                .load_plan_wisdom(data)
                .map_err(renderer_error)
        })
    }

    /// How many glyphs are uploaded.
    #[getter]
    fn count(&self, py: Python<'_>) -> PyResult<usize> {
        self.with_state(py, |state| Ok(state.scene.as_ref().map_or(0, Scene::len)))
    }

    /// The device's name.
    #[getter]
    fn device(&self, py: Python<'_>) -> PyResult<String> {
        self.with_state(py, |state| Ok(state.renderer.context().info().name.clone()))
    }

    /// The data addresses of the arrays the last upload read, in argument order (centers,
    /// radii, rotations, colors, tensors; 0 where not given): a test hook, to show that
    /// float32 arrays reach the library without a copy.
    #[getter]
    fn _upload_addresses(&self, py: Python<'_>) -> PyResult<Vec<usize>> {
        self.with_state(py, |state| Ok(state.addresses.clone()))
    }
}
