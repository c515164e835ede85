//! Uploads: a whole scene or a range of instances, staged, copied between barriers and
//! taken in at once (`staged.rs`); a failed one changes nothing.

use crate::allocator::MemoryAllocator;
use ash::vk;

use crate::ellipsoid::Ellipsoid;
use crate::error::Result;
use crate::instances::Placement;
use crate::scene::Scene;

use super::staged::StagedUpload;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Replaces the instance data with `scene`, recording the copy into `cmd`. Positions are
    /// stored relative to a scene origin chosen at the centre of the data's bounds, so float32
    /// keeps its precision where the data is, however far that is from the world origin.
    ///
    /// The bytes go to a staging buffer now; `cmd` gets a barrier ordering earlier reads of
    /// the instance buffer before the copy, the copy, and a barrier ordering it before vertex
    /// and compute shader reads. Buffers that are replaced are retired, not destroyed. An
    /// upload that fails (out of memory, say) changes nothing: the scene uploaded before stays.
    /// One that succeeds is the renderer's at once: a host that then does not submit `cmd`
    /// uploads again (`Error`'s documentation).
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::record_prepass`]: `cmd` is recording outside any pass and
    /// is submitted before, or is, the command buffer that draws this scene.
    pub unsafe fn upload(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        scene: &Scene,
    ) -> Result<()> {
        // SAFETY: forwarded caller contract.
        unsafe { self.upload_placed(device, allocator, cmd, scene, Placement::of(scene)) }
    }

    /// [`EllipsoidRenderer::upload`] with the glyphs stored as `placement` says, not from the
    /// scene's own bounds: a part of a scene drawn apart from the rest (another process's
    /// share) draws the whole scene's bits with the whole's [`Placement::enclosing`].
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    pub unsafe fn upload_placed(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        scene: &Scene,
        placement: Placement,
    ) -> Result<()> {
        let staged = self.stage_scene(device, allocator, scene, placement)?;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_and_commit(device, cmd, staged) }
    }

    /// Replaces instances `first..first + ellipsoids.len()` of the uploaded scene, recording
    /// the copy into `cmd` with the barriers of [`EllipsoidRenderer::upload`]. They keep the
    /// scene's origin, so they should lie near the uploaded data for full precision. The
    /// sample that picks the footprint is not updated.
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    pub unsafe fn update(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        first: u32,
        ellipsoids: &[Ellipsoid],
    ) -> Result<()> {
        let staged = self.stage_update(device, allocator, first, ellipsoids)?;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_and_commit(device, cmd, staged) }
    }

    /// Records a staged upload into `cmd` and commits it (or, if that fails, discards it).
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    unsafe fn record_and_commit(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        staged: StagedUpload,
    ) -> Result<()> {
        // SAFETY: forwarded caller contract.
        match unsafe { self.record_staged(device, cmd, &staged) } {
            Ok(()) => {
                self.commit_staged(staged);
                Ok(())
            }
            Err(e) => {
                self.discard_staged(staged);
                Err(e)
            }
        }
    }
}
