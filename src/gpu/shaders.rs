//! SPIR-V compiled by `build.rs` from `glsl/`, and shader-module creation.

use ash::vk;

use crate::error::{Error, Result, VkCall};

/// The ellipsoid impostor vertex shader.
pub const ELLIPSOID_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid.vert.spv"));
/// The ellipsoid impostor fragment shader.
pub const ELLIPSOID_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid.frag.spv"));

/// `ELLIPSOID_VERT` reading the set-up the culling pre-pass computed (`PRESET_SETUP`).
pub const ELLIPSOID_PRESET_VERT: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid_preset.vert.spv"));
/// `ELLIPSOID_FRAG` reading the set-up the culling pre-pass computed (`PRESET_SETUP`).
pub const ELLIPSOID_PRESET_FRAG: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid_preset.frag.spv"));

/// The `impostor-flat-depth` fragment shader (no depth write).
pub const ELLIPSOID_FLAT_DEPTH_FRAG: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid_flat_depth.frag.spv"));
/// The `flat-fill` fragment shader.
pub const FLAT_FILL_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/flat_fill.frag.spv"));
/// Icosphere vertex shader (`mesh-L*`).
pub const MESH_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/mesh.vert.spv"));
/// Icosphere fragment shader (`mesh-L*`).
pub const MESH_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/mesh.frag.spv"));
/// Oriented-box proxy vertex shader (`box-proxy`).
pub const BOX_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/box.vert.spv"));

/// The culling pre-pass compute shader.
pub const CULL_COMP: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/cull.comp.spv"));

/// Fragment shaders built with `COUNT_FRAGMENTS` (an atomic count of shaded pixels).
pub mod counted {
    /// `ELLIPSOID_FRAG` with the fragment counter.
    pub const ELLIPSOID_FRAG: &[u8] =
        include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid.frag.counted.spv"));
    /// `ELLIPSOID_PRESET_FRAG` with the fragment counter.
    pub const ELLIPSOID_PRESET_FRAG: &[u8] = include_bytes!(concat!(
        env!("OUT_DIR"),
        "/ellipsoid_preset.frag.counted.spv"
    ));
    /// `ELLIPSOID_FLAT_DEPTH_FRAG` with the fragment counter.
    pub const ELLIPSOID_FLAT_DEPTH_FRAG: &[u8] = include_bytes!(concat!(
        env!("OUT_DIR"),
        "/ellipsoid_flat_depth.frag.counted.spv"
    ));
    /// `FLAT_FILL_FRAG` with the fragment counter.
    pub const FLAT_FILL_FRAG: &[u8] =
        include_bytes!(concat!(env!("OUT_DIR"), "/flat_fill.frag.counted.spv"));
    /// `MESH_FRAG` with the fragment counter.
    pub const MESH_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/mesh.frag.counted.spv"));
}

/// Creates a shader module from SPIR-V bytes; the caller owns and destroys it.
pub fn create_module(device: &ash::Device, spirv: &[u8]) -> Result<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
        .map_err(|e| Error::invalid("SPIR-V", e.to_string()))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: `words` is SPIR-V produced and validated by glslangValidator --spirv-val.
    unsafe { device.create_shader_module(&info, None) }.call("vkCreateShaderModule")
}
