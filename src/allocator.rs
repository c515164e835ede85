//! The host's GPU memory allocator as the renderer uses it ([`MemoryAllocator`], whose
//! documentation is the contract), and its implementations for gpu-allocator and vk-mem.

#[cfg(feature = "gpu-allocator")]
mod gpu_allocator;
#[cfg(feature = "gpu-allocator")]
#[cfg(feature = "offscreen")]
pub(crate) use self::gpu_allocator::allocation_error as gpu_allocation_error;
#[cfg(feature = "vk-mem")]
mod vk_mem;

use std::any::Any;
use std::ptr::NonNull;

use ash::vk;

use crate::error::Result;

/// What a buffer's memory is used for. Deliberately exhaustive: an allocator must place every
/// use, so a new one would be a breaking change anyway.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryUse {
    /// Read and written by the GPU only (instances, culling and set-up buffers): device-local
    /// where the device has it.
    GpuOnly,
    /// Written by the CPU, read by the GPU (staging, the benchmark's pixel lists):
    /// host-visible, host-coherent, mapped for as long as it lives.
    Upload,
    /// Written by the GPU, read by the CPU (the benchmark's counters): host-visible,
    /// host-coherent, mapped for as long as it lives.
    Readback,
}

impl MemoryUse {
    /// Whether the CPU reads or writes the memory through its mapping.
    pub fn mapped(self) -> bool {
        self != MemoryUse::GpuOnly
    }
}

/// One buffer's memory, as the host's allocator gave it: the allocator's own record of the
/// allocation (handed back to [`MemoryAllocator::destroy_buffer`]), its size, and for
/// host-visible uses where it is mapped.
pub struct BufferMemory {
    allocation: Box<dyn Any + Send + Sync>,
    size: u64,
    mapped: Option<NonNull<u8>>,
}

// SAFETY: the mapping is host memory that lives as long as the allocation; it is only read
// through `&self` and written through `&mut self`, as the allocators' own allocation types
// (which are `Send + Sync`) allow.
unsafe impl Send for BufferMemory {}
// SAFETY: as above.
unsafe impl Sync for BufferMemory {}

impl BufferMemory {
    /// Memory of `size` bytes (the allocation's, at least the buffer's requirement) kept as
    /// `allocation`; `mapped` points at its first byte when it is host-visible and mapped.
    ///
    /// # Safety
    /// `mapped`, when given, points at `size` bytes of host-coherent memory mapped for as
    /// long as `allocation` lives, which nothing else writes while this value exists.
    pub unsafe fn new(
        allocation: impl Any + Send + Sync,
        size: u64,
        mapped: Option<NonNull<u8>>,
    ) -> Self {
        Self {
            allocation: Box::new(allocation),
            size,
            mapped,
        }
    }

    /// The allocation's size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// The allocator's record of the allocation, if it is a `T` (else this memory back).
    pub fn into_allocation<T: Any>(self) -> std::result::Result<T, Self> {
        let Self {
            allocation,
            size,
            mapped,
        } = self;
        match allocation.downcast::<T>() {
            Ok(allocation) => Ok(*allocation),
            Err(allocation) => Err(Self {
                allocation,
                size,
                mapped,
            }),
        }
    }

    /// The mapped bytes, for host-visible memory.
    pub fn mapped(&self) -> Option<&[u8]> {
        // SAFETY: `new`'s contract: `size` mapped bytes that live with the allocation.
        self.mapped
            .map(|p| unsafe { std::slice::from_raw_parts(p.as_ptr(), self.size as usize) })
    }

    /// The mapped bytes for writing, for host-visible memory.
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        // SAFETY: as `mapped`; `&mut self` makes the access exclusive.
        self.mapped
            .map(|p| unsafe { std::slice::from_raw_parts_mut(p.as_ptr(), self.size as usize) })
    }
}

/// The host's GPU memory allocator. The renderer asks it for every buffer it needs, with
/// memory bound (as `vmaCreateBuffer` makes them) and named, and gives each back to it, so the
/// host's memory budget sees all of it (`gpu_memory_bytes()` counts the sizes it reports); every
/// call passes the same device and allocator. The renderer needs three kinds of memory
/// ([`MemoryUse`]) and nothing else from an allocator; every method that allocates or frees
/// takes `&mut dyn MemoryAllocator`.
///
/// Implemented for `gpu_allocator::vulkan::Allocator` (feature `gpu-allocator`, on by default)
/// and for `vk_mem::Allocator` (feature `vk-mem`, VMA 0.5: explicit required and preferred
/// property flags rather than VMA's usage guesses, mapped allocations for the host-visible
/// uses); a host on another allocator implements it itself.
///
/// # Safety
/// `create_buffer` returns a buffer made from `info` on `device` with memory bound that meets
/// the buffer's requirements and `usage`: for [`MemoryUse::Upload`] and [`MemoryUse::Readback`]
/// host-visible and host-coherent memory, mapped for as long as it lives, with its mapping in
/// the returned [`BufferMemory`]. The renderer relies on this for memory safety.
pub unsafe trait MemoryAllocator {
    /// Creates a buffer from `info` on `device` and binds memory for `usage` to it, under the
    /// name `name`.
    ///
    /// # Safety
    /// `device` is the allocator's device and `info` a valid create info.
    unsafe fn create_buffer(
        &mut self,
        device: &ash::Device,
        info: &vk::BufferCreateInfo<'_>,
        name: &str,
        usage: MemoryUse,
    ) -> Result<(vk::Buffer, BufferMemory)>;

    /// Destroys a buffer `create_buffer` made and frees its memory.
    ///
    /// # Safety
    /// `buffer` and `memory` came together from `create_buffer` of this allocator with
    /// `device`, and no pending GPU work uses them.
    unsafe fn destroy_buffer(
        &mut self,
        device: &ash::Device,
        buffer: vk::Buffer,
        memory: BufferMemory,
    ) -> Result<()>;
}
