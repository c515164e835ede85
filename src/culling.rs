//! The culling pre-pass: which exact culling it does, how its buffers are sized, and the
//! dispatches and barriers it records (the shader is `glsl/cull.comp`).

use ash::vk;

use crate::barriers;
use crate::gpu_layout::{IndirectDraw, PushConstants};

/// Which exact culling the pre-pass does before the draw (none: the pre-pass runs only to set
/// up glyphs once, if it does that). Nothing culled
/// can change a pixel: see `glsl/cull.comp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct Culling {
    /// Drop instances whose silhouette lies off screen or before the near plane.
    pub frustum: bool,
    /// Drop instances whose silhouette's bounding rectangle holds no pixel centre (on
    /// multisampled targets: no sample).
    pub pixel_centres: bool,
    /// Drop instances whose every pixel centre (multisampled: every sample) is covered by an
    /// ellipsoid lying wholly nearer (each ellipsoid vouches for the pixels of its inscribed
    /// sphere).
    pub occlusion: bool,
}

impl Culling {
    /// No culling.
    pub const OFF: Culling = Culling {
        frustum: false,
        pixel_centres: false,
        occlusion: false,
    };
    /// Every kind.
    pub const ON: Culling = Culling {
        frustum: true,
        pixel_centres: true,
        occlusion: true,
    };

    /// Whether anything is culled.
    pub fn any(self) -> bool {
        self.frustum || self.pixel_centres || self.occlusion
    }
}

impl Default for Culling {
    /// Every kind: each is exact, and each costs little where it finds nothing to drop
    /// (README, "Skipping what a scene doesn't need").
    fn default() -> Self {
        Self::ON
    }
}

/// One dispatch of the pre-pass (`CULL_STEP` in the shader).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum CullStep {
    /// Lower the occlusion tiles each ellipsoid's inscribed sphere covers.
    Occluders = 0,
    /// Keep bits and a count per group of instances.
    Classify = 1,
    /// Counts to first output slots, and the draw's instance count.
    Scan = 2,
    /// Kept instance indices to their slots.
    Scatter = 3,
    /// The visible-first splat: each occlusion tile takes the farthest depth the first
    /// pass left over its pixels.
    KeyTiles = 4,
    /// The visible-first splat: the glyphs the finished frame shows are stamped.
    MarkShown = 5,
}

/// Which glyphs the CLASSIFY step lists (`CULL_SELECT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub(crate) enum CullSelect {
    /// Every glyph the culling keeps.
    #[default]
    All = 0,
    /// The glyphs the last stamping frame showed (a still camera's): the visible-first
    /// splat's first pass.
    Shown = 1,
    /// The others the culling keeps, where the first pass's hits do not hide them: its
    /// second pass.
    Rest = 2,
    /// Those a splat pass of this frame left to the draw.
    Drawn = 3,
}

/// Instances per workgroup (`local_size_x` of `cull.comp`).
pub(crate) const GROUP_SIZE: u64 = 256;
/// Occlusion tile edge in pixels (`TILE`).
const TILE: u64 = 4;
/// Most workgroups in one dimension of a dispatch that every device supports.
const MAX_GROUPS_X: u32 = 65_535;

/// Workgroups over `count` instances.
pub(crate) fn group_count(count: u32) -> u32 {
    (count as u64).div_ceil(GROUP_SIZE) as u32
}

/// Bytes of the groups buffer: 8 words of keep bits and one count per group.
pub(crate) fn groups_bytes(count: u32) -> u64 {
    4 * 9 * group_count(count).max(1) as u64
}

/// Occlusion tiles of a `width` x `height` image.
pub(crate) fn tiles_count(width: u32, height: u32) -> u32 {
    (width as u64).div_ceil(TILE) as u32 * (height as u64).div_ceil(TILE) as u32
}

/// Bytes of the occlusion tiles of a `width` x `height` image.
pub(crate) fn tiles_bytes(width: u32, height: u32) -> u64 {
    4 * tiles_count(width, height) as u64
}

/// The dispatch grid for `groups` workgroups: x up to the guaranteed limit, then rows.
pub(crate) fn dispatch_grid(groups: u32) -> (u32, u32) {
    let x = groups.clamp(1, MAX_GROUPS_X);
    (x, groups.div_ceil(x).max(1))
}

/// The steps after the compute splat: it writes the keep bits and counts of the glyphs it
/// leaves to the draw, and these compact them in instance order.
pub(crate) const SPLAT_STEPS: [CullStep; 2] = [CullStep::Scan, CullStep::Scatter];

/// The steps a culling frame runs, in order.
pub(crate) fn steps(culling: Culling) -> Vec<CullStep> {
    let mut steps = Vec::with_capacity(4);
    if culling.occlusion {
        steps.push(CullStep::Occluders);
    }
    steps.extend([CullStep::Classify, CullStep::Scan, CullStep::Scatter]);
    steps
}

/// The buffers the pre-pass fills with transfer commands (the rest it writes through the
/// descriptor set).
pub(crate) struct PrepassBuffers {
    pub indirect: vk::Buffer,
    pub tiles: vk::Buffer,
}

/// How big one dispatch of the pre-pass is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DispatchSize {
    /// One invocation per instance of the chunk, in the culling's groups of 256.
    Groups,
    /// One invocation per instance of the chunk, in the splat's groups of 64.
    Splat,
    /// These workgroups (x, y).
    Grid(u32, u32),
    /// The size the previous step wrote into the chunk's command (`IndirectDraw::dispatch_x`
    /// and on): a splat pass over the pre-pass's list.
    Indirect,
}

/// One dispatch of the pre-pass.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dispatch {
    pub pipeline: vk::Pipeline,
    pub size: DispatchSize,
}

/// One frame's pre-pass, ready to record: its clears, then its dispatches in order.
pub(crate) struct Prepass {
    pub layout: vk::PipelineLayout,
    pub descriptor_set: vk::DescriptorSet,
    /// The push constants.
    pub push: PushConstants,
    /// The indirect command the steps start from.
    pub command: IndirectDraw,
    /// Where in the indirect buffer this chunk's command lies.
    pub indirect_offset: u64,
    /// Occlusion runs: reset the tiles first.
    pub clear_tiles: bool,
    pub buffers: PrepassBuffers,
    /// Buffer ranges filled before the dispatches (buffer, offset, bytes, word): the compute
    /// splat's visibility buffer (first chunk) and keep bits, and the glyph stamps of a new
    /// scene.
    pub fills: Vec<(vk::Buffer, u64, u64, u32)>,
    pub dispatches: Vec<Dispatch>,
}

/// Instances per workgroup of the compute splat (`local_size_x` of `splat.comp`).
pub(crate) const SPLAT_GROUP_SIZE: u32 = 64;

/// Byte offset of the dispatch command in a chunk's `IndirectDraw`.
const DISPATCH_OFFSET: u64 = std::mem::offset_of!(IndirectDraw, dispatch_x) as u64;

impl Prepass {
    /// Records the pre-pass with its barriers: after the previous frame's draw (its reads)
    /// and pre-pass (its writes); the indirect command written with `vkCmdUpdateBuffer`, the
    /// tiles and the splat's buffers cleared with `vkCmdFillBuffer`; each dispatch after a
    /// compute-to-compute barrier (one that also covers the indirect read before a dispatch
    /// sized by the previous step); and before this frame's indirect, vertex and fragment
    /// reads.
    ///
    /// # Safety
    /// `cmd` must be recording outside a render pass, and every handle must stay alive until
    /// the submission completes.
    pub unsafe fn record(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let b = &self.buffers;
        // SAFETY: the caller guarantees the command buffer's state and the handles' lifetime;
        // every region lies within the buffers.
        unsafe {
            barriers::PREPASS_AFTER_PREVIOUS_FRAME.record(device, cmd);
            device.cmd_update_buffer(
                cmd,
                b.indirect,
                self.indirect_offset,
                bytemuck::bytes_of(&self.command),
            );
            if self.clear_tiles {
                // +inf: no surface known in front of any tile yet.
                device.cmd_fill_buffer(cmd, b.tiles, 0, vk::WHOLE_SIZE, f32::INFINITY.to_bits());
            }
            for &(buffer, offset, bytes, word) in &self.fills {
                device.cmd_fill_buffer(cmd, buffer, offset, bytes, word);
            }
            barriers::PREPASS_CLEARED.record(device, cmd);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout,
                0,
                &[self.descriptor_set],
                &[],
            );
            device.cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck::bytes_of(&self.push),
            );
            let total = self.command.total;
            for (k, dispatch) in self.dispatches.iter().enumerate() {
                if dispatch.size == DispatchSize::Indirect {
                    barriers::PREPASS_STEP_TO_DISPATCH.record(device, cmd);
                } else if k > 0 {
                    barriers::PREPASS_STEP.record(device, cmd);
                }
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, dispatch.pipeline);
                let (x, y) = match dispatch.size {
                    DispatchSize::Groups => dispatch_grid(group_count(total)),
                    DispatchSize::Splat => dispatch_grid(total.div_ceil(SPLAT_GROUP_SIZE)),
                    DispatchSize::Grid(x, y) => (x, y),
                    DispatchSize::Indirect => {
                        let offset = self.indirect_offset + DISPATCH_OFFSET;
                        device.cmd_dispatch_indirect(cmd, b.indirect, offset);
                        continue;
                    }
                };
                device.cmd_dispatch(cmd, x, y, 1);
            }
            barriers::PREPASS_TO_DRAW.record(device, cmd);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_cover_every_instance_and_pixel() {
        assert_eq!(group_count(0), 0);
        assert_eq!(group_count(256), 1);
        assert_eq!(group_count(257), 2);
        assert_eq!(groups_bytes(0), 36);
        assert_eq!(groups_bytes(1_000_000), 4 * 9 * 3907);
        assert_eq!(tiles_bytes(1920, 1080), 4 * 480 * 270);
        assert_eq!(tiles_bytes(161, 121), 4 * 41 * 31);
    }

    #[test]
    fn dispatch_grid_covers_all_groups() {
        assert_eq!(dispatch_grid(0), (1, 1));
        assert_eq!(dispatch_grid(3907), (3907, 1));
        let (x, y) = dispatch_grid(200_000);
        assert!(x <= MAX_GROUPS_X && x as u64 * y as u64 >= 200_000);
    }
}
