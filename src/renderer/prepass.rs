//! Recording the culling pre-pass of a frame: one per chunk, sharing the occlusion tiles.

use crate::allocator::MemoryAllocator;
use ash::vk;

use crate::camera::Camera;
use crate::culling::{
    self, CullSelect, CullStep, Culling, Dispatch, DispatchSize, Prepass, PrepassBuffers,
};
use crate::error::Result;
use crate::gpu_layout::{glyph_stamps_bytes, resolve_tiles, visibility_bytes, IndirectDraw};
use crate::pipeline::{CullKey, SplatKey};

use super::buffers::Binding;
use super::chunks::SLICE_ALIGN;
use super::plan::FramePlan;
use super::push::push_constants;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Records the pre-pass of a frame with `camera` (when its plan has one) into `cmd`,
    /// outside any rendering pass, with the barriers that order it after the previous frame's
    /// draw and before this draw's indirect and vertex reads. Call it before the pass that
    /// `record` draws into.
    ///
    /// A frame may have several views (two eyes, several viewports, several targets): record
    /// each view's pre-pass, then each view's draw with the same camera, in any pass after
    /// them. Each call takes the frame's next view, with buffers of its own (the first after
    /// `begin_frame` takes view 0), so record the views in the same order every frame: a
    /// view's still camera is then recognised and its visible-first splat runs.
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
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        camera: &Camera,
    ) -> Result<()> {
        let view = self.take_next_view()?;
        let plan = self.plan_for_view(view, camera)?;
        self.views[view].last_camera = Some(*camera);
        // Every pre-pass has a stamp of its own (never 0); the glyphs the view's last stamping
        // frame showed (of this scene) go first, whatever frames came between.
        self.frame_stamp = self.frame_stamp.checked_add(1).unwrap_or(1);
        let shown = self.views[view].shown_stamped.map(|(stamp, _)| stamp);
        if !plan.prepass {
            // Nothing to record, but the draw keeps this plan (and so the target current
            // now), as a view with a pre-pass does.
            self.views[view].prepared = Some((*camera, plan));
            return Ok(());
        }
        #[cfg(feature = "research")]
        self.check_floor_pixels(&plan)?;
        let (pipeline, _) = self.prepare(device, allocator, &plan)?;
        let marks = plan.mark_shown && self.splat_floor == 0;
        let extent = if plan.culling.occlusion || plan.resolve {
            (camera.width, camera.height)
        } else {
            (1, 1)
        };
        self.size_buffers(
            device,
            allocator,
            view,
            self.scene.count,
            extent,
            plan.resolve,
            marks,
        )?;
        #[cfg(feature = "research")]
        if plan.visibility_draw {
            // SAFETY: caller contract; the visibility buffer was sized for `camera` above.
            unsafe { self.record_visibility_draw(device, cmd, view, camera, &plan, pipeline)? };
            self.views[view].prepared = Some((*camera, plan));
            return Ok(());
        }
        #[cfg(not(feature = "research"))]
        let _ = pipeline;
        let dispatches = self.prepass_dispatches(device, &plan, camera, marks)?;
        let own = &self.views[view].buffers;
        let buffers = PrepassBuffers {
            indirect: own.handle(Binding::IndirectDraw)?,
            tiles: own.handle(Binding::OcclusionTiles)?,
        };
        let visibility = own.handle(Binding::Visibility)?;
        let stamps = own.handle(Binding::GlyphStamps)?;
        let groups = own.handle(Binding::CullGroups)?;
        let sets = self.descriptor_sets(device, view)?;
        let chunking = self.chunking();
        let groups_slice = chunking.groups_slice();
        // Each chunk culls its own instances into its own indirect command; the occlusion
        // tiles are cleared once and shared, so later chunks also see earlier occluders.
        let chunks: Vec<(u32, u32)> = chunking.chunks().collect();
        for (k, ((first, count), set)) in chunks.into_iter().zip(sets).enumerate() {
            let mut fills = Vec::new();
            if plan.compute_splat {
                if k == 0 {
                    // Nothing hit yet: every 64-bit key of the image holds the empty value.
                    let empty = if plan.reversed_z { 0 } else { u32::MAX };
                    let bytes = visibility_bytes(camera.width, camera.height);
                    fills.push((visibility, 0, bytes, empty));
                }
                // The keep bits of the glyphs the splat leaves to the draw.
                let bytes = culling::groups_bytes(count);
                fills.push((groups, k as u64 * groups_slice, bytes, 0));
                if marks && shown.is_none() {
                    // A new scene: no glyph shown yet, none left to the draw.
                    fills.push((stamps, 0, glyph_stamps_bytes(count), 0));
                }
            }
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
                    frame: self.frame_stamp,
                    shown: shown.unwrap_or(0),
                    dispatch_x: 0,
                    dispatch_y: 1,
                    dispatch_z: 1,
                },
                indirect_offset: k as u64 * SLICE_ALIGN,
                clear_tiles: plan.culling.occlusion && k == 0,
                buffers: PrepassBuffers { ..buffers },
                fills,
                dispatches: dispatches
                    .iter()
                    .map(|&(pipeline, size)| Dispatch { pipeline, size })
                    .collect(),
            };
            // SAFETY: `cmd` is recording outside a pass (caller contract); every handle is
            // owned by `self` and lives until the submission completes.
            unsafe { prepass.record(device, cmd) };
        }
        if marks {
            self.views[view].shown_stamped = Some((self.frame_stamp, *camera));
        }
        self.views[view].prepared = Some((*camera, plan));
        Ok(())
    }
}

impl EllipsoidRenderer {
    /// The pipelines of the pre-pass `plan` asks for, in order, each with its size: the
    /// culling steps; or the compute splat and the compaction of what it leaves to the draw;
    /// or the visible-first splat's two passes (with `marks`, the frame stamps what it shows).
    fn prepass_dispatches(
        &mut self,
        device: &ash::Device,
        plan: &FramePlan,
        camera: &Camera,
        marks: bool,
    ) -> Result<Vec<(vk::Pipeline, DispatchSize)>> {
        if !plan.compute_splat {
            return culling::steps(plan.culling)
                .into_iter()
                .map(|step| self.cull_step(device, plan, step, CullSelect::All, plan.culling))
                .collect();
        }
        let (w, h) = (camera.width, camera.height);
        let grid = |groups| {
            let (x, y) = culling::dispatch_grid(groups);
            DispatchSize::Grid(x, y)
        };
        let off = Culling::OFF;
        let mark_shown = (
            self.cull_pipeline(device, plan, CullStep::MarkShown, CullSelect::All, off)?,
            grid(resolve_tiles(w, h)),
        );
        let splat = SplatKey {
            floor: self.splat_floor,
            ..SplatKey::of(plan)
        };
        let mut dispatches = Vec::new();
        if plan.visible_first && self.splat_floor == 0 {
            let list = SplatKey {
                list: true,
                ..splat
            };
            let pass = (self.pipelines.splat(device, list)?, DispatchSize::Indirect);
            let key_tiles = (
                self.cull_pipeline(device, plan, CullStep::KeyTiles, CullSelect::All, off)?,
                grid(culling::tiles_count(w, h).div_ceil(culling::GROUP_SIZE as u32)),
            );
            let rest = plan.rest_culling;
            dispatches.extend(self.list_steps(device, plan, CullSelect::Shown, off)?);
            dispatches.push(pass);
            dispatches.push(key_tiles);
            dispatches.extend(self.list_steps(device, plan, CullSelect::Rest, rest)?);
            dispatches.push(pass);
            dispatches.push(mark_shown);
            dispatches.extend(self.list_steps(device, plan, CullSelect::Drawn, off)?);
        } else {
            dispatches.push((self.pipelines.splat(device, splat)?, DispatchSize::Splat));
            if marks {
                dispatches.push(mark_shown);
            }
            for step in culling::SPLAT_STEPS {
                dispatches.push(self.cull_step(device, plan, step, CullSelect::All, off)?);
            }
        }
        Ok(dispatches)
    }

    /// The steps that list the glyphs `select` picks (with `culling`), in instance order.
    fn list_steps(
        &mut self,
        device: &ash::Device,
        plan: &FramePlan,
        select: CullSelect,
        culling: Culling,
    ) -> Result<[(vk::Pipeline, DispatchSize); 3]> {
        let off = Culling::OFF;
        Ok([
            self.cull_step(device, plan, CullStep::Classify, select, culling)?,
            self.cull_step(device, plan, CullStep::Scan, CullSelect::All, off)?,
            self.cull_step(device, plan, CullStep::Scatter, CullSelect::All, off)?,
        ])
    }

    /// A culling step over the chunk's groups (SCAN: one workgroup) and its pipeline.
    fn cull_step(
        &mut self,
        device: &ash::Device,
        plan: &FramePlan,
        step: CullStep,
        select: CullSelect,
        culling: Culling,
    ) -> Result<(vk::Pipeline, DispatchSize)> {
        let size = match step {
            CullStep::Scan => DispatchSize::Grid(1, 1),
            _ => DispatchSize::Groups,
        };
        Ok((
            self.cull_pipeline(device, plan, step, select, culling)?,
            size,
        ))
    }

    /// The pipeline of one culling step, listing what `select` picks with `culling`.
    fn cull_pipeline(
        &mut self,
        device: &ash::Device,
        plan: &FramePlan,
        step: CullStep,
        select: CullSelect,
        culling: Culling,
    ) -> Result<vk::Pipeline> {
        let key = CullKey {
            select,
            culling,
            ..CullKey::of(plan, step)
        };
        self.pipelines.cull(device, key)
    }
}
