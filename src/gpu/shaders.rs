//! SPIR-V compiled by `build.rs` from `glsl/`, and shader-module creation.

use ash::vk;

use crate::error::{Error, Result, VkCall};

/// The ellipsoid impostor vertex shader.
pub const ELLIPSOID_VERT: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid.vert.spv"));
/// The ellipsoid impostor fragment shader.
pub const ELLIPSOID_FRAG: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/ellipsoid.frag.spv"));

/// Creates a shader module from SPIR-V bytes; the caller owns and destroys it.
pub fn create_module(device: &ash::Device, spirv: &[u8]) -> Result<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
        .map_err(|e| Error::invalid("SPIR-V", e.to_string()))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: `words` is SPIR-V produced and validated by glslangValidator --spirv-val.
    unsafe { device.create_shader_module(&info, None) }.call("vkCreateShaderModule")
}
