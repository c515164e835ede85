//! The material, the work-skipping and the frame plan's mode a host may tune.

use ellipsoid_splat::{Culling, Material, Settings};
use ellipsoid_splat::{PathKind, PlanMode};

use crate::status::{guard, output, versioned_prefix, EsStatus, Failure};

/// The shading: Blinn-Phong weights and highlight colour.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsMaterial {
    /// Ambient weight.
    pub ambient: f32,
    /// Diffuse weight.
    pub diffuse: f32,
    /// Specular weight.
    pub specular: f32,
    /// Phong exponent.
    pub shininess: f32,
    /// Colour of highlights (linear RGB).
    pub specular_color: [f32; 3],
}

/// How the frame plan chooses among the exact paths that can serve a frame (each draws the
/// same picture; they differ in cost).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsPlanMode {
    /// First a guess from the scene's size on screen, then the candidate paths timed on
    /// frames the renderer draws anyway, a few frames each; the fastest is kept per scene
    /// class (`es_renderer_plan_wisdom` saves what was learned). Where the queue family has
    /// no timestamps it plans as `ES_PLAN_MODE_ESTIMATE`. The default.
    Measure = 0,
    /// The first guess alone: the same path for the same scene and camera every time.
    Estimate = 1,
    /// The path `fixed_path` names wherever it can serve the frame; otherwise the draw.
    Fixed = 2,
}

/// A kind of exact path a frame can take.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsPathKind {
    /// No path: in `EsSettings.fixed_path` when no path is fixed, in
    /// `EsFramePlan.runner_up` when no other candidate was timed.
    None = 0,
    /// Every glyph rasterized as an impostor (after a pre-pass where it culls or sets up).
    Draw = 1,
    /// The compute splat: the glyphs ray cast into a visibility buffer and shaded by a
    /// resolve in the host's pass; glyphs too large for it are drawn in the same frame.
    Splat = 2,
    /// The compute splat, the glyphs the last frame showed first, the camera still or moving
    /// (its first frame after an upload stamps what it shows).
    VisibleFirst = 3,
}

impl EsPathKind {
    /// The C value of a library kind.
    pub(crate) fn of(kind: PathKind) -> Self {
        match kind {
            PathKind::Draw => Self::Draw,
            PathKind::Splat => Self::Splat,
            PathKind::VisibleFirst => Self::VisibleFirst,
        }
    }
}

/// What a host may tune. Start from `es_settings_default`; every field but the material only
/// changes the work done and leaves the picture the same.
///
/// Versions: the first (`struct_size` 52) ends at `per_sample_shading`; the second adds
/// `plan_mode` and `fixed_path`. The library reads only the version `struct_size` names, and
/// a first-version struct keeps its meaning: `compute_splat` zero keeps every frame on the
/// draw; non-zero lets the plan choose as the renderer's settings had it (measuring unless a
/// second-version struct chose otherwise).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsSettings {
    /// `sizeof(EsSettings)`.
    pub struct_size: u32,
    /// The shading.
    pub material: EsMaterial,
    /// Non-zero: cull glyphs wholly outside the view.
    pub culling_frustum: u32,
    /// Non-zero: cull glyphs that cover no pixel centre.
    pub culling_pixel_centres: u32,
    /// Non-zero: cull glyphs hidden behind nearer ones (needs a `D32_SFLOAT` depth
    /// attachment).
    pub culling_occlusion: u32,
    /// Deprecated (leave it at the default 1 and use `plan_mode`): zero keeps every frame on
    /// the draw whatever `plan_mode` says, as `ES_PLAN_MODE_FIXED` with `ES_PATH_KIND_DRAW`
    /// does; zero with a `plan_mode` that fixes a splat path is refused.
    pub compute_splat: u32,
    /// Non-zero: multisampled targets shade every sample (exact depth per sample) instead of
    /// once per pixel with exact per-sample coverage.
    pub per_sample_shading: u32,
    /// How the frame plan chooses its path: an `EsPlanMode` value (second version).
    pub plan_mode: u32,
    /// With `ES_PLAN_MODE_FIXED`, the path: an `EsPathKind` value other than
    /// `ES_PATH_KIND_NONE`; otherwise ignored (`es_settings_default` writes
    /// `ES_PATH_KIND_NONE`). Second version.
    pub fixed_path: u32,
}

/// The size of the first version of [`EsSettings`] (64-bit targets), frozen.
pub(crate) const SETTINGS_V1: usize = 52;
/// The size of the second version of [`EsSettings`]: `plan_mode` and `fixed_path` added.
pub(crate) const SETTINGS_V2: usize = 60;
// Growing the struct again is a third version (the library reads the prefix a host of an
// older version allocated, its `struct_size`), and `es_settings_default`, which writes the
// whole struct, then needs a new ABI version.
const _: () = assert!(std::mem::size_of::<EsSettings>() == SETTINGS_V2);

/// The plain struct of `settings`.
pub(crate) fn settings_to(settings: &Settings) -> EsSettings {
    let m = settings.material;
    let (plan_mode, fixed_path) = match settings.plan {
        PlanMode::Measure => (EsPlanMode::Measure, EsPathKind::None),
        PlanMode::Estimate => (EsPlanMode::Estimate, EsPathKind::None),
        PlanMode::Fixed(kind) => (EsPlanMode::Fixed, EsPathKind::of(kind)),
    };
    EsSettings {
        struct_size: SETTINGS_V2 as u32,
        material: EsMaterial {
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            specular_color: m.specular_color,
        },
        culling_frustum: settings.culling.frustum as u32,
        culling_pixel_centres: settings.culling.pixel_centres as u32,
        culling_occlusion: settings.culling.occlusion as u32,
        compute_splat: (settings.plan != PlanMode::Fixed(PathKind::Draw)) as u32,
        per_sample_shading: settings.per_sample_shading as u32,
        plan_mode: plan_mode as u32,
        fixed_path: fixed_path as u32,
    }
}

/// The library's kind of an `EsPathKind` value (`None` for `ES_PATH_KIND_NONE`).
fn path_kind(value: u32) -> Result<Option<PathKind>, Failure> {
    Ok(match value {
        v if v == EsPathKind::None as u32 => None,
        v if v == EsPathKind::Draw as u32 => Some(PathKind::Draw),
        v if v == EsPathKind::Splat as u32 => Some(PathKind::Splat),
        v if v == EsPathKind::VisibleFirst as u32 => Some(PathKind::VisibleFirst),
        v => {
            return Err(Failure::invalid(
                "EsSettings.fixed_path",
                format!("{v} is not an EsPathKind"),
            ))
        }
    })
}

/// The plan mode of a second-version struct.
fn plan_mode(settings: &EsSettings) -> Result<PlanMode, Failure> {
    let fixed = path_kind(settings.fixed_path)?;
    let mode = match settings.plan_mode {
        m if m == EsPlanMode::Measure as u32 => PlanMode::Measure,
        m if m == EsPlanMode::Estimate as u32 => PlanMode::Estimate,
        m if m == EsPlanMode::Fixed as u32 => PlanMode::Fixed(fixed.ok_or_else(|| {
            Failure::invalid(
                "EsSettings.fixed_path",
                "is ES_PATH_KIND_NONE with ES_PLAN_MODE_FIXED: name the path to fix",
            )
        })?),
        m => {
            return Err(Failure::invalid(
                "EsSettings.plan_mode",
                format!("{m} is not an EsPlanMode"),
            ))
        }
    };
    if settings.compute_splat != 0 {
        return Ok(mode);
    }
    match mode {
        PlanMode::Fixed(kind) if kind != PathKind::Draw => Err(Failure::invalid(
            "EsSettings.compute_splat",
            format!(
                "is 0 (the draw alone), but plan_mode fixes the {} path: set compute_splat to 1",
                kind.name()
            ),
        )),
        _ => Ok(PlanMode::Fixed(PathKind::Draw)),
    }
}

/// `base` with the host's choices of `settings`, of which the first `size` bytes were the
/// host's (its `struct_size`, at least [`SETTINGS_V1`]).
pub(crate) fn settings_from(
    settings: &EsSettings,
    size: usize,
    base: &Settings,
) -> Result<Settings, Failure> {
    let mut out = *base;
    let mut material = Material::default();
    material.ambient = settings.material.ambient;
    material.diffuse = settings.material.diffuse;
    material.specular = settings.material.specular;
    material.shininess = settings.material.shininess;
    material.specular_color = settings.material.specular_color;
    out.material = material;
    let mut culling = Culling::OFF;
    culling.frustum = settings.culling_frustum != 0;
    culling.pixel_centres = settings.culling_pixel_centres != 0;
    culling.occlusion = settings.culling_occlusion != 0;
    out.culling = culling;
    out.plan = if size >= SETTINGS_V2 {
        plan_mode(settings)?
    } else {
        // The first version: `compute_splat` alone, as it meant then.
        match (settings.compute_splat != 0, base.plan) {
            (false, _) => PlanMode::Fixed(PathKind::Draw),
            (true, PlanMode::Fixed(PathKind::Draw)) => PlanMode::Measure,
            (true, plan) => plan,
        }
    };
    out.per_sample_shading = settings.per_sample_shading != 0;
    Ok(out)
}

/// The settings behind a host's pointer: the fields of the version its `struct_size` names
/// (those of later versions as in `base`), checked.
///
/// # Safety
/// A non-null `settings` points at a readable struct of at least its `struct_size` bytes
/// (or of `sizeof(EsSettings)`, whichever is smaller), whose first field is `struct_size`.
pub(crate) unsafe fn read_settings(
    settings: *const EsSettings,
    base: &Settings,
) -> Result<Settings, Failure> {
    let later = || settings_to(base);
    // SAFETY: caller contract; `EsSettings` holds only `u32`s and `f32`s.
    let (host, size) = unsafe { versioned_prefix(settings, "settings", SETTINGS_V1, later)? };
    settings_from(&host, size, base)
}

/// Fills `out_settings` with the shipped renderer's settings (the whole struct, this
/// header's version). Any thread.
///
/// # Safety
/// `out_settings` points at a writable `EsSettings`.
#[no_mangle]
pub unsafe extern "C" fn es_settings_default(out_settings: *mut EsSettings) -> EsStatus {
    guard("es_settings_default", || {
        // SAFETY: caller contract.
        *unsafe { output(out_settings, "out_settings")? } = settings_to(&Settings::default());
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn host(size: usize) -> EsSettings {
        let mut s = settings_to(&Settings::default());
        s.struct_size = size as u32;
        s
    }

    fn read(s: &EsSettings, base: &Settings) -> Result<Settings, Failure> {
        // SAFETY: a whole struct.
        unsafe { read_settings(s, base) }
    }

    #[test]
    fn the_defaults_measure_and_round_trip() {
        let s = host(SETTINGS_V2);
        assert_eq!(
            (s.plan_mode, s.fixed_path, s.compute_splat),
            (EsPlanMode::Measure as u32, EsPathKind::None as u32, 1)
        );
        let back = read(&s, &Settings::default()).unwrap();
        assert_eq!(back.plan, PlanMode::Measure);
        for plan in [
            PlanMode::Estimate,
            PlanMode::Fixed(PathKind::Draw),
            PlanMode::Fixed(PathKind::Splat),
            PlanMode::Fixed(PathKind::VisibleFirst),
        ] {
            let mut settings = Settings::default();
            settings.plan = plan;
            let plain = settings_to(&settings);
            assert_eq!(read(&plain, &Settings::default()).unwrap().plan, plan);
        }
    }

    #[test]
    fn a_first_version_struct_keeps_its_meaning() {
        let mut estimate = Settings::default();
        estimate.plan = PlanMode::Estimate;
        // Only the first 52 bytes are the host's: what lies after them is never read.
        let mut s = host(SETTINGS_V1);
        s.plan_mode = 0xdead;
        s.fixed_path = 0xbeef;
        assert_eq!(read(&s, &estimate).unwrap().plan, PlanMode::Estimate);
        s.compute_splat = 0;
        let drawn = read(&s, &estimate).unwrap();
        assert_eq!(drawn.plan, PlanMode::Fixed(PathKind::Draw));
        s.compute_splat = 1;
        assert_eq!(read(&s, &drawn).unwrap().plan, PlanMode::Measure);
    }

    #[test]
    fn bad_modes_and_paths_are_named() {
        let base = Settings::default();
        let mut s = host(SETTINGS_V2);
        s.plan_mode = 3;
        let e = read(&s, &base).unwrap_err();
        assert_eq!(e.status, EsStatus::ErrorInvalidArgument);
        assert!(
            e.message.contains("plan_mode") && e.message.contains('3'),
            "{e:?}"
        );
        s.plan_mode = EsPlanMode::Fixed as u32;
        let e = read(&s, &base).unwrap_err();
        assert!(e.message.contains("fixed_path"), "{e:?}");
        s.fixed_path = 9;
        let e = read(&s, &base).unwrap_err();
        assert!(
            e.message.contains("fixed_path") && e.message.contains('9'),
            "{e:?}"
        );
        s.fixed_path = EsPathKind::Splat as u32;
        assert_eq!(
            read(&s, &base).unwrap().plan,
            PlanMode::Fixed(PathKind::Splat)
        );
        s.compute_splat = 0;
        let e = read(&s, &base).unwrap_err();
        assert!(e.message.contains("compute_splat"), "{e:?}");
        s.plan_mode = EsPlanMode::Estimate as u32;
        assert_eq!(
            read(&s, &base).unwrap().plan,
            PlanMode::Fixed(PathKind::Draw)
        );
        s.struct_size = 51;
        let e = read(&s, &base).unwrap_err();
        assert!(e.message.contains("struct_size is 51"), "{e:?}");
    }
}
