//! [`MemoryAllocator`] for `vk_mem::Allocator` (VMA). VMA's allocations carry no name here:
//! vk-mem 0.5 does not expose `vmaSetAllocationName`.

use std::ptr::NonNull;

use ash::vk;
use vk_mem::{
    Alloc, Allocation, AllocationCreateFlags, AllocationCreateInfo, Allocator, MemoryUsage,
};

use super::{BufferMemory, MemoryAllocator, MemoryUse};
use crate::error::{Error, Result};

/// VMA's flags and memory properties for `usage`, named outright rather than left to VMA's
/// `Auto` usages, so both allocators place memory by the same rule.
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

// SAFETY: `vmaCreateBuffer` makes the buffer from the caller's create info and binds memory
// allocated for its requirements; host-visible uses require HOST_VISIBLE | HOST_COHERENT and are
// created MAPPED, so VMA keeps them mapped for the allocation's lifetime and reports the mapping,
// which covers the allocation's size.
unsafe impl MemoryAllocator for Allocator {
    unsafe fn create_buffer(
        &mut self,
        _device: &ash::Device,
        info: &vk::BufferCreateInfo<'_>,
        name: &str,
        usage: MemoryUse,
    ) -> Result<(vk::Buffer, BufferMemory)> {
        // SAFETY: a valid create info for this allocator's device (the caller's contract).
        let (buffer, mut allocation) =
            unsafe { Alloc::create_buffer(self, info, &create_info(usage)) }
                .map_err(|e| allocation_error(name, e))?;
        let info = self.get_allocation_info(&allocation);
        let mapped = NonNull::new(info.mapped_data.cast::<u8>());
        if usage.mapped() && mapped.is_none() {
            // SAFETY: the buffer is unused.
            unsafe { Allocator::destroy_buffer(self, buffer, &mut allocation) };
            return Err(Error::Allocation {
                what: name.to_string(),
                reason: "VMA: host-visible memory came back unmapped".into(),
            });
        }
        // SAFETY: created MAPPED and HOST_COHERENT (see `create_info`): mapped for the
        // allocation's lifetime, `info.size` bytes.
        Ok((buffer, unsafe {
            BufferMemory::new(allocation, info.size, mapped)
        }))
    }

    unsafe fn destroy_buffer(
        &mut self,
        device: &ash::Device,
        buffer: vk::Buffer,
        memory: BufferMemory,
    ) -> Result<()> {
        match memory.into_allocation::<Allocation>() {
            Ok(mut allocation) => {
                // SAFETY: caller contract: made together by this allocator, unused by pending
                // work.
                unsafe { Allocator::destroy_buffer(self, buffer, &mut allocation) };
                Ok(())
            }
            Err(_) => {
                // SAFETY: caller contract: unused by pending work; the buffer goes even though
                // its memory is of another allocator's kind.
                unsafe { device.destroy_buffer(buffer, None) };
                Err(Error::invalid(
                    "destroy_buffer",
                    "the memory came from another allocator",
                ))
            }
        }
    }
}
