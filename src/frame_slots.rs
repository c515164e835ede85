//! Frames in flight: objects the renderer replaces while earlier frames may still read them
//! wait here until the host's fences prove every such frame finished.
//!
//! The host numbers its frames in flight `0..frames_in_flight` and calls `begin` with a slot
//! once the work it recorded the last time it used that slot has completed (it waited for that
//! slot's fence). An object retired during frame `F` (the count of `begin` calls so far) can be
//! used only by work recorded up to then; once every slot has begun after `F`, all of that work
//! is complete and the object is destroyed.

use crate::allocator::MemoryAllocator;
use ash::vk;

use crate::error::{Error, Result};
use crate::gpu::GpuBuffer;

/// Something the GPU may still be using.
pub(crate) enum Retired {
    /// A buffer (instances, staging, culling scratch).
    Buffer(GpuBuffer),
    /// A descriptor pool with the sets (one per chunk) the renderer allocated from it.
    DescriptorPool(vk::DescriptorPool),
    /// A texel view the sets of a retired pool pointed at.
    BufferView(vk::BufferView),
}

impl Retired {
    /// Destroys the object.
    ///
    /// # Safety
    /// No pending work uses it (the frame-slot rule above proves that for what `begin`
    /// returns).
    pub unsafe fn destroy(self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        match self {
            // SAFETY: caller contract.
            Retired::Buffer(buffer) => unsafe { buffer.destroy(device, allocator) },
            // SAFETY: created by the renderer from `device`; caller contract.
            Retired::DescriptorPool(pool) => unsafe { device.destroy_descriptor_pool(pool, None) },
            // SAFETY: created by the renderer from `device`; caller contract.
            Retired::BufferView(view) => unsafe { device.destroy_buffer_view(view, None) },
        }
    }
}

/// Per-slot bookkeeping and the objects (`Retired` in the renderer) waiting to be destroyed.
pub(crate) struct FrameSlots<T> {
    /// Frames begun so far.
    frame: u64,
    /// The frame at which each slot last began (0: never).
    last_begin: Vec<u64>,
    /// Objects and the frame during which they were retired.
    retired: Vec<(u64, T)>,
}

impl<T> FrameSlots<T> {
    pub fn new(frames_in_flight: u32) -> Result<Self> {
        if !(1..=16).contains(&frames_in_flight) {
            return Err(Error::invalid(
                "frames in flight",
                format!("{frames_in_flight} is outside 1..=16"),
            ));
        }
        Ok(Self {
            frame: 0,
            last_begin: vec![0; frames_in_flight as usize],
            retired: Vec::new(),
        })
    }

    /// Starts a frame in `slot`; returns what no pending work can use any more.
    pub fn begin(&mut self, slot: u32) -> Result<Vec<T>> {
        let slots = self.last_begin.len();
        let Some(last) = self.last_begin.get_mut(slot as usize) else {
            return Err(Error::invalid(
                "frame slot",
                format!("{slot} but the renderer was made for {slots} frames in flight"),
            ));
        };
        self.frame += 1;
        *last = self.frame;
        let oldest = self.last_begin.iter().copied().min().unwrap_or(0);
        let (done, waiting): (Vec<_>, Vec<_>) = std::mem::take(&mut self.retired)
            .into_iter()
            .partition(|(frame, _)| *frame < oldest);
        self.retired = waiting;
        Ok(done.into_iter().map(|(_, object)| object).collect())
    }

    /// Keeps `object` until no frame recorded so far can still be running.
    pub fn retire(&mut self, object: T) {
        self.retired.push((self.frame, object));
    }

    /// Everything retired, for destruction once the GPU is idle.
    pub fn drain(&mut self) -> Vec<T> {
        self.retired.drain(..).map(|(_, object)| object).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three slots used round robin: an object retired in one frame is released when the
    /// third frame after it begins, the first moment every slot's older work has finished.
    #[test]
    fn releases_only_after_every_slot_began_again() {
        let mut slots = FrameSlots::new(3).unwrap();
        assert!(slots.begin(0).unwrap().is_empty());
        slots.retire("a"); // during frame 1: slots 1 and 2 have never begun
        assert!(slots.begin(1).unwrap().is_empty());
        assert!(slots.begin(2).unwrap().is_empty());
        slots.retire("b"); // during frame 3
        assert_eq!(slots.begin(0).unwrap(), ["a"]); // frame 4: 0, 1, 2 all began after 1
        assert!(slots.begin(1).unwrap().is_empty());
        assert_eq!(slots.begin(2).unwrap(), ["b"]); // frame 6: slot 2's frame 3 is done
        slots.retire("c");
        assert_eq!(slots.drain(), ["c"]);
    }

    /// A slot that stays busy holds back everything retired after it last began.
    #[test]
    fn a_busy_slot_holds_objects_back() {
        let mut slots = FrameSlots::new(2).unwrap();
        slots.begin(0).unwrap();
        slots.begin(1).unwrap();
        slots.retire(7);
        for _ in 0..5 {
            assert!(
                slots.begin(0).unwrap().is_empty(),
                "slot 1 has not begun again"
            );
        }
        assert_eq!(slots.begin(1).unwrap(), [7]);
        assert!(FrameSlots::<u8>::new(0).is_err());
        assert!(slots
            .begin(2)
            .unwrap_err()
            .to_string()
            .contains("frame slot"));
    }
}
