//! The baselines' SPIR-V and the counting builds of every fragment shader
//! (`COUNT_FRAGMENTS`), compiled by `build.rs` only with the `research` feature.

use crate::error::{Error, Result};
use crate::gpu::shaders::{fragment_shader, spirv, FragmentShader};

/// The `impostor-flat-depth` fragment shader (no depth write).
pub const ELLIPSOID_FLAT_DEPTH_FRAG: FragmentShader = fragment_shader!("ellipsoid_flat_depth.frag");
/// The `flat-fill` fragment shader.
pub const FLAT_FILL_FRAG: FragmentShader = fragment_shader!("flat_fill.frag");
/// `impostor-visbuffer`'s fragment stage: the nearest hit per pixel into the visibility
/// buffer, nothing shaded.
pub const ELLIPSOID_VISIBILITY_FRAG: FragmentShader = fragment_shader!("ellipsoid_visibility.frag");
/// Icosphere vertex shader (`mesh-L*`).
pub const MESH_VERT: &[u8] = spirv!("mesh.vert.spv");
/// Icosphere fragment shader (`mesh-L*`).
pub const MESH_FRAG: FragmentShader = fragment_shader!("mesh.frag");
/// The benchmark's tiled splat (`impostor-tiled`), its binning steps: per screen tile, the
/// glyphs whose box touches it.
pub const TILED_BINS_COMP: &[u8] = spirv!("tiled_bins.comp.spv");
/// The benchmark's tiled splat, its tile pass: each screen tile's glyphs walked by one
/// workgroup, its keys written once.
pub const TILED_SPLAT_COMP: &[u8] = spirv!("tiled_splat.comp.spv");
/// Oriented-box proxy vertex shader (`box-proxy`).
pub const BOX_VERT: &[u8] = spirv!("box.vert.spv");

/// A fragment shader's counting builds (colour only, and with normal and ID), by its name.
macro_rules! counted {
    ($name:literal) => {
        (
            $name,
            include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".counted.spv")).as_slice(),
            include_bytes!(concat!(env!("OUT_DIR"), "/", $name, ".aux.counted.spv")).as_slice(),
        )
    };
}

/// Every fragment shader's counting builds.
const COUNTED: [(&str, &[u8], &[u8]); 7] = [
    counted!("ellipsoid.frag"),
    counted!("ellipsoid_setup_once.frag"),
    counted!("resolve.frag"),
    counted!("ellipsoid_flat_depth.frag"),
    counted!("flat_fill.frag"),
    counted!("ellipsoid_visibility.frag"),
    counted!("mesh.frag"),
];

/// `shader`'s build that counts shaded pixels (`COUNT_FRAGMENTS`), with or without the normal
/// and ID outputs.
pub(crate) fn counted(shader: &FragmentShader, aux: bool) -> Result<&'static [u8]> {
    let (_, plain, with_aux) = COUNTED
        .iter()
        .find(|(name, _, _)| *name == shader.name)
        .ok_or_else(|| {
            Error::invalid(
                "fragment shader",
                format!("{} has no counting build", shader.name),
            )
        })?;
    Ok(if aux { with_aux } else { plain })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::shaders::{mirror_depth_layout, ELLIPSOID_FRAG, ELLIPSOID_SETUP_ONCE_FRAG};

    #[test]
    fn counting_builds_declare_depth_less_once() {
        for shader in [ELLIPSOID_FRAG, ELLIPSOID_SETUP_ONCE_FRAG] {
            for aux in [false, true] {
                let spirv = counted(&shader, aux).unwrap();
                let mut words = ash::util::read_spv(&mut std::io::Cursor::new(spirv)).unwrap();
                assert_eq!(mirror_depth_layout(&mut words), 1, "{}", shader.name);
            }
        }
    }
}
