//! The fixed-function state that differs between what a pipeline draws: the shipped
//! impostor's strip of screen polygons, or a research baseline's meshes and boxes.

use ash::vk;

/// What a graphics pipeline rasterizes and how it tests depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Raster {
    /// Vertices come from a buffer of unit-sphere positions (binding 0, location 0).
    pub mesh_vertices: bool,
    pub topology: vk::PrimitiveTopology,
    pub cull_mode: vk::CullModeFlags,
    /// Depth test and write (off for fill-rate and visibility-buffer baselines).
    pub depth: bool,
}

impl Raster {
    /// The impostor: a triangle strip per instance, built from indices, both faces, depth
    /// tested and written.
    pub const IMPOSTOR: Raster = Raster {
        mesh_vertices: false,
        topology: vk::PrimitiveTopology::TRIANGLE_STRIP,
        cull_mode: vk::CullModeFlags::NONE,
        depth: true,
    };
}
