//! The material and the work-skipping a host may tune.

use ellipsoid_splat::{Culling, Material, Settings};

use crate::status::{guard, output, EsStatus};

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

/// What a host may tune. Start from `es_settings_default`; every field but the material only
/// skips work and leaves the picture the same.
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
    /// Non-zero: frames of many small glyphs skip the rasterizer where the device allows.
    pub compute_splat: u32,
    /// Non-zero: multisampled targets shade every sample (exact depth per sample) instead of
    /// once per pixel with exact per-sample coverage.
    pub per_sample_shading: u32,
}

/// The size of the first version of [`EsSettings`] (64-bit targets), frozen.
pub(crate) const SETTINGS_V1: usize = 52;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsSettings>() == SETTINGS_V1);

/// The plain struct of `settings`.
pub(crate) fn settings_to(settings: &Settings) -> EsSettings {
    let m = settings.material;
    EsSettings {
        struct_size: SETTINGS_V1 as u32,
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
        compute_splat: settings.compute_splat as u32,
        per_sample_shading: settings.per_sample_shading as u32,
    }
}

/// `base` with the host's choices of `settings`.
pub(crate) fn settings_from(settings: &EsSettings, base: &Settings) -> Settings {
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
    out.compute_splat = settings.compute_splat != 0;
    out.per_sample_shading = settings.per_sample_shading != 0;
    out
}

/// Fills `out_settings` with the shipped renderer's settings. Any thread.
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
