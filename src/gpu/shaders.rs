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

/// Creates a fragment shader module whose declared conservative depth (`depth_less`, for
/// reversed Z) is mirrored to `depth_greater` when `reversed_z` is false: the written depth
/// then lies at or beyond the quad's in standard Z, so the declaration stays true.
pub fn create_fragment_module(
    device: &ash::Device,
    spirv: &[u8],
    reversed_z: bool,
) -> Result<vk::ShaderModule> {
    if reversed_z {
        return create_module(device, spirv);
    }
    let mut words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))
        .map_err(|e| Error::invalid("SPIR-V", e.to_string()))?;
    mirror_depth_layout(&mut words);
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_ne_bytes()).collect();
    create_module(device, &bytes)
}

/// SPIR-V `OpExecutionMode` and its `DepthGreater` / `DepthLess` modes.
const OP_EXECUTION_MODE: u32 = 16;
const DEPTH_GREATER: u32 = 14;
const DEPTH_LESS: u32 = 15;

/// Turns `OpExecutionMode %main DepthLess` into `DepthGreater`; returns how many it changed.
fn mirror_depth_layout(words: &mut [u32]) -> usize {
    let mut changed = 0;
    let mut at = 5; // after the header
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        let opcode = words[at] & 0xffff;
        if count == 0 {
            break; // malformed; leave the rest to the driver's validation
        }
        if opcode == OP_EXECUTION_MODE && count >= 3 && words.get(at + 2) == Some(&DEPTH_LESS) {
            words[at + 2] = DEPTH_GREATER;
            changed += 1;
        }
        at += count;
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_depth_writing_fragment_shader_declares_depth_less_once() {
        for spirv in [
            ELLIPSOID_FRAG,
            ELLIPSOID_PRESET_FRAG,
            counted::ELLIPSOID_FRAG,
        ] {
            let mut words = ash::util::read_spv(&mut std::io::Cursor::new(spirv)).unwrap();
            assert_eq!(mirror_depth_layout(&mut words), 1);
            assert_eq!(mirror_depth_layout(&mut words), 0, "now DepthGreater");
        }
    }
}
