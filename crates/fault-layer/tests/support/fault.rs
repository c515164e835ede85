//! The faults a walk injects: the layer's two (a Vulkan call out of device memory, the device
//! lost) and the host allocator's (its N-th buffer refused, as out of memory).

use std::sync::atomic::{AtomicU8, Ordering};

use super::allocator;
use super::layer::{layer, LayerFault};

/// A fault to walk over a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fault {
    /// The N-th Vulkan call that can run out of memory returns
    /// `VK_ERROR_OUT_OF_DEVICE_MEMORY`.
    OutOfMemory,
    /// The device is lost at the N-th call that can report it.
    DeviceLost,
    /// The host's allocator refuses its N-th buffer (out of memory).
    AllocatorFails,
}

static ARMED: AtomicU8 = AtomicU8::new(0);

impl Fault {
    /// The error the call it hits must return: out of memory or device lost.
    pub fn named(self) -> Fault {
        match self {
            Fault::AllocatorFails => Fault::OutOfMemory,
            fault => fault,
        }
    }

    /// Counts the points this fault can hit from now on; the `at`-th (1-based; 0: none) gets
    /// it.
    pub fn arm(self, at: u64) {
        ARMED.store(self as u8, Ordering::SeqCst);
        match self {
            Fault::OutOfMemory => layer().arm(LayerFault::OutOfMemory, at),
            Fault::DeviceLost => layer().arm(LayerFault::DeviceLost, at),
            Fault::AllocatorFails => {
                layer().arm(LayerFault::OutOfMemory, 0);
                allocator::arm(at);
            }
        }
    }

    /// The points counted since `arm`.
    pub fn count(self) -> u64 {
        match self {
            Fault::AllocatorFails => allocator::count(),
            _ => layer().count(),
        }
    }

    /// What the fault hit, once it has.
    pub fn fired(self) -> Option<String> {
        match self {
            Fault::AllocatorFails => allocator::fired(),
            _ => layer().fired(),
        }
    }
}

/// Runs the test host's own per-frame `work` (its submissions and waits): counted where the
/// armed fault is a loss (the host is where a loss shows), paused where it is memory (the
/// host's own allocations are not the renderer's).
pub fn host_call<T>(work: impl FnOnce() -> T) -> T {
    if ARMED.load(Ordering::SeqCst) == Fault::DeviceLost as u8 {
        work()
    } else {
        layer().paused(work)
    }
}
