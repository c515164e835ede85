//! The pre-pass of a frame, outside the host's pass: the culling steps before the draw, or
//! the compute splat (plain or visible-first) and the compaction of what it leaves to the
//! draw; one per chunk, sharing the occlusion tiles.
//!
//! The visible-first splat's steps (design §5.7):
//!
//! 1. CLASSIFY with `CULL_SELECT` `SHOWN`, SCAN, SCATTER (`glsl/cull.comp`): the glyphs whose stamp
//!    (`GlyphStamps`, binding 10) is the last stamping frame's (`IndirectDraw::shown`), in
//!    instance order. SCAN also writes the splat's dispatch over the list
//!    (`IndirectDraw::dispatch_x` to `dispatch_z`).
//! 2. The first pass: `glsl/splat.comp` with `SPLAT_LIST`, dispatched indirectly (after
//!    `PREPASS_STEP_TO_DISPATCH`), takes its glyphs from the list; otherwise it is the splat of
//!    design §5.6, except that a glyph too large for it is left to the draw by its stamp (the keep bits
//!    are busy with the lists).
//! 3. KEY_TILES: each 4 x 4 occlusion tile takes the farthest depth-buffer value the visibility
//!    buffer holds at its on-screen pixels (as bits: positive floats order like their bits; an
//!    empty pixel gives the empty key's, which hides nothing). One invocation per strip (a
//!    row of occlusion tiles across a resolve tile), which reads nothing where no glyph marked
//!    the resolve tile.
//! 4. CLASSIFY `REST`, SCAN, SCATTER: the glyphs not stamped, with frustum and pixel-centre
//!    culling, kept unless every tile under the pixels with a sample in their rectangle (the
//!    rectangle the culling trusts, design §5.3) hides them: their nearest point, moved nearer by
//!    `DEPTH_GAP` (1e-4) of the depths involved (`|cz| + |A^T f|`: the difference may be far
//!    smaller than its terms), lies beyond the near plane and has a depth-buffer value more than
//!    two float steps beyond the tile's; a glyph that may reach the near plane is kept. Every
//!    hit of the glyph then lies beyond what each of its pixels holds, so it can neither win nor
//!    tie one, and the splat's atomics would change nothing. The second pass splats the list,
//!    each glyph skipping the tiles under it where the same test holds.
//! 5. MARK_SHOWN: one invocation per strip of a resolve tile a glyph marked (a loop of no
//!    trips elsewhere: lavapipe runs a branch's body whatever the condition, but not a loop's)
//!    stamps the glyph each pixel shows with the frame's stamp.
//! 6. CLASSIFY `DRAWN`, SCAN, SCATTER: the glyphs a pass left to the draw, in instance order, for
//!    the indirect draw after the resolve.

mod record;
pub(crate) mod steps;

use crate::allocator::MemoryAllocator;
use ash::vk;

use crate::camera::Camera;
use crate::culling::Culling;
use crate::error::Result;
use crate::gpu_layout::{glyph_stamps_bytes, resolve_tiles, visibility_bytes, IndirectDraw};
use crate::path::{FramePath, HiddenLayers};

use super::buffers::Binding;
use super::chunks::SLICE_ALIGN;
use super::pipelines::keys::{CullKey, SplatKey};
use super::plan::FramePlan;
use super::push::push_constants;
use super::EllipsoidRenderer;
// The traced path's boxes shader (research) takes the splat's grid.
#[cfg(feature = "research")]
pub(crate) use record::splat_grid;
pub(crate) use record::TracedDispatch;
use record::{Dispatch, DispatchSize, Prepass, PrepassBuffers};
use steps::{CullSelect, CullStep, TiledStep};

impl EllipsoidRenderer {
    /// Records the pre-pass of a frame with `camera` (when its plan has one) into `cmd`,
    /// outside any rendering pass, with the barriers that order it after the previous frame's
    /// draw and before this draw's indirect and vertex reads. Call it before the pass that
    /// `record` draws into.
    ///
    /// A frame may have several views (two eyes, several viewports, several targets): record
    /// each view's pre-pass, then each view's draw with the same camera, in any pass after
    /// them. Each call takes the frame's next view, with buffers of its own (the first after
    /// `begin_frame` takes view 0), so record the views in the same order every frame: each
    /// view's visible-first splat then starts from what that view showed last.
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
        self.last_plan = Some(plan);
        // The plan that measures notes what this frame runs; its timestamps say how long.
        // A view the timer cannot time counts as a frame with nothing to time.
        let timed = self.timer.times_view(view);
        let token = plan.class.and_then(|class| {
            let candidates = plan.candidates();
            let ran = plan.path.timed_kind().filter(|_| timed);
            self.learning.commit(class, &candidates, plan.chosen, ran)
        });
        // SAFETY: caller contract: `cmd` records outside a pass for the current slot.
        unsafe {
            self.timer
                .prepass_start(device, cmd, self.slot, view, token)
        };
        // Every pre-pass has a stamp of its own (never 0); the glyphs the view's last stamping
        // frame showed (of this scene) go first, whatever frames came between.
        self.frame_stamp = self.frame_stamp.checked_add(1).unwrap_or(1);
        let shown = self.views[view].shown_stamped;
        let recorded = if plan.prepass() {
            // SAFETY: forwarded caller contract.
            unsafe { self.record_prepass_of(device, allocator, cmd, view, camera, &plan, shown) }
        } else {
            Ok(())
        };
        // SAFETY: as above, after the pre-pass's commands.
        unsafe { self.timer.prepass_end(device, cmd, self.slot, view) };
        recorded?;
        // The draw keeps this plan (and so the target current now).
        self.views[view].prepared = Some((*camera, plan));
        Ok(())
    }

    /// Records the pre-pass `plan` has, for `view`.
    ///
    /// # Safety
    /// As [`EllipsoidRenderer::record_prepass`].
    #[allow(clippy::too_many_arguments)]
    unsafe fn record_prepass_of(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        view: usize,
        camera: &Camera,
        plan: &FramePlan,
        shown: Option<u32>,
    ) -> Result<()> {
        self.check_floor_pixels(plan)?;
        let (pipeline, _) = self.prepare(device, allocator, plan)?;
        let marks = matches!(
            plan.path,
            FramePath::Splat(s) if s.hidden != HiddenLayers::SplatAll
        );
        let extent = if plan.culling().occlusion || plan.resolves() {
            (camera.width, camera.height)
        } else {
            (1, 1)
        };
        self.size_buffers(
            device,
            allocator,
            view,
            self.chunking(),
            extent,
            plan.resolves(),
            marks,
        )?;
        if plan.visibility_draw() {
            // SAFETY: caller contract; the visibility buffer was sized for `camera` above.
            return unsafe {
                self.record_visibility_draw(device, cmd, view, camera, plan, pipeline)
            };
        }
        let sets = self.descriptor_sets(device, view)?;
        let first_push = push_constants(
            camera,
            &self.settings.material,
            self.scene.origin,
            self.scene.radius_unit,
            0,
        );
        // SAFETY: forwarded caller contract.
        let traced = unsafe {
            self.record_traced_build(device, allocator, cmd, plan, sets[0], &first_push)?
        };
        let dispatches = self.prepass_dispatches(device, plan, camera, traced)?;
        let own = &self.views[view].buffers;
        let buffers = PrepassBuffers {
            indirect: own.handle(Binding::IndirectDraw)?,
            tiles: own.handle(Binding::OcclusionTiles)?,
        };
        let visibility = own.handle(Binding::Visibility)?;
        let stamps = own.handle(Binding::GlyphStamps)?;
        let groups = own.handle(Binding::CullGroups)?;
        let tile_lists = own.handle(Binding::TileLists)?;
        let tiled = self.tiled_splat(plan);
        let chunking = self.chunking();
        let groups_slice = chunking.groups_slice();
        // Each chunk culls its own instances into its own indirect command; the occlusion
        // tiles are cleared once and shared, so later chunks also see earlier occluders.
        let chunks: Vec<(u32, u32)> = chunking.chunks().collect();
        // The occlusion tiles' clear word: the culling's +inf bits (no surface known in front
        // of any tile yet), or under the visible-first splat the empty key's word (hides
        // nothing, glsl/include/nearest_depth.glsl), which KEY_TILES leaves in the tiles no
        // glyph marked: cleared every such frame, since they hold what an earlier frame, of
        // another camera or path, left there.
        let empty_key_word = if plan.reversed_z { 0 } else { u32::MAX };
        let visible_first = matches!(
            plan.path.splat().map(|s| s.hidden),
            Some(HiddenLayers::VisibleFirst { .. })
        );
        let tiles_word = if visible_first {
            empty_key_word
        } else {
            f32::INFINITY.to_bits()
        };
        for (k, ((first, count), set)) in chunks.into_iter().zip(sets).enumerate() {
            let mut fills = Vec::new();
            if plan.path.splat().is_some() {
                if k == 0 {
                    // Nothing hit yet: every 64-bit key of the image holds the empty value.
                    let bytes = visibility_bytes(camera.width, camera.height);
                    fills.push((visibility, 0, bytes, empty_key_word));
                }
                // The keep bits of the glyphs the splat leaves to the draw.
                let bytes = steps::groups_bytes(count);
                fills.push((groups, k as u64 * groups_slice, bytes, 0));
                if tiled {
                    // The tiled splat's header (no glyph depth yet: nearest +inf, farthest 0)
                    // and counts.
                    let cells = steps::tiled_cells(camera.width, camera.height);
                    fills.push((tile_lists, 0, 4, f32::INFINITY.to_bits()));
                    let words = steps::TILED_HEADER_WORDS - 1 + cells;
                    fills.push((tile_lists, 4, 4 * words, 0));
                }
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
                traced_set: traced.map(|t| (t.layout, t.set)),
                command: IndirectDraw {
                    vertex_count: plan.vertices(),
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
                clear_tiles: ((plan.culling().occlusion || visible_first) && k == 0)
                    .then_some(tiles_word),
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
            self.views[view].shown_stamped = Some(self.frame_stamp);
        }
        Ok(())
    }
}
impl EllipsoidRenderer {
    /// The pipelines of the pre-pass `plan` asks for, in order, each with its size: the
    /// culling steps; or the compute splat and the compaction of what it leaves to the draw
    /// (stamping what the frame shows where the path asks); or the visible-first splat's two
    /// passes.
    fn prepass_dispatches(
        &mut self,
        device: &ash::Device,
        plan: &FramePlan,
        camera: &Camera,
        traced: Option<TracedDispatch>,
    ) -> Result<Vec<(vk::Pipeline, DispatchSize)>> {
        let splat_path = match plan.path {
            FramePath::Draw(draw) => {
                return steps::steps(draw.culling)
                    .into_iter()
                    .map(|step| self.cull_step(device, plan, step, CullSelect::All, draw.culling))
                    .collect();
            }
            FramePath::Splat(splat) => splat,
        };
        let (w, h) = (camera.width, camera.height);
        let grid = |groups| {
            let (x, y) = steps::dispatch_grid(groups);
            DispatchSize::Grid(x, y)
        };
        let off = Culling::OFF;
        let mark_shown = (
            self.cull_pipeline(device, plan, CullStep::MarkShown, CullSelect::All, off)?,
            grid(steps::strip_groups(resolve_tiles(w, h))),
        );
        let splat = SplatKey::of(plan, &self.research);
        let mut dispatches = Vec::new();
        match splat_path.hidden {
            HiddenLayers::VisibleFirst { rest } => {
                let mut pass = |select| -> Result<_> {
                    let list = SplatKey {
                        list: Some(select),
                        ..splat
                    };
                    Ok((self.pipelines.splat(device, list)?, DispatchSize::Indirect))
                };
                let (first_pass, second_pass) = (pass(CullSelect::Shown)?, pass(CullSelect::Rest)?);
                let key_tiles = (
                    self.cull_pipeline(device, plan, CullStep::KeyTiles, CullSelect::All, off)?,
                    grid(steps::strip_groups(resolve_tiles(w, h))),
                );
                dispatches.extend(self.list_steps(device, plan, CullSelect::Shown, off)?);
                dispatches.push(first_pass);
                dispatches.push(key_tiles);
                dispatches.extend(self.list_steps(device, plan, CullSelect::Rest, rest)?);
                dispatches.push(second_pass);
                dispatches.push(mark_shown);
                dispatches.extend(self.list_steps(device, plan, CullSelect::Drawn, off)?);
            }
            _ if self.tiled_splat(plan) => {
                // The benchmark's tiled splat in place of the splat (same keep bits after).
                let (x, y) = steps::tiled_grid(w, h);
                for step in TiledStep::ALL {
                    let size = match step {
                        TiledStep::Scan => DispatchSize::Grid(1, 1),
                        TiledStep::Tiles => DispatchSize::Grid(x, y),
                        _ => DispatchSize::Splat,
                    };
                    let key = SplatKey {
                        tiled: Some(step),
                        ..splat
                    };
                    dispatches.push((self.pipelines.splat(device, key)?, size));
                }
                for step in steps::SPLAT_STEPS {
                    dispatches.push(self.cull_step(device, plan, step, CullSelect::All, off)?);
                }
            }
            hidden => {
                dispatches.push(match traced {
                    // One invocation per pixel, in squares of the traversal's group edge.
                    Some(t) => (
                        t.pipeline,
                        DispatchSize::Grid(w.div_ceil(t.group_edge), h.div_ceil(t.group_edge)),
                    ),
                    None => (self.pipelines.splat(device, splat)?, DispatchSize::Splat),
                });
                if hidden == HiddenLayers::StampShown {
                    dispatches.push(mark_shown);
                }
                for step in steps::SPLAT_STEPS {
                    dispatches.push(self.cull_step(device, plan, step, CullSelect::All, off)?);
                }
            }
        }
        Ok(dispatches)
    }

    /// Whether `plan`'s frame runs the benchmark's tiled splat: it splats every glyph and the
    /// research state asks for it.
    fn tiled_splat(&self, plan: &FramePlan) -> bool {
        self.research.tiled_splat()
            && matches!(plan.path, FramePath::Splat(s) if s.hidden == HiddenLayers::SplatAll)
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
            CullStep::Scatter => DispatchSize::Words,
            CullStep::Classify if select.by_stamp() => DispatchSize::Words,
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
        self.pipelines
            .cull(device, CullKey::of(plan, step, select, culling))
    }
}
