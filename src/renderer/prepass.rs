//! Recording the culling pre-pass of a frame: one per chunk, sharing the occlusion tiles.

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use crate::camera::Camera;
use crate::culling::{self, Prepass, PrepassBuffers, SplatStep, SPLAT_GROUP_SIZE};
use crate::error::Result;
use crate::gpu_layout::{visibility_bytes, IndirectDraw};
use crate::pipeline::{CullKey, SplatKey};

use super::buffers::Binding;
use super::chunks::SLICE_ALIGN;
use super::push::push_constants;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Records the pre-pass of a frame with `camera` (when its plan has one) into `cmd`,
    /// outside any rendering pass, with the barriers that order it after the previous frame's
    /// draw and before this draw's indirect and vertex reads. Call it before the pass that
    /// `record` draws into.
    ///
    /// It writes the indirect command with `vkCmdUpdateBuffer`, clears the occlusion tiles
    /// with `vkCmdFillBuffer`, then runs the steps of `glsl/cull.comp`, each after a
    /// compute-to-compute barrier. When the image grew since the last frame the tiles buffer
    /// is replaced (the old one retired).
    ///
    /// With the `research` feature's visibility-buffer draw (`impostor-visbuffer`) it records
    /// instead a rendering pass of its own, with no attachments, and binds a graphics
    /// pipeline, descriptor sets, push constants, viewport and scissor there: a host that
    /// measures it rebinds its own state after this call.
    ///
    /// # Safety
    /// `device` is the renderer's device, `cmd` a command buffer of it in the recording state
    /// outside any pass, for the queue family the renderer was made for, and submitted before
    /// the slot that is current (`begin_frame`) begins again.
    pub unsafe fn record_prepass(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        self.prepared = None;
        let plan = self.plan(camera)?;
        if !plan.prepass {
            return Ok(());
        }
        let (pipeline, _) = self.prepare(device, allocator, &plan)?;
        if plan.culling.occlusion || plan.resolve {
            self.size_buffers(
                device,
                allocator,
                self.scene.count,
                (camera.width, camera.height),
                plan.resolve,
            )?;
        }
        #[cfg(feature = "research")]
        if plan.visibility_draw {
            // SAFETY: caller contract; the visibility buffer was sized for `camera` above.
            unsafe { self.record_visibility_draw(device, cmd, camera, &plan, pipeline)? };
            self.prepared = Some((*camera, plan));
            return Ok(());
        }
        #[cfg(not(feature = "research"))]
        let _ = pipeline;
        let splat = if plan.compute_splat {
            let key = SplatKey {
                floor: self.splat_floor,
                ..SplatKey::of(&plan)
            };
            let pipeline = self.pipelines.splat(device, key)?;
            let empty = if plan.reversed_z { 0 } else { u32::MAX };
            Some((pipeline, self.buffers.handle(Binding::Visibility)?, empty))
        } else {
            None
        };
        let steps = if plan.compute_splat {
            culling::SPLAT_STEPS.to_vec()
        } else {
            culling::steps(plan.culling)
        };
        let steps = steps
            .into_iter()
            .map(|step| Ok((step, self.pipelines.cull(device, CullKey::of(&plan, step))?)))
            .collect::<Result<Vec<_>>>()?;
        let buffers = PrepassBuffers {
            indirect: self.buffers.handle(Binding::IndirectDraw)?,
            tiles: self.buffers.handle(Binding::OcclusionTiles)?,
        };
        let sets = self.descriptor_sets(device)?;
        let groups = self.buffers.handle(Binding::CullGroups)?;
        let chunking = self.chunking();
        let groups_slice = chunking.groups_slice();
        // Each chunk culls its own instances into its own indirect command; the occlusion
        // tiles are cleared once and shared, so later chunks also see earlier occluders.
        let chunks: Vec<(u32, u32)> = chunking.chunks().collect();
        for (k, ((first, count), set)) in chunks.into_iter().zip(sets).enumerate() {
            let prepass = Prepass {
                layout: self.pipelines.cull_layout,
                descriptor_set: set,
                push: push_constants(
                    camera,
                    &self.settings.material,
                    self.scene.origin,
                    self.scene.radius_unit,
                    first,
                ),
                command: IndirectDraw {
                    vertex_count: plan.config.footprint.vertices(),
                    instance_count: 0,
                    first_vertex: 0,
                    first_instance: 0,
                    total: count,
                },
                indirect_offset: k as u64 * SLICE_ALIGN,
                steps: steps.clone(),
                groups: culling::dispatch_grid(culling::group_count(count)),
                clear_tiles: plan.culling.occlusion && k == 0,
                buffers: PrepassBuffers { ..buffers },
                splat: splat.map(|(pipeline, visibility, empty)| SplatStep {
                    pipeline,
                    groups: culling::dispatch_grid(count.div_ceil(SPLAT_GROUP_SIZE)),
                    clear: (k == 0).then_some((
                        visibility,
                        visibility_bytes(camera.width, camera.height),
                        empty,
                    )),
                    keep: (
                        groups,
                        k as u64 * groups_slice,
                        culling::groups_bytes(count),
                    ),
                }),
            };
            // SAFETY: `cmd` is recording outside a pass (caller contract); every handle is
            // owned by `self` and lives until the submission completes.
            unsafe { prepass.record(device, cmd) };
        }
        self.prepared = Some((*camera, plan));
        Ok(())
    }
}
