//! [`MemoryAllocator`] for `vk_mem::Allocator` (VMA). VMA's allocations carry no name here:
//! vk-mem 0.5 does not expose `vmaSetAllocationName`.

use std::ptr::NonNull;

use ash::vk;
use vk_mem::{
    Alloc, Allocation, AllocationCreateFlags, AllocationCreateInfo, Allocator, MemoryUsage,
};

use super::{BufferMemory, MemoryAllocator, MemoryUse};
use crate::error::{Error, Result};

/// VMA's flags and memory properties for `usage`. `vmaAllocateMemoryForBuffer` does not see
/// the buffer's usage, so VMA's `Auto` usages are refused there: the properties are named.
/// Host-visible memory stays mapped (`MAPPED`) and is coherent, so no flush or invalidate is
/// ever needed.
fn create_info(usage: MemoryUse) -> AllocationCreateInfo {
    use vk::MemoryPropertyFlags as Property;
    let host = Property::HOST_VISIBLE | Property::HOST_COHERENT;
    let (flags, required_flags, preferred_flags) = match usage {
        MemoryUse::GpuOnly => (
            AllocationCreateFlags::empty(),
            Property::empty(),
            Property::DEVICE_LOCAL,
        ),
        MemoryUse::Upload => (AllocationCreateFlags::MAPPED, host, Property::empty()),
        MemoryUse::Readback => (AllocationCreateFlags::MAPPED, host, Property::HOST_CACHED),
    };
    AllocationCreateInfo {
        flags,
        usage: MemoryUsage::Unknown,
        required_flags,
        preferred_flags,
        ..AllocationCreateInfo::default()
    }
}

fn allocation_error(what: &str, result: vk::Result) -> Error {
    match result {
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
            Error::OutOfMemory {
                what: what.to_string(),
                device: result == vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
                reason: format!("VMA: {result:?}"),
            }
        }
        result => Error::Allocation {
            what: what.to_string(),
            reason: format!("VMA: {result:?}"),
        },
    }
}

// SAFETY: `vmaAllocateMemoryForBuffer` allocates for the buffer's own requirements and
// `vmaBindBufferMemory` binds it; host-visible uses require HOST_VISIBLE | HOST_COHERENT and
// are created MAPPED, so VMA keeps them mapped for the allocation's lifetime and reports the
// mapping, which covers the allocation's size.
unsafe impl MemoryAllocator for Allocator {
    fn allocate_buffer_memory(
        &mut self,
        _device: &ash::Device,
        buffer: vk::Buffer,
        name: &str,
        usage: MemoryUse,
    ) -> Result<BufferMemory> {
        // SAFETY: `buffer` is a valid, unbound buffer of this allocator's device (the
        // trait's caller contract).
        let mut allocation =
            unsafe { self.allocate_memory_for_buffer(buffer, &create_info(usage)) }
                .map_err(|e| allocation_error(name, e))?;
        // SAFETY: the allocation was made for `buffer`.
        if let Err(result) = unsafe { self.bind_buffer_memory(&allocation, buffer) } {
            // SAFETY: the allocation is unused.
            unsafe { self.free_memory(&mut allocation) };
            return Err(Error::vulkan("vmaBindBufferMemory", result));
        }
        let info = self.get_allocation_info(&allocation);
        let mapped = NonNull::new(info.mapped_data.cast::<u8>());
        if usage.mapped() && mapped.is_none() {
            // SAFETY: the allocation is unused (the buffer's owner destroys the buffer).
            unsafe { self.free_memory(&mut allocation) };
            return Err(Error::Allocation {
                what: name.to_string(),
                reason: "VMA: host-visible memory came back unmapped".into(),
            });
        }
        // SAFETY: created MAPPED and HOST_COHERENT (see `create_info`): mapped for the
        // allocation's lifetime, `info.size` bytes.
        Ok(unsafe { BufferMemory::new(allocation, info.size, mapped) })
    }

    fn free_buffer_memory(&mut self, memory: BufferMemory) -> Result<()> {
        let mut allocation = memory.into_allocation::<Allocation>().map_err(|_| {
            Error::invalid(
                "free_buffer_memory",
                "the memory came from another allocator",
            )
        })?;
        // SAFETY: the allocation came from this allocator and its buffer is destroyed.
        unsafe { self.free_memory(&mut allocation) };
        Ok(())
    }
}
