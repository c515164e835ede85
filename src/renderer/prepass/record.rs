//! One chunk's pre-pass, ready to record: its clears, then its dispatches in order, with the
//! barriers between them.

use ash::vk;

use crate::barriers;
use crate::gpu_layout::{IndirectDraw, PushConstants};

use super::steps::{dispatch_grid, group_count, word_groups, SPLAT_GROUP_SIZE};

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
    /// One invocation per keep word of the chunk (`steps::word_groups`).
    Words,
    /// One invocation per instance of the chunk, in the splat's groups of 64.
    Splat,
    /// These workgroups (x, y).
    Grid(u32, u32),
    /// The size the previous step wrote into the chunk's command (`IndirectDraw::dispatch_x`
    /// and on): a splat pass over the pre-pass's list.
    Indirect,
}

/// The traced path's traversal (research, `impostor-traced`): its pipeline and the layout and
/// set 1 (the hierarchy) it is bound with; set 0 is the pre-pass's.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TracedDispatch {
    pub layout: vk::PipelineLayout,
    pub set: vk::DescriptorSet,
    pub pipeline: vk::Pipeline,
    /// The traversal's workgroups are squares of this many pixels a side.
    pub group_edge: u32,
}

/// The workgroups of a dispatch with one invocation per glyph of `count`, in the splat's
/// groups of 64.
pub(crate) fn splat_grid(count: u32) -> (u32, u32) {
    dispatch_grid(count.div_ceil(SPLAT_GROUP_SIZE))
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
    /// Frames with occlusion culling or the visible-first splat: reset the tiles first, every
    /// word to this one (the culling's +inf bits: no surface known yet; the visible-first
    /// splat's empty key word: hides nothing, so KEY_TILES writes only the tiles a glyph may
    /// have covered).
    pub clear_tiles: Option<u32>,
    pub buffers: PrepassBuffers,
    /// Buffer ranges filled before the dispatches (buffer, offset, bytes, word): the compute
    /// splat's visibility buffer (first chunk) and keep bits, and the glyph stamps of a new
    /// scene.
    pub fills: Vec<(vk::Buffer, u64, u64, u32)>,
    /// Set 1 of the traced path's traversal, bound with its layout (research).
    pub traced_set: Option<(vk::PipelineLayout, vk::DescriptorSet)>,
    pub dispatches: Vec<Dispatch>,
}

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
            if let Some(word) = self.clear_tiles {
                device.cmd_fill_buffer(cmd, b.tiles, 0, vk::WHOLE_SIZE, word);
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
            if let Some((layout, set)) = self.traced_set {
                // Set 0's layout and the push constants' range are the pre-pass's, so the
                // sets bound with either layout stay bound for the other's pipelines.
                device.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::COMPUTE,
                    layout,
                    1,
                    &[set],
                    &[],
                );
            }
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
                    DispatchSize::Words => dispatch_grid(word_groups(total)),
                    DispatchSize::Splat => splat_grid(total),
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
