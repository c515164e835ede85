//! The barriers the renderer records, checked against the hazards they exist for.
//!
//! Synchronization validation sees only what one submission does in the order it records, and
//! lavapipe runs commands in order anyway, so a missing stage or access bit would pass every
//! image test. Here each hazard -- who writes or reads what, in which stage, and which barrier
//! sits between them (see the module documentation of `src/renderer/mod.rs`) -- is written out from the
//! shaders and commands, and the barrier must cover it. `tests/embedding.rs` then runs two
//! frames in one command buffer under synchronization validation.

use ash::vk::{AccessFlags as A, PipelineStageFlags as S};
use ellipsoid_splat::internals::barriers::{self, Barrier};

/// An access by a command or shader stage.
#[derive(Clone, Copy, Debug)]
struct Access {
    stage: S,
    access: A,
}

const fn at(stage: S, access: A) -> Access {
    Access { stage, access }
}

/// Whether `barrier` orders `first` before `then` and, if `first` writes, makes the write
/// available to and visible for `then`'s access.
fn covers(barrier: &Barrier, first: Access, then: Access) -> bool {
    let writes = A::TRANSFER_WRITE | A::SHADER_WRITE | A::COLOR_ATTACHMENT_WRITE;
    let ordered =
        barrier.src_stages.contains(first.stage) && barrier.dst_stages.contains(then.stage);
    let first_writes = first.access.intersects(writes);
    let visible = !first_writes
        || (barrier.src_access.contains(first.access & writes)
            && barrier.dst_access.contains(then.access));
    ordered && visible
}

#[test]
fn every_hazard_is_covered_by_its_barrier() {
    let copy = at(S::TRANSFER, A::TRANSFER_WRITE);
    let compute_read = at(S::COMPUTE_SHADER, A::SHADER_READ);
    let compute_write = at(S::COMPUTE_SHADER, A::SHADER_WRITE);
    let compute_read_write = at(S::COMPUTE_SHADER, A::SHADER_READ | A::SHADER_WRITE);
    let vertex_read = at(S::VERTEX_SHADER, A::SHADER_READ);
    let fragment_read = at(S::FRAGMENT_SHADER, A::SHADER_READ);
    let indirect_read = at(S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ);
    // (what, first access, later access, the barrier between them)
    let hazards: [(&str, Access, Access, Barrier); 30] = [
        // An upload or update of the instances.
        (
            "copy -> pre-pass reads instances",
            copy,
            compute_read,
            barriers::INSTANCES_AFTER_COPY,
        ),
        (
            "copy -> vertex stage reads instances",
            copy,
            vertex_read,
            barriers::INSTANCES_AFTER_COPY,
        ),
        (
            "earlier draw's vertex reads -> copy",
            vertex_read,
            copy,
            barriers::INSTANCES_BEFORE_COPY,
        ),
        (
            "earlier pre-pass reads -> copy",
            compute_read,
            copy,
            barriers::INSTANCES_BEFORE_COPY,
        ),
        (
            "copy -> the compute splat's resolve reads instances",
            copy,
            fragment_read,
            barriers::INSTANCES_AFTER_COPY,
        ),
        (
            "earlier resolve's fragment reads of instances -> copy",
            fragment_read,
            copy,
            barriers::INSTANCES_BEFORE_COPY,
        ),
        (
            "earlier copy -> copy (update after upload)",
            copy,
            copy,
            barriers::INSTANCES_BEFORE_COPY,
        ),
        // The pre-pass, after the previous frame.
        (
            "previous indirect draw -> indirect reset",
            indirect_read,
            copy,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous vertex reads of kept indices -> rewrite",
            vertex_read,
            compute_write,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous fragment reads of set-up records -> rewrite",
            fragment_read,
            compute_write,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous resolve's reads of the visibility buffer -> its clear",
            fragment_read,
            copy,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous resolve's vertex reads of the tile marks -> their clear",
            vertex_read,
            copy,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous pre-pass writes -> tile clear",
            compute_write,
            copy,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        (
            "previous pre-pass writes -> this pre-pass",
            compute_write,
            compute_read_write,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
        // Inside the pre-pass.
        (
            "indirect reset and tile clear -> dispatches",
            copy,
            compute_read_write,
            barriers::PREPASS_CLEARED,
        ),
        (
            "visibility clear -> the compute splat's atomics",
            copy,
            compute_read_write,
            barriers::PREPASS_CLEARED,
        ),
        (
            "one step -> the next",
            compute_write,
            compute_read_write,
            barriers::PREPASS_STEP,
        ),
        (
            "keep-bit clear -> the compute splat's atomics",
            copy,
            compute_read_write,
            barriers::PREPASS_CLEARED,
        ),
        (
            "the compute splat's keep bits -> the compaction that follows it",
            compute_write,
            compute_read_write,
            barriers::PREPASS_STEP,
        ),
        // The visible-first splat: each pass runs over the list the steps before it wrote.
        (
            "the list's dispatch size (SCAN) -> the splat pass's indirect dispatch",
            compute_write,
            indirect_read,
            barriers::PREPASS_STEP_TO_DISPATCH,
        ),
        (
            "the list (SCATTER) -> the splat pass reads it",
            compute_write,
            compute_read_write,
            barriers::PREPASS_STEP_TO_DISPATCH,
        ),
        (
            "the first pass's atomics -> the key tiles that read them",
            compute_write,
            compute_read_write,
            barriers::PREPASS_STEP,
        ),
        (
            "stamps clear of a new scene -> the stamping step",
            copy,
            compute_read_write,
            barriers::PREPASS_CLEARED,
        ),
        // The pre-pass feeds the draw.
        (
            "culled count -> indirect draw",
            compute_write,
            indirect_read,
            barriers::PREPASS_TO_DRAW,
        ),
        (
            "kept indices and footprints -> vertex stage",
            compute_write,
            vertex_read,
            barriers::PREPASS_TO_DRAW,
        ),
        (
            "shading records -> fragment stage",
            compute_write,
            fragment_read,
            barriers::PREPASS_TO_DRAW,
        ),
        (
            "the compute splat's atomics -> its resolve",
            compute_write,
            fragment_read,
            barriers::PREPASS_TO_DRAW,
        ),
        (
            "the compute splat's tile marks -> its resolve's vertex stage",
            compute_write,
            vertex_read,
            barriers::PREPASS_TO_DRAW,
        ),
        // Bench's fragment counter, and the compute splat's ray casts beside it.
        (
            "the splat's ray-cast atomics -> host read",
            compute_write,
            at(S::HOST, A::HOST_READ),
            barriers::COUNTER_TO_HOST,
        ),
        (
            "fragment atomics -> host read",
            at(S::FRAGMENT_SHADER, A::SHADER_WRITE),
            at(S::HOST, A::HOST_READ),
            barriers::COUNTER_TO_HOST,
        ),
    ];
    for (what, first, then, barrier) in hazards {
        assert!(
            covers(&barrier, first, then),
            "{what}: {barrier:?} does not order {first:?} before {then:?}"
        );
    }
    // Every barrier the renderer records is there for at least one hazard above.
    for barrier in barriers::ALL {
        assert!(
            hazards.iter().any(|(_, _, _, b)| *b == barrier),
            "{} covers no listed hazard",
            barrier.purpose
        );
    }
}

/// The check itself can fail: dropping one bit from a barrier breaks its hazard.
#[test]
fn a_barrier_missing_a_bit_is_caught() {
    let compute_write = at(S::COMPUTE_SHADER, A::SHADER_WRITE);
    let indirect_read = at(S::DRAW_INDIRECT, A::INDIRECT_COMMAND_READ);
    let full = barriers::PREPASS_TO_DRAW;
    assert!(covers(&full, compute_write, indirect_read));
    let no_stage = Barrier {
        dst_stages: full.dst_stages & !S::DRAW_INDIRECT,
        ..full
    };
    let no_access = Barrier {
        dst_access: full.dst_access & !A::INDIRECT_COMMAND_READ,
        ..full
    };
    assert!(!covers(&no_stage, compute_write, indirect_read));
    assert!(!covers(&no_access, compute_write, indirect_read));
}

/// The benchmark's visibility-buffer draw (`impostor-visbuffer`) adds two barriers of its
/// own around its pass: its fragment atomics come after the clear and before the resolve.
#[cfg(feature = "research")]
#[test]
fn visibility_draw_hazards_are_covered() {
    let copy = at(S::TRANSFER, A::TRANSFER_WRITE);
    let fragment_atomics = at(S::FRAGMENT_SHADER, A::SHADER_READ | A::SHADER_WRITE);
    let fragment_write = at(S::FRAGMENT_SHADER, A::SHADER_WRITE);
    let hazards = [
        (
            "visibility clear -> the draw's atomics",
            copy,
            fragment_atomics,
            barriers::VISIBILITY_CLEARED_TO_DRAW,
        ),
        (
            "the draw's atomics -> the resolve's key reads",
            fragment_write,
            at(S::FRAGMENT_SHADER, A::SHADER_READ),
            barriers::VISIBILITY_DRAW_TO_RESOLVE,
        ),
        (
            "the draw's tile marks -> the resolve's vertex stage",
            fragment_write,
            at(S::VERTEX_SHADER, A::SHADER_READ),
            barriers::VISIBILITY_DRAW_TO_RESOLVE,
        ),
        (
            "previous frame's draw atomics -> this frame's clear",
            fragment_write,
            copy,
            barriers::PREPASS_AFTER_PREVIOUS_FRAME,
        ),
    ];
    for (what, first, then, barrier) in hazards {
        assert!(
            covers(&barrier, first, then),
            "{what}: {barrier:?} does not order {first:?} before {then:?}"
        );
    }
    for barrier in barriers::RESEARCH {
        assert!(
            hazards.iter().any(|(_, _, _, b)| *b == barrier),
            "{} covers no listed hazard",
            barrier.purpose
        );
    }
}

/// The traced path (`impostor-traced`) builds its boxes and hierarchy before the pre-pass:
/// each step after the one it reads, and the whole after the previous frame's traversal and
/// build (acceleration-structure writes count as writes here).
#[cfg(feature = "research")]
#[test]
fn traced_hazards_are_covered() {
    let build = S::ACCELERATION_STRUCTURE_BUILD_KHR;
    let structure_write = at(build, A::ACCELERATION_STRUCTURE_WRITE_KHR);
    let covers_all = |barrier: &Barrier, first: Access, then: Access| {
        let writes = A::TRANSFER_WRITE | A::SHADER_WRITE | A::ACCELERATION_STRUCTURE_WRITE_KHR;
        barrier.src_stages.contains(first.stage)
            && barrier.dst_stages.contains(then.stage)
            && (!first.access.intersects(writes)
                || (barrier.src_access.contains(first.access & writes)
                    && barrier.dst_access.contains(then.access)))
    };
    let hazards = [
        (
            "previous traversal's hierarchy reads -> this frame's build",
            at(S::COMPUTE_SHADER, A::ACCELERATION_STRUCTURE_READ_KHR),
            structure_write,
            barriers::TRACED_BEFORE_BUILD,
        ),
        (
            "previous build -> this frame's box writes",
            structure_write,
            at(S::COMPUTE_SHADER, A::SHADER_WRITE),
            barriers::TRACED_BEFORE_BUILD,
        ),
        (
            "previous box reads -> this frame's box count",
            at(build, A::SHADER_READ),
            at(S::TRANSFER, A::TRANSFER_WRITE),
            barriers::TRACED_BEFORE_BUILD,
        ),
        (
            "box count -> the boxes shader",
            at(S::TRANSFER, A::TRANSFER_WRITE),
            at(S::COMPUTE_SHADER, A::SHADER_READ),
            barriers::PREPASS_CLEARED,
        ),
        (
            "boxes -> the bottom level's build",
            at(S::COMPUTE_SHADER, A::SHADER_WRITE),
            at(build, A::SHADER_READ),
            barriers::TRACED_BOXES_TO_BUILD,
        ),
        (
            "bottom level -> the top level's build",
            structure_write,
            at(build, A::ACCELERATION_STRUCTURE_READ_KHR),
            barriers::TRACED_BOTTOM_TO_TOP,
        ),
        (
            "the bottom level's scratch -> the top level's",
            structure_write,
            structure_write,
            barriers::TRACED_BOTTOM_TO_TOP,
        ),
        (
            "hierarchy -> the traversal's ray queries",
            structure_write,
            at(S::COMPUTE_SHADER, A::ACCELERATION_STRUCTURE_READ_KHR),
            barriers::TRACED_BUILT_TO_TRACE,
        ),
    ];
    for (what, first, then, barrier) in hazards {
        assert!(
            covers_all(&barrier, first, then),
            "{what}: {barrier:?} does not order {first:?} before {then:?}"
        );
    }
    for barrier in barriers::TRACED {
        assert!(
            hazards.iter().any(|(_, _, _, b)| *b == barrier),
            "{} covers no listed hazard",
            barrier.purpose
        );
    }
}
