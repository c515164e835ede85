//! SPIR-V compiled by `build.rs` from `glsl/`, and shader-module creation.

use ash::vk;

use crate::error::{Error, Result, VkCall};

/// One fragment shader's builds (`build.rs`): with or without the normal and ID outputs
/// (`AUX_OUTPUTS`). The `research` feature's counting builds are the research module's.
#[derive(Clone, Copy, Debug)]
pub struct FragmentShader {
    /// The source's file name, e.g. `ellipsoid.frag`.
    pub name: &'static str,
    /// Colour only.
    pub plain: &'static [u8],
    /// Colour, normal and ID.
    pub aux: &'static [u8],
}

impl FragmentShader {
    /// The build with (`aux`) or without the normal and ID outputs.
    pub fn pick(&self, aux: bool) -> &'static [u8] {
        if aux {
            self.aux
        } else {
            self.plain
        }
    }
}

/// The SPIR-V `build.rs` made of one build, by its file name.
macro_rules! spirv {
    ($file:literal) => {
        include_bytes!(concat!(env!("OUT_DIR"), "/", $file))
    };
}
// The research module's shaders use the two macros too.
#[allow(unused_imports)]
pub(crate) use spirv;

/// A fragment shader's two builds, by its source's file name.
macro_rules! fragment_shader {
    ($name:literal) => {
        $crate::gpu::shaders::FragmentShader {
            name: $name,
            plain: include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".spv")),
            aux: include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".aux.spv")),
        }
    };
}
#[allow(unused_imports)]
pub(crate) use fragment_shader;

/// The ellipsoid impostor vertex shader.
pub const ELLIPSOID_VERT: &[u8] = spirv!("ellipsoid.vert.spv");
/// The ellipsoid impostor fragment shader.
pub const ELLIPSOID_FRAG: FragmentShader = fragment_shader!("ellipsoid.frag");
/// `ELLIPSOID_VERT` reading the set-up the pre-pass computed once (`SETUP_ONCE`).
pub const ELLIPSOID_SETUP_ONCE_VERT: &[u8] = spirv!("ellipsoid_setup_once.vert.spv");
/// `ELLIPSOID_FRAG` reading the set-up the pre-pass computed once (`SETUP_ONCE`).
pub const ELLIPSOID_SETUP_ONCE_FRAG: FragmentShader = fragment_shader!("ellipsoid_setup_once.frag");
/// The compute splat: each kept glyph's pixel centres into the visibility buffer.
pub const SPLAT_COMP: &[u8] = spirv!("splat.comp.spv");
/// The compute splat's resolve: a square per resolve tile a splatted glyph touched.
pub const RESOLVE_VERT: &[u8] = spirv!("resolve.vert.spv");
/// The compute splat's resolve: shades each pixel's nearest hit once.
pub const RESOLVE_FRAG: FragmentShader = fragment_shader!("resolve.frag");
/// The culling pre-pass compute shader.
pub const CULL_COMP: &[u8] = spirv!("cull.comp.spv");

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
pub(crate) fn mirror_depth_layout(words: &mut [u32]) -> usize {
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

    /// (The research module checks its counting builds the same way.)
    #[test]
    fn every_depth_writing_fragment_shader_declares_depth_less_once() {
        let builds = |f: FragmentShader| [f.plain, f.aux];
        for spirv in builds(ELLIPSOID_FRAG)
            .into_iter()
            .chain(builds(ELLIPSOID_SETUP_ONCE_FRAG))
        {
            let mut words = ash::util::read_spv(&mut std::io::Cursor::new(spirv)).unwrap();
            assert_eq!(mirror_depth_layout(&mut words), 1);
            assert_eq!(mirror_depth_layout(&mut words), 0, "now DepthGreater");
        }
    }
}
