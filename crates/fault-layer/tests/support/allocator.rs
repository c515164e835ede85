//! The host allocator's faults: a count of the buffers the renderer asks the host for, the
//! N-th refused (out of memory), and the buffers still live. The Rust host's allocator is
//! [`FailingAllocator`] (the host's gpu-allocator behind that count); the C host's is the pair
//! of callbacks [`callbacks`] hands the C ABI.

use std::ffi::{c_char, c_void, CStr};
use std::sync::atomic::{AtomicBool, AtomicI64, AtomicU64, Ordering};
use std::sync::Mutex;

use ash::vk::{self, Handle};
use ellipsoid_splat::{BufferMemory, MemoryUse};
use ellipsoid_splat::{Error, MemoryAllocator, Result};
use ellipsoid_splat_capi::{EsAllocatorCallbacks, EsBuffer, EsMemoryUse};
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

static CALLS: AtomicU64 = AtomicU64::new(0);
static AT: AtomicU64 = AtomicU64::new(0);
static FIRED: Mutex<Option<String>> = Mutex::new(None);
static LIVE: AtomicI64 = AtomicI64::new(0);
static COUNTING: AtomicBool = AtomicBool::new(false);

/// Counts buffer requests from now on; the `at`-th (1-based; 0: none) is refused.
pub fn arm(at: u64) {
    CALLS.store(0, Ordering::SeqCst);
    AT.store(at, Ordering::SeqCst);
    *FIRED.lock().unwrap() = None;
    COUNTING.store(true, Ordering::SeqCst);
}

/// Buffer requests since `arm`.
pub fn count() -> u64 {
    CALLS.load(Ordering::SeqCst)
}

/// The buffer refused, once one was.
pub fn fired() -> Option<String> {
    FIRED.lock().unwrap().clone()
}

/// Buffers made and not yet destroyed (0 once a renderer is gone).
pub fn live() -> i64 {
    LIVE.load(Ordering::SeqCst)
}

/// Counts a request for the buffer `name`; true where it is the one to refuse.
fn refuse(name: &str) -> bool {
    let n = CALLS.fetch_add(1, Ordering::SeqCst) + 1;
    let hit = COUNTING.load(Ordering::SeqCst) && n == AT.load(Ordering::SeqCst);
    if hit {
        *FIRED.lock().unwrap() = Some(format!("allocation of {name}"));
    }
    hit
}

/// The host's gpu-allocator behind the count: the N-th buffer is refused as out of memory.
pub struct FailingAllocator<'a>(pub &'a mut Allocator);

// SAFETY: every buffer is the inner allocator's, made as its `create_buffer` makes them.
unsafe impl MemoryAllocator for FailingAllocator<'_> {
    unsafe fn create_buffer(
        &mut self,
        device: &ash::Device,
        info: &vk::BufferCreateInfo<'_>,
        name: &str,
        usage: MemoryUse,
    ) -> Result<(vk::Buffer, BufferMemory)> {
        if refuse(name) {
            return Err(Error::OutOfMemory {
                what: name.to_string(),
                device: true,
                reason: "the host's allocator refused it (injected)".into(),
            });
        }
        // SAFETY: forwarded caller contract.
        let made = unsafe { self.0.create_buffer(device, info, name, usage) }?;
        LIVE.fetch_add(1, Ordering::SeqCst);
        Ok(made)
    }

    unsafe fn destroy_buffer(
        &mut self,
        device: &ash::Device,
        buffer: vk::Buffer,
        memory: BufferMemory,
    ) -> Result<()> {
        LIVE.fetch_sub(1, Ordering::SeqCst);
        // SAFETY: forwarded caller contract.
        unsafe { self.0.destroy_buffer(device, buffer, memory) }
    }
}

/// What the C callbacks need: the host's device and allocator, borrowed for the renderer's
/// life (the host uses neither while a renderer call runs).
pub struct CallbackHost {
    pub device: ash::Device,
    pub allocator: *mut Allocator,
}

/// The C host's allocator callbacks, with `host` as their user data.
pub fn callbacks(host: *mut CallbackHost) -> EsAllocatorCallbacks {
    EsAllocatorCallbacks {
        struct_size: size_of::<EsAllocatorCallbacks>() as u32,
        user_data: host.cast(),
        create_buffer: Some(create_buffer),
        destroy_buffer: Some(destroy_buffer),
    }
}

/// `EsAllocatorCallbacks.create_buffer`: the buffer with gpu-allocator memory bound, or
/// `VK_ERROR_OUT_OF_DEVICE_MEMORY` where the count says so (or the allocator runs out).
unsafe extern "C" fn create_buffer(
    user_data: *mut c_void,
    info: *const vk::BufferCreateInfo<'static>,
    usage: EsMemoryUse,
    name: *const c_char,
    out: *mut EsBuffer,
) -> vk::Result {
    // SAFETY: the library passes a NUL-terminated name, our user data, its create info and
    // a writable `out`.
    let (host, info, name, out) = unsafe {
        (
            &mut *(user_data as *mut CallbackHost),
            &*info,
            CStr::from_ptr(name).to_string_lossy().into_owned(),
            &mut *out,
        )
    };
    if refuse(&name) {
        return vk::Result::ERROR_OUT_OF_DEVICE_MEMORY;
    }
    // SAFETY: the host's allocator, not used elsewhere during the call.
    let allocator = unsafe { &mut *host.allocator };
    // SAFETY: the host's device and the library's create info.
    let buffer = match unsafe { host.device.create_buffer(info, None) } {
        Ok(buffer) => buffer,
        Err(result) => return result,
    };
    // SAFETY: just made.
    let requirements = unsafe { host.device.get_buffer_memory_requirements(buffer) };
    let location = match usage {
        EsMemoryUse::GpuOnly => MemoryLocation::GpuOnly,
        EsMemoryUse::Upload => MemoryLocation::CpuToGpu,
        EsMemoryUse::Readback => MemoryLocation::GpuToCpu,
    };
    let allocation = allocator.allocate(&AllocationCreateDesc {
        name: &name,
        requirements,
        location,
        linear: true,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    });
    let allocation = match allocation {
        Ok(allocation) => allocation,
        Err(_) => {
            // SAFETY: unused.
            unsafe { host.device.destroy_buffer(buffer, None) };
            return vk::Result::ERROR_OUT_OF_DEVICE_MEMORY;
        }
    };
    // SAFETY: memory made for this buffer's requirements.
    let bound = unsafe {
        host.device
            .bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
    };
    if let Err(result) = bound {
        // SAFETY: unused.
        unsafe { host.device.destroy_buffer(buffer, None) };
        let _ = allocator.free(allocation);
        return result;
    }
    *out = EsBuffer {
        buffer,
        mapped: allocation
            .mapped_ptr()
            .map_or(std::ptr::null_mut(), |p| p.as_ptr()),
        size: allocation.size(),
        allocation: Box::into_raw(Box::new(allocation)).cast(),
    };
    LIVE.fetch_add(1, Ordering::SeqCst);
    vk::Result::SUCCESS
}

/// `EsAllocatorCallbacks.destroy_buffer`.
unsafe extern "C" fn destroy_buffer(user_data: *mut c_void, buffer: *const EsBuffer) {
    // SAFETY: our user data and a buffer `create_buffer` made.
    let (host, buffer) = unsafe { (&mut *(user_data as *mut CallbackHost), &*buffer) };
    // SAFETY: made by `Box::into_raw` in `create_buffer`.
    let allocation = unsafe { Box::from_raw(buffer.allocation as *mut Allocation) };
    // SAFETY: the library no longer uses it.
    unsafe { host.device.destroy_buffer(buffer.buffer, None) };
    // SAFETY: the host's allocator, not used elsewhere during the call.
    let _ = unsafe { &mut *host.allocator }.free(*allocation);
    LIVE.fetch_sub(1, Ordering::SeqCst);
    debug_assert!(!buffer.buffer.is_null());
}
