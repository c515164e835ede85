//! What a frame with a camera will do: the renderer's plan, as a plain struct.

use std::ffi::{c_char, CStr, CString};
use std::sync::Mutex;

use ellipsoid_splat::{DrawReason, FramePlan};

use crate::camera::{read_camera, EsCamera};
use crate::renderer::{with_renderer, EsRenderer};
use crate::status::{output, EsStatus};

/// The plan of a frame: every decision `es_renderer_record_prepass` and `es_renderer_record`
/// will take with that camera.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsFramePlan {
    /// `sizeof(EsFramePlan)`, set by the library.
    pub struct_size: u32,
    /// Non-zero: the pre-pass runs (to cull, to set glyphs up, or to splat), and the draw
    /// is indirect.
    pub prepass: u32,
    /// Non-zero: the compute splat draws the small glyphs without the rasterizer.
    pub compute_splat: u32,
    /// Why the frame keeps the draw: a NUL-terminated sentence, or null where the compute
    /// splat runs (static storage).
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
    /// Non-zero: the glyphs the view's last still frame showed go first.
    pub visible_first: u32,
    /// Samples the fragment stage decides per pixel (0 where it shades every sample).
    pub coverage_samples: u32,
    /// Non-zero: an orthographic camera.
    pub orthographic: u32,
    /// Non-zero: reversed Z.
    pub reversed_z: u32,
}

/// The library's sentence of `reason`, NUL-terminated in static storage: each reason's text
/// is made once and kept for the life of the process (a handful of short strings).
fn reason_text(reason: DrawReason) -> *const c_char {
    static TEXTS: Mutex<Vec<(DrawReason, &'static CStr)>> = Mutex::new(Vec::new());
    let mut texts = TEXTS
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some((_, text)) = texts.iter().find(|(r, _)| *r == reason) {
        return text.as_ptr();
    }
    let text = CString::new(reason.to_string().replace('\0', " ")).unwrap_or_default();
    let text: &'static CStr = Box::leak(text.into_boxed_c_str());
    texts.push((reason, text));
    text.as_ptr()
}

/// The plain struct of `plan`.
fn plan_to(plan: &FramePlan) -> EsFramePlan {
    EsFramePlan {
        struct_size: std::mem::size_of::<EsFramePlan>() as u32,
        prepass: plan.prepass as u32,
        compute_splat: plan.compute_splat as u32,
        drawn_because: plan.drawn_because.map_or(std::ptr::null(), reason_text),
        mean_area_px: plan.mean_area_px.unwrap_or(-1.0),
        culling_frustum: plan.culling.frustum as u32,
        culling_pixel_centres: plan.culling.pixel_centres as u32,
        culling_occlusion: plan.culling.occlusion as u32,
        setup_once: plan.setup_once as u32,
        visible_first: plan.visible_first as u32,
        coverage_samples: plan.coverage_samples,
        orthographic: plan.orthographic as u32,
        reversed_z: plan.reversed_z as u32,
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
