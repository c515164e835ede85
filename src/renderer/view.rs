//! One view of a frame: what a camera drawn in the frame owns for itself. Each
//! `record_prepass` of a frame takes the next view (the first after `begin_frame` takes view
//! 0), so a host that records its views in the same order every frame finds each view's
//! history -- the camera of its last pre-pass, the glyphs it last showed -- where it left it.

use crate::allocator::MemoryAllocator;

use crate::camera::Camera;

use super::buffers::SceneBuffers;
use super::descriptors::ChunkSets;
use super::plan::FramePlan;

/// The most views one frame may have: each holds its own pre-pass buffers.
pub(crate) const MAX_VIEWS: usize = 64;

/// A view's pre-pass buffers and descriptor sets, its plan until its draw, and what the
/// visible-first splat remembers of its earlier frames.
#[derive(Default)]
pub(crate) struct View {
    /// The bindings each view has for itself (`Binding::per_view`); the others are the
    /// renderer's.
    pub buffers: SceneBuffers,
    /// The per-chunk descriptor sets, the pool holding them alone and their texel views.
    pub descriptors: ChunkSets,
    /// The plan and camera of the pre-pass recorded for this view's next `record`.
    pub prepared: Option<(Camera, FramePlan)>,
    /// The stamp of the view's last pre-pass that stamped the glyphs its frame showed, since
    /// the last upload (frames between that did not stamp leave it).
    pub shown_stamped: Option<u32>,
    /// The camera of the view's last pre-pass.
    pub last_camera: Option<Camera>,
}

impl View {
    /// Destroys the view's buffers, descriptor pool and texel views.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(&mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        // SAFETY: caller contract; a null pool is ignored.
        unsafe {
            self.buffers.destroy(device, allocator);
            self.descriptors.destroy(device);
        }
    }
}
