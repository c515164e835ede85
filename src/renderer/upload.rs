//! Uploads: a whole scene or a range of instances, staged and copied between barriers.

use crate::allocator::MemoryAllocator;
use crate::allocator::MemoryUse;
use ash::vk;

use crate::barriers;
use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result};
use crate::frame_slots::Retired;
use crate::gpu::GpuBuffer;
use crate::instances::{pack_relative, pack_scene, Placement};
use crate::scene::Scene;

use super::buffers::Binding;
use super::uploaded::UploadedScene;
use super::EllipsoidRenderer;

impl EllipsoidRenderer {
    /// Replaces the instance data with `scene`, recording the copy into `cmd`. Positions are
    /// stored relative to a scene origin chosen at the centre of the data's bounds, so float32
    /// keeps its precision where the data is, however far that is from the world origin.
    ///
    /// The bytes go to a staging buffer now; `cmd` gets a barrier ordering earlier reads of
    /// the instance buffer before the copy, the copy, and a barrier ordering it before vertex
    /// and compute shader reads. Buffers that are replaced are retired, not destroyed.
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
        let packed = pack_scene(scene, self.settings.instance_format, placement)?;
        // A pre-pass recorded before this upload culled the old scene; the stamps of the old
        // scene say nothing of this one.
        for view in &mut self.views {
            view.prepared = None;
            view.shown_stamped = None;
        }
        // Until the new scene is recorded, none is drawn (so a failed upload draws nothing).
        let chunk_limit = self.settings.max_chunk_instances;
        self.scene = UploadedScene {
            format: packed.format(),
            chunk_limit,
            ..UploadedScene::default()
        };
        self.buffers.replaced = true; // the chunks and slices change
        let uploaded = UploadedScene::new(scene, &packed, chunk_limit);
        let bytes = packed.records.bytes();
        for view in 0..self.views.len() {
            self.size_buffers(
                device,
                allocator,
                view,
                uploaded.count,
                (1, 1),
                false,
                false,
            )?;
        }
        // Nor do the floor's lists.
        self.research.forget_upload();
        self.buffers.ensure(
            device,
            allocator,
            &mut self.slots,
            Binding::Instances,
            bytes.len().max(1) as u64,
        )?;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_copy(device, allocator, cmd, 0, bytes)? };
        self.scene = uploaded;
        Ok(())
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
        let end = first as u64 + ellipsoids.len() as u64;
        if end > self.scene.count as u64 {
            return Err(Error::invalid(
                "update",
                format!(
                    "instances {first}..{end} but {} are uploaded",
                    self.scene.count
                ),
            ));
        }
        if ellipsoids.is_empty() {
            return Ok(());
        }
        // A pre-pass recorded before this update planned for the old instances.
        for view in &mut self.views {
            view.prepared = None;
        }
        let format = self.scene.format;
        let packed = pack_relative(
            ellipsoids,
            self.scene.origin,
            first as usize,
            format,
            self.scene.radius_unit,
        )?;
        let offset = first as u64 * format.bytes() as u64;
        // SAFETY: forwarded caller contract.
        unsafe { self.record_copy(device, allocator, cmd, offset, packed.records.bytes())? };
        self.scene.merge_update(&packed);
        Ok(())
    }

    /// Stages `bytes` and records their copy to `offset` of the instance buffer, between the
    /// barriers [`barriers::INSTANCES_BEFORE_COPY`] and [`barriers::INSTANCES_AFTER_COPY`].
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`].
    unsafe fn record_copy(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        cmd: vk::CommandBuffer,
        offset: u64,
        bytes: &[u8],
    ) -> Result<()> {
        let instances = self.buffers.handle(Binding::Instances)?;
        if bytes.is_empty() {
            return Ok(());
        }
        let mut staging = GpuBuffer::new(
            device,
            allocator,
            "instance staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryUse::Upload,
        )?;
        if let Err(e) = staging.write(bytes) {
            // SAFETY: just made, never used.
            unsafe { staging.destroy(device, allocator) };
            return Err(e);
        }
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: offset,
            size: bytes.len() as u64,
        };
        // SAFETY: `cmd` is recording outside a pass (caller contract); both buffers are live
        // and the region lies inside them; the staging buffer is retired below, so it lives
        // until the copy has executed.
        unsafe {
            barriers::INSTANCES_BEFORE_COPY.record(device, cmd);
            device.cmd_copy_buffer(cmd, staging.handle(), instances, &[region]);
            barriers::INSTANCES_AFTER_COPY.record(device, cmd);
        }
        self.slots.retire(Retired::Buffer(staging));
        Ok(())
    }
}
