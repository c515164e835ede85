//! The culling pre-pass: which exact culling it does, how its buffers are sized, and the
//! dispatches and barriers it records (the shader is `glsl/cull.comp`).

use ash::vk;

use crate::barriers;
use crate::gpu_layout::{IndirectDraw, PushConstants};

/// Which exact culling the pre-pass does before the draw (none: the pre-pass runs only to set
/// up glyphs once, if it does that). Nothing culled
/// can change a pixel: see `glsl/cull.comp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
}

/// Instances per workgroup (`local_size_x`).
const GROUP_SIZE: u64 = 256;
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

/// Bytes of the occlusion tiles of a `width` x `height` image.
pub(crate) fn tiles_bytes(width: u32, height: u32) -> u64 {
    4 * (width as u64).div_ceil(TILE) * (height as u64).div_ceil(TILE)
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

/// The compute splat's dispatch at the start of a pre-pass (`glsl/splat.comp`).
pub(crate) struct SplatStep {
    pub pipeline: vk::Pipeline,
    /// The dispatch grid over the chunk's instances, 64 per workgroup.
    pub groups: (u32, u32),
    /// Clear the visibility buffer first (the first chunk): its first bytes, to this word.
    pub clear: Option<(vk::Buffer, u64, u32)>,
    /// The chunk's keep bits and counts (buffer, offset, bytes), zeroed before the splat
    /// sets those of the glyphs it leaves to the draw.
    pub keep: (vk::Buffer, u64, u64),
}

/// One frame's pre-pass, ready to record.
pub(crate) struct Prepass {
    pub layout: vk::PipelineLayout,
    pub descriptor_set: vk::DescriptorSet,
    /// The push constants.
    pub push: PushConstants,
    /// The indirect command the steps start from.
    pub command: IndirectDraw,
    /// Where in the indirect buffer this chunk's command lies.
    pub indirect_offset: u64,
    pub steps: Vec<(CullStep, vk::Pipeline)>,
    /// The dispatch grid of the per-group steps.
    pub groups: (u32, u32),
    /// Occlusion runs: reset the tiles first.
    pub clear_tiles: bool,
    pub buffers: PrepassBuffers,
    /// The compute splat, before the steps.
    pub splat: Option<SplatStep>,
}

/// Instances per workgroup of the compute splat (`local_size_x` of `splat.comp`).
pub(crate) const SPLAT_GROUP_SIZE: u32 = 64;

impl Prepass {
    /// Records the pre-pass with its barriers: after the previous frame's draw (its reads)
    /// and pre-pass (its writes); the indirect command written with `vkCmdUpdateBuffer` and
    /// the tiles cleared with `vkCmdFillBuffer`; each step after a compute-to-compute
    /// barrier; and before this frame's indirect, vertex and fragment reads.
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
            if let Some(splat) = &self.splat {
                if let Some((visibility, bytes, word)) = splat.clear {
                    // Nothing hit yet: every 64-bit key of the image holds the empty value.
                    device.cmd_fill_buffer(cmd, visibility, 0, bytes, word);
                }
                let (groups, offset, bytes) = splat.keep;
                device.cmd_fill_buffer(cmd, groups, offset, bytes, 0);
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
            if let Some(splat) = &self.splat {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, splat.pipeline);
                device.cmd_dispatch(cmd, splat.groups.0, splat.groups.1, 1);
            }
            for (k, &(step, pipeline)) in self.steps.iter().enumerate() {
                if k > 0 || self.splat.is_some() {
                    barriers::PREPASS_STEP.record(device, cmd);
                }
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
                match step {
                    CullStep::Scan => device.cmd_dispatch(cmd, 1, 1, 1),
                    _ => device.cmd_dispatch(cmd, self.groups.0, self.groups.1, 1),
                }
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
