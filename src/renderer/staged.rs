//! An upload or update in three parts, so that one that fails changes nothing: staged (the
//! memory it needs allocated, its bytes written to a staging buffer; a failure frees what was
//! made and leaves the uploaded scene as it was), recorded (the copy, between barriers), then
//! committed (the renderer takes the new scene) -- or discarded, when the command buffer
//! holding the copy was never submitted or did not complete, which leaves the old scene.

use ash::vk;

use crate::allocator::{MemoryAllocator, MemoryUse};
use crate::barriers;
use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result};
use crate::frame_slots::Retired;
use crate::gpu::GpuBuffer;
use crate::instances::{pack_relative, pack_scene, PackedInstances, Placement};
use crate::scene::Scene;

use super::buffers::Binding;
use super::chunks::Chunking;
use super::uploaded::UploadedScene;
use super::EllipsoidRenderer;

/// What a staged upload changes once committed.
enum Change {
    /// A whole new scene: its facts, and a new instance buffer where the current one is too
    /// small (or missing).
    Scene {
        uploaded: UploadedScene,
        instances: Option<GpuBuffer>,
    },
    /// Instances of the uploaded scene replaced.
    Update(PackedInstances),
}

/// An upload or update staged: nothing of the renderer has changed yet.
pub(crate) struct StagedUpload {
    change: Change,
    /// The bytes, in host-visible memory (none when there are none).
    staging: Option<GpuBuffer>,
    /// Where in the instance buffer they go.
    offset: u64,
}

impl EllipsoidRenderer {
    /// Stages `scene`, stored as `placement` says. The buffers every view needs for it are
    /// grown now (a failure leaves them larger, which the old scene does not mind).
    pub(crate) fn stage_scene(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        scene: &Scene,
        placement: Placement,
    ) -> Result<StagedUpload> {
        let packed = pack_scene(scene, self.settings.instance_format, placement)?;
        let chunk_limit = self.settings.max_chunk_instances;
        let uploaded = UploadedScene::new(scene, &packed, chunk_limit);
        let chunking = Chunking::new(
            uploaded.count,
            packed.format().bytes(),
            Chunking::max_binding_bytes(&self.caps.limits, 16),
            chunk_limit,
        );
        // A pre-pass recorded before this call may have planned with buffers replaced below.
        for view in &mut self.views {
            view.prepared = None;
        }
        for view in 0..self.views.len() {
            self.size_buffers(device, allocator, view, chunking, (1, 1), false, false)?;
        }
        let bytes = packed.records.bytes();
        // At least one record: each chunk's texel view of the buffer holds one at least.
        let needed = bytes.len().max(packed.format().bytes()) as u64;
        let fits = self
            .buffers
            .get(Binding::Instances)
            .is_some_and(|b| b.size() >= needed);
        let instances = if fits {
            None
        } else {
            Some(GpuBuffer::new(
                device,
                allocator,
                Binding::Instances.name(),
                needed,
                Binding::Instances.usage(),
                Binding::Instances.memory_use(),
            )?)
        };
        let staging = match stage(device, allocator, bytes) {
            Ok(staging) => staging,
            Err(e) => {
                if let Some(buffer) = instances {
                    // SAFETY: just made, never used.
                    unsafe { buffer.destroy(device, allocator) };
                }
                return Err(e);
            }
        };
        Ok(StagedUpload {
            change: Change::Scene {
                uploaded,
                instances,
            },
            staging,
            offset: 0,
        })
    }

    /// Stages the replacement of instances `first..first + ellipsoids.len()` of the uploaded
    /// scene (a range past the uploaded count is [`Error::Invalid`]).
    pub(crate) fn stage_update(
        &mut self,
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        first: u32,
        ellipsoids: &[Ellipsoid],
    ) -> Result<StagedUpload> {
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
        let format = self.scene.format;
        let packed = pack_relative(
            ellipsoids,
            self.scene.origin,
            first as usize,
            format,
            self.scene.radius_unit,
        )?;
        let staging = stage(device, allocator, packed.records.bytes())?;
        Ok(StagedUpload {
            change: Change::Update(packed),
            staging,
            offset: first as u64 * format.bytes() as u64,
        })
    }

    /// Records the staged copy into `cmd`, between [`barriers::INSTANCES_BEFORE_COPY`] and
    /// [`barriers::INSTANCES_AFTER_COPY`].
    ///
    /// # Safety
    /// As for [`EllipsoidRenderer::upload`]: `cmd` is recording outside any pass. `staged`
    /// is then committed or discarded, not recorded again.
    pub(crate) unsafe fn record_staged(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        staged: &StagedUpload,
    ) -> Result<()> {
        let Some(staging) = &staged.staging else {
            return Ok(());
        };
        let instances = match &staged.change {
            Change::Scene {
                instances: Some(new),
                ..
            } => new.handle(),
            _ => self.buffers.handle(Binding::Instances)?,
        };
        let region = vk::BufferCopy {
            src_offset: 0,
            dst_offset: staged.offset,
            size: staging.size(),
        };
        // SAFETY: `cmd` is recording outside a pass (caller contract); both buffers are live
        // and the region lies inside them; both live until the copy has executed (committed
        // or discarded, they are retired).
        unsafe {
            barriers::INSTANCES_BEFORE_COPY.record(device, cmd);
            device.cmd_copy_buffer(cmd, staging.handle(), instances, &[region]);
            barriers::INSTANCES_AFTER_COPY.record(device, cmd);
        }
        Ok(())
    }

    /// Takes in a staged upload whose copy was recorded: the renderer draws it from now on.
    pub(crate) fn commit_staged(&mut self, staged: StagedUpload) {
        let StagedUpload {
            change, staging, ..
        } = staged;
        if let Some(staging) = staging {
            self.slots.retire(Retired::Buffer(staging));
        }
        match change {
            Change::Scene {
                uploaded,
                instances,
            } => {
                // The stamps of the old scene say nothing of this one, nor do the floor's lists.
                for view in &mut self.views {
                    view.prepared = None;
                    view.shown_stamped = None;
                }
                self.research.forget_upload();
                if let Some(instances) = instances {
                    self.buffers
                        .install(&mut self.slots, Binding::Instances, instances);
                }
                self.buffers.replaced = true; // the chunks and slices change
                self.scene = uploaded;
            }
            Change::Update(packed) if !packed.is_empty() => {
                // A pre-pass recorded before this update planned for the old instances.
                for view in &mut self.views {
                    view.prepared = None;
                }
                self.scene.merge_update(&packed);
                self.research.forget_instances();
            }
            Change::Update(_) => {}
        }
    }

    /// Drops a staged upload: the renderer keeps drawing what it drew. Its buffers are
    /// retired, not destroyed, since a command buffer that recorded the copy may still run.
    pub(crate) fn discard_staged(&mut self, staged: StagedUpload) {
        let instances = match staged.change {
            Change::Scene { instances, .. } => instances,
            Change::Update(_) => None,
        };
        for buffer in staged.staging.into_iter().chain(instances) {
            self.slots.retire(Retired::Buffer(buffer));
        }
    }
}

/// A host-visible buffer holding `bytes` (none for no bytes).
fn stage(
    device: &ash::Device,
    allocator: &mut dyn MemoryAllocator,
    bytes: &[u8],
) -> Result<Option<GpuBuffer>> {
    if bytes.is_empty() {
        return Ok(None);
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
    Ok(Some(staging))
}
