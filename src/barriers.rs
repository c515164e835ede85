//! Every pipeline barrier the renderer records, as data: the module documentation of
//! `src/renderer/mod.rs` says where each goes, and `tests/barriers.rs` checks each covers the hazards
//! it is there for (synchronization validation misses some, e.g. across submissions).
//!
//! All are global memory barriers: the renderer's buffers are its own and every hazard is
//! between its own commands, so naming buffers would add nothing but recording cost.
//!
//! | barrier | source stages / access | destination stages / access | where |
//! |---|---|---|---|
//! | `INSTANCES_BEFORE_COPY` | vertex, fragment, compute, transfer / transfer write | transfer / transfer write | before an upload's copy |
//! | `INSTANCES_AFTER_COPY` | transfer / transfer write | vertex, fragment, compute / shader read | after the copy |
//! | `PREPASS_AFTER_PREVIOUS_FRAME` | draw indirect, vertex, fragment, compute / shader write | transfer, compute / transfer write, shader read and write | start of each chunk's pre-pass |
//! | `PREPASS_CLEARED` | transfer / transfer write | compute / shader read and write | after the indirect reset and the tile, visibility, keep-bit and stamp clears |
//! | `PREPASS_STEP` | compute / shader write | compute / shader read and write | between culling dispatches |
//! | `PREPASS_STEP_TO_DISPATCH` | compute / shader write | draw indirect, compute / indirect-command read, shader read and write | before a visible-first splat pass, whose size and list the steps before it wrote (design §5.7) |
//! | `PREPASS_TO_DRAW` | compute / shader write | draw indirect, vertex, fragment / indirect-command read, shader read | end of each chunk's pre-pass |
//! | `COUNTER_TO_HOST` | fragment, compute / shader write | host / host read | after a counting frame's pass (`research`: `record_counter_barrier`) |
//! | `VISIBILITY_CLEARED_TO_DRAW` | transfer / transfer write | fragment / shader read and write | `research` only: after the visibility clear of `impostor-visbuffer`, before its pass |
//! | `VISIBILITY_DRAW_TO_RESOLVE` | fragment / shader write | vertex, fragment / shader read | `research` only: after `impostor-visbuffer`'s pass, before the host's |

use ash::vk;

/// One `vkCmdPipelineBarrier` with a single global memory barrier.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Barrier {
    /// What it orders, in words.
    pub purpose: &'static str,
    /// Stages whose earlier work must finish first.
    pub src_stages: vk::PipelineStageFlags,
    /// Writes of those stages made available.
    pub src_access: vk::AccessFlags,
    /// Stages of later work that wait.
    pub dst_stages: vk::PipelineStageFlags,
    /// Accesses of those stages the writes are made visible to.
    pub dst_access: vk::AccessFlags,
}

impl Barrier {
    /// Records the barrier.
    ///
    /// # Safety
    /// `cmd` is a command buffer of `device` in the recording state, outside any pass.
    pub(crate) unsafe fn record(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let memory = [vk::MemoryBarrier::default()
            .src_access_mask(self.src_access)
            .dst_access_mask(self.dst_access)];
        // SAFETY: caller contract; a global memory barrier references no object.
        unsafe {
            device.cmd_pipeline_barrier(
                cmd,
                self.src_stages,
                self.dst_stages,
                vk::DependencyFlags::empty(),
                &memory,
                &[],
                &[],
            )
        };
    }
}

const fn stages(flags: &[vk::PipelineStageFlags]) -> vk::PipelineStageFlags {
    let mut raw = 0;
    let mut k = 0;
    while k < flags.len() {
        raw |= flags[k].as_raw();
        k += 1;
    }
    vk::PipelineStageFlags::from_raw(raw)
}

const fn access(flags: &[vk::AccessFlags]) -> vk::AccessFlags {
    let mut raw = 0;
    let mut k = 0;
    while k < flags.len() {
        raw |= flags[k].as_raw();
        k += 1;
    }
    vk::AccessFlags::from_raw(raw)
}

/// Before an upload's copy: earlier shader reads of the instance buffer (draws and pre-passes
/// already recorded) and earlier copies into it finish first.
pub const INSTANCES_BEFORE_COPY: Barrier = Barrier {
    purpose: "earlier vertex/fragment/compute reads and copies of the instances -> this copy",
    src_stages: stages(&[
        vk::PipelineStageFlags::VERTEX_SHADER,
        vk::PipelineStageFlags::FRAGMENT_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::TRANSFER,
    ]),
    src_access: vk::AccessFlags::TRANSFER_WRITE,
    dst_stages: vk::PipelineStageFlags::TRANSFER,
    dst_access: vk::AccessFlags::TRANSFER_WRITE,
};

/// After an upload's copy: the pre-pass and the draw read what it wrote.
pub const INSTANCES_AFTER_COPY: Barrier = Barrier {
    purpose: "copy into the instances -> pre-pass, vertex and resolve reads",
    src_stages: vk::PipelineStageFlags::TRANSFER,
    src_access: vk::AccessFlags::TRANSFER_WRITE,
    dst_stages: stages(&[
        vk::PipelineStageFlags::VERTEX_SHADER,
        vk::PipelineStageFlags::FRAGMENT_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
    ]),
    dst_access: vk::AccessFlags::SHADER_READ,
};

/// At the start of a pre-pass: the previous frame's draw (indirect command, kept indices,
/// set-up records) and pre-pass are done with the buffers this one rewrites.
pub const PREPASS_AFTER_PREVIOUS_FRAME: Barrier = Barrier {
    purpose: "previous draw's reads and pre-pass writes -> this pre-pass's clears and writes",
    src_stages: stages(&[
        vk::PipelineStageFlags::DRAW_INDIRECT,
        vk::PipelineStageFlags::VERTEX_SHADER,
        vk::PipelineStageFlags::FRAGMENT_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
    ]),
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: stages(&[
        vk::PipelineStageFlags::TRANSFER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
    ]),
    dst_access: access(&[
        vk::AccessFlags::TRANSFER_WRITE,
        vk::AccessFlags::SHADER_READ,
        vk::AccessFlags::SHADER_WRITE,
    ]),
};

/// After the pre-pass resets the indirect command and clears the occlusion tiles.
pub const PREPASS_CLEARED: Barrier = Barrier {
    purpose: "indirect-command reset and the tile, visibility, keep-bit and stamp clears -> the \
              dispatches",
    src_stages: vk::PipelineStageFlags::TRANSFER,
    src_access: vk::AccessFlags::TRANSFER_WRITE,
    dst_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    dst_access: access(&[vk::AccessFlags::SHADER_READ, vk::AccessFlags::SHADER_WRITE]),
};

/// Between two culling dispatches.
pub const PREPASS_STEP: Barrier = Barrier {
    purpose: "one step's writes (the compute splat's included) -> the next step",
    src_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    dst_access: access(&[vk::AccessFlags::SHADER_READ, vk::AccessFlags::SHADER_WRITE]),
};

/// Before a dispatch whose size the previous step wrote (the visible-first splat's passes over
/// the pre-pass's list).
pub const PREPASS_STEP_TO_DISPATCH: Barrier = Barrier {
    purpose: "one step's writes (the list and its dispatch size) -> the indirect dispatch",
    src_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: stages(&[
        vk::PipelineStageFlags::DRAW_INDIRECT,
        vk::PipelineStageFlags::COMPUTE_SHADER,
    ]),
    dst_access: access(&[
        vk::AccessFlags::INDIRECT_COMMAND_READ,
        vk::AccessFlags::SHADER_READ,
        vk::AccessFlags::SHADER_WRITE,
    ]),
};

/// After the pre-pass: the draw reads the indirect command, kept indices and set-up records.
pub const PREPASS_TO_DRAW: Barrier = Barrier {
    purpose: "pre-pass writes -> indirect draw, vertex and fragment reads",
    src_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: stages(&[
        vk::PipelineStageFlags::DRAW_INDIRECT,
        vk::PipelineStageFlags::VERTEX_SHADER,
        vk::PipelineStageFlags::FRAGMENT_SHADER,
    ]),
    dst_access: access(&[
        vk::AccessFlags::INDIRECT_COMMAND_READ,
        vk::AccessFlags::SHADER_READ,
    ]),
};

/// After a read-back frame's pass with the `research` feature: the host reads the fragment
/// and ray-cast counters (`bench`).
pub const COUNTER_TO_HOST: Barrier = Barrier {
    purpose: "fragment and compute counter atomics -> host read",
    src_stages: stages(&[
        vk::PipelineStageFlags::FRAGMENT_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
    ]),
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: vk::PipelineStageFlags::HOST,
    dst_access: vk::AccessFlags::HOST_READ,
};

/// `impostor-visbuffer` (feature `research`): the visibility buffer's clear -> the
/// visibility-buffer draw's atomics.
pub const VISIBILITY_CLEARED_TO_DRAW: Barrier = Barrier {
    purpose: "visibility-buffer clear -> the visibility-buffer draw's fragment atomics",
    src_stages: vk::PipelineStageFlags::TRANSFER,
    src_access: vk::AccessFlags::TRANSFER_WRITE,
    dst_stages: vk::PipelineStageFlags::FRAGMENT_SHADER,
    dst_access: access(&[vk::AccessFlags::SHADER_READ, vk::AccessFlags::SHADER_WRITE]),
};

/// `impostor-visbuffer` (feature `research`): the visibility-buffer draw's atomics -> the
/// resolve's tile reads (vertex stage) and key reads (fragment stage) in the host's pass.
pub const VISIBILITY_DRAW_TO_RESOLVE: Barrier = Barrier {
    purpose: "visibility-buffer draw's fragment atomics -> the resolve's vertex and fragment reads",
    src_stages: vk::PipelineStageFlags::FRAGMENT_SHADER,
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: stages(&[
        vk::PipelineStageFlags::VERTEX_SHADER,
        vk::PipelineStageFlags::FRAGMENT_SHADER,
    ]),
    dst_access: vk::AccessFlags::SHADER_READ,
};

/// The traced path (feature `research`), before its boxes and hierarchy are rebuilt: the
/// previous frame's traversal and build are done with them.
pub const TRACED_BEFORE_BUILD: Barrier = Barrier {
    purpose: "previous traversal's and build's reads and writes -> this frame's box count, boxes \
              and build",
    src_stages: stages(&[
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    ]),
    src_access: access(&[
        vk::AccessFlags::SHADER_WRITE,
        vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
    ]),
    dst_stages: stages(&[
        vk::PipelineStageFlags::TRANSFER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    ]),
    dst_access: access(&[
        vk::AccessFlags::TRANSFER_WRITE,
        vk::AccessFlags::SHADER_READ,
        vk::AccessFlags::SHADER_WRITE,
        vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
        vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
    ]),
};

/// The traced path (feature `research`): the boxes written -> the bottom level's build reads
/// them.
pub const TRACED_BOXES_TO_BUILD: Barrier = Barrier {
    purpose: "box writes -> the bottom level's build",
    src_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    src_access: vk::AccessFlags::SHADER_WRITE,
    dst_stages: vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    dst_access: access(&[
        vk::AccessFlags::SHADER_READ,
        vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
    ]),
};

/// The traced path (feature `research`): the bottom level built -> the top level's build
/// reads it (and reuses the scratch).
pub const TRACED_BOTTOM_TO_TOP: Barrier = Barrier {
    purpose: "bottom-level build -> top-level build (reads it, reuses the scratch)",
    src_stages: vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    src_access: vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
    dst_stages: vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    dst_access: access(&[
        vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
        vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
    ]),
};

/// The traced path (feature `research`): the hierarchy built -> the traversal's ray queries.
pub const TRACED_BUILT_TO_TRACE: Barrier = Barrier {
    purpose: "hierarchy build -> the traversal's ray queries",
    src_stages: vk::PipelineStageFlags::ACCELERATION_STRUCTURE_BUILD_KHR,
    src_access: vk::AccessFlags::ACCELERATION_STRUCTURE_WRITE_KHR,
    dst_stages: vk::PipelineStageFlags::COMPUTE_SHADER,
    dst_access: access(&[
        vk::AccessFlags::ACCELERATION_STRUCTURE_READ_KHR,
        vk::AccessFlags::SHADER_READ,
    ]),
};

/// Every barrier above that a host's frames may record (the two `research` ones are in
/// `RESEARCH`, with that feature).
pub const ALL: [Barrier; 8] = [
    INSTANCES_BEFORE_COPY,
    INSTANCES_AFTER_COPY,
    PREPASS_AFTER_PREVIOUS_FRAME,
    PREPASS_CLEARED,
    PREPASS_STEP,
    PREPASS_STEP_TO_DISPATCH,
    PREPASS_TO_DRAW,
    COUNTER_TO_HOST,
];

/// The `research` barriers of `impostor-visbuffer`.
pub const RESEARCH: [Barrier; 2] = [VISIBILITY_CLEARED_TO_DRAW, VISIBILITY_DRAW_TO_RESOLVE];

/// The traced path's barriers (feature `research`, `impostor-traced`).
pub const TRACED: [Barrier; 4] = [
    TRACED_BEFORE_BUILD,
    TRACED_BOXES_TO_BUILD,
    TRACED_BOTTOM_TO_TOP,
    TRACED_BUILT_TO_TRACE,
];
