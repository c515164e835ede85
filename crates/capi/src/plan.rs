//! What a frame with a camera will do, or what the last one did: the renderer's plan, as a
//! plain struct.

use std::ffi::{c_char, CStr, CString};
use std::fmt::Display;
use std::sync::Mutex;

use ellipsoid_splat::FramePlan;
use ellipsoid_splat::{FramePath, HiddenLayers, PlanReason};

use crate::camera::{read_camera, EsCamera};
use crate::renderer::{with_renderer, EsRenderer};
use crate::settings::EsPathKind;
use crate::status::{output, EsStatus, Failure};

/// Which glyphs a splatted frame ray casts first, and what it leaves out.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsHiddenLayers {
    /// The frame draws every glyph: nothing is splatted.
    None = 0,
    /// Every glyph is splatted, hidden ones too.
    SplatAll = 1,
    /// Every glyph is splatted, and those the frame shows are stamped so that the next frame
    /// can splat them first (the visible-first splat's first frame after an upload).
    StampShown = 2,
    /// The glyphs the last stamping frame showed are splatted first, then of the rest only those
    /// their hits do not hide.
    VisibleFirst = 3,
}

/// Why a frame takes its path.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsPlanReasonKind {
    /// The draw is the only path that can serve the frame (`drawn_because` says why).
    Only = 0,
    /// The host fixed the path (`ES_PLAN_MODE_FIXED`).
    Fixed = 1,
    /// The first guess from the scene's size on screen (before measuring, or with
    /// `ES_PLAN_MODE_ESTIMATE`).
    Estimated = 2,
    /// A candidate timed while the plan learns this scene class.
    Exploring = 3,
    /// The fastest candidate measured for this scene class on this device (`measured_ms`,
    /// `runner_up`, `runner_up_ms`).
    Measured = 4,
}

/// The plan of a frame: the path `es_renderer_record_prepass` and `es_renderer_record`
/// take with a camera, why, and what it does. Written whole by the library (this header's
/// version).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsFramePlan {
    /// `sizeof(EsFramePlan)`, set by the library.
    pub struct_size: u32,
    /// Non-zero: the pre-pass runs (to cull, to set glyphs up, or to splat), and the draw
    /// is indirect.
    pub prepass: u32,
    /// Non-zero: the compute splat draws the glyphs without the rasterizer (`path` is
    /// `ES_PATH_KIND_SPLAT` or `ES_PATH_KIND_VISIBLE_FIRST`).
    pub compute_splat: u32,
    /// Where the draw is the only path (`reason` is `ES_PLAN_REASON_KIND_ONLY`), why: a
    /// NUL-terminated sentence in static storage; null otherwise.
    pub drawn_because: *const c_char,
    /// The sampled glyphs' mean projected area in pixels; negative where none is on screen.
    pub mean_area_px: f64,
    /// Non-zero for each culling that runs.
    pub culling_frustum: u32,
    /// As above: pixel centres.
    pub culling_pixel_centres: u32,
    /// As above: occlusion.
    pub culling_occlusion: u32,
    /// Non-zero: small glyphs are set up once by the pre-pass.
    pub setup_once: u32,
    /// Non-zero: the glyphs the view's last stamping frame showed go first (`hidden_layers`
    /// is `ES_HIDDEN_LAYERS_VISIBLE_FIRST`).
    pub visible_first: u32,
    /// Samples the fragment stage decides per pixel (0 where it shades every sample).
    pub coverage_samples: u32,
    /// Non-zero: an orthographic camera.
    pub orthographic: u32,
    /// Non-zero: reversed Z.
    pub reversed_z: u32,
    /// The path the frame takes: an `EsPathKind` value (`ES_PATH_KIND_VISIBLE_FIRST` also for
    /// its first frame after an upload, which stamps what it shows).
    pub path: u32,
    /// What a splatted frame does about hidden glyphs: an `EsHiddenLayers` value
    /// (`ES_HIDDEN_LAYERS_NONE` where the frame draws).
    pub hidden_layers: u32,
    /// Why the frame takes its path: an `EsPlanReasonKind` value.
    pub reason: u32,
    /// With `ES_PLAN_REASON_KIND_MEASURED`, the next fastest candidate: an `EsPathKind`
    /// value, `ES_PATH_KIND_NONE` where no other was timed (or the plan did not measure).
    pub runner_up: u32,
    /// With `ES_PLAN_REASON_KIND_MEASURED`, the median GPU time of the path's frames in
    /// milliseconds; negative otherwise.
    pub measured_ms: f64,
    /// The runner-up's median GPU time in milliseconds; negative where there is none.
    pub runner_up_ms: f64,
}

/// The size of the first version of [`EsFramePlan`] (64-bit targets), frozen: it ended at
/// `reversed_z`.
pub(crate) const FRAME_PLAN_V1: usize = 64;
/// The size of the second version: the path, hidden layers, reason and measured times.
pub(crate) const FRAME_PLAN_V2: usize = 96;
// The library writes the whole struct: growing it again changes `ES_ABI_VERSION`.
const _: () = assert!(std::mem::size_of::<EsFramePlan>() == FRAME_PLAN_V2);
const _: () = assert!(std::mem::offset_of!(EsFramePlan, path) == FRAME_PLAN_V1);

/// The library's sentence of `reason` (why the draw is the only path), NUL-terminated in
/// static storage: each distinct sentence is made once and kept for the life of the process
/// (a handful of short strings).
fn reason_text(reason: impl Display) -> *const c_char {
    static TEXTS: Mutex<Vec<&'static CStr>> = Mutex::new(Vec::new());
    let sentence = CString::new(reason.to_string().replace('\0', " ")).unwrap_or_default();
    let mut texts = TEXTS
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(text) = texts
        .iter()
        .copied()
        .find(|text| *text == sentence.as_c_str())
    {
        return text.as_ptr();
    }
    let text: &'static CStr = Box::leak(sentence.into_boxed_c_str());
    texts.push(text);
    text.as_ptr()
}

/// The plain struct of `plan`.
fn plan_to(plan: &FramePlan) -> EsFramePlan {
    let (path, hidden_layers) = match plan.path {
        FramePath::Draw(_) => (EsPathKind::Draw, EsHiddenLayers::None),
        FramePath::Splat(splat) => match splat.hidden {
            HiddenLayers::SplatAll => (EsPathKind::Splat, EsHiddenLayers::SplatAll),
            HiddenLayers::StampShown => (EsPathKind::VisibleFirst, EsHiddenLayers::StampShown),
            HiddenLayers::VisibleFirst { .. } => {
                (EsPathKind::VisibleFirst, EsHiddenLayers::VisibleFirst)
            }
        },
    };
    let (reason, measured) = match plan.reason {
        PlanReason::Only(_) => (EsPlanReasonKind::Only, None),
        PlanReason::Fixed => (EsPlanReasonKind::Fixed, None),
        PlanReason::Estimated(_) => (EsPlanReasonKind::Estimated, None),
        PlanReason::Measured(m) => (EsPlanReasonKind::Measured, Some(m)),
        PlanReason::Exploring => (EsPlanReasonKind::Exploring, None),
        // A reason a later library adds: the plan is still learning.
        _ => (EsPlanReasonKind::Exploring, None),
    };
    let runner_up = measured.and_then(|m| m.runner_up);
    EsFramePlan {
        struct_size: std::mem::size_of::<EsFramePlan>() as u32,
        prepass: plan.prepass() as u32,
        compute_splat: plan.path.splat().is_some() as u32,
        drawn_because: match plan.reason {
            PlanReason::Only(why) => reason_text(why),
            _ => std::ptr::null(),
        },
        mean_area_px: plan.mean_area_px.unwrap_or(-1.0),
        culling_frustum: plan.culling().frustum as u32,
        culling_pixel_centres: plan.culling().pixel_centres as u32,
        culling_occlusion: plan.culling().occlusion as u32,
        setup_once: plan.setup_once() as u32,
        visible_first: (hidden_layers == EsHiddenLayers::VisibleFirst) as u32,
        coverage_samples: plan.coverage_samples,
        orthographic: plan.orthographic as u32,
        reversed_z: plan.reversed_z as u32,
        path: path as u32,
        hidden_layers: hidden_layers as u32,
        reason: reason as u32,
        runner_up: runner_up.map_or(EsPathKind::None, |(k, _)| EsPathKind::of(k)) as u32,
        measured_ms: measured.map_or(-1.0, |m| m.ms),
        runner_up_ms: runner_up.map_or(-1.0, |(_, ms)| ms),
    }
}

/// The plan the next `es_renderer_record_prepass` with `camera` would make (the views'
/// history is the renderer's: call it before recording). Thread: the renderer's.
///
/// # Safety
/// `renderer` is a live renderer; `camera` points at a valid `EsCamera`; `out_plan` at a
/// writable `EsFramePlan`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_plan(
    renderer: *mut EsRenderer,
    camera: *const EsCamera,
    out_plan: *mut EsFramePlan,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_plan", |r| {
            let camera = read_camera(camera)?;
            let out = output(out_plan, "out_plan")?;
            *out = plan_to(&r.renderer()?.plan(&camera)?);
            Ok(())
        })
    }
}

/// The plan of the last frame recorded (the last `es_renderer_record_prepass`): the path it
/// took and why. Fails with `ES_STATUS_ERROR_INVALID_ARGUMENT` before the first pre-pass.
/// Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `out_plan` points at a writable `EsFramePlan`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_last_plan(
    renderer: *mut EsRenderer,
    out_plan: *mut EsFramePlan,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_last_plan", |r| {
            let out = output(out_plan, "out_plan")?;
            let plan = r.renderer()?.last_plan().ok_or_else(|| {
                Failure::invalid(
                    "renderer",
                    "has recorded no frame yet (es_renderer_record_prepass makes the plan)",
                )
            })?;
            *out = plan_to(plan);
            Ok(())
        })
    }
}
