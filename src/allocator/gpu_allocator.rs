//! [`MemoryAllocator`] for `gpu_allocator::vulkan::Allocator`.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use super::{BufferMemory, MemoryAllocator, MemoryUse};
use crate::error::{Error, Result};

/// Where `gpu-allocator` places memory for `usage`.
fn location(usage: MemoryUse) -> MemoryLocation {
    match usage {
        MemoryUse::GpuOnly => MemoryLocation::GpuOnly,
        MemoryUse::Upload => MemoryLocation::CpuToGpu,
        MemoryUse::Readback => MemoryLocation::GpuToCpu,
    }
}

/// The error of a failed allocation of `what`. Mapping a new memory block fails only where
/// the driver runs out of memory for it (`vkMapMemory` has no other errors but
/// `VK_ERROR_MEMORY_MAP_FAILED`, address space), so that is out of memory too.
pub(crate) fn allocation_error(what: &str, error: gpu_allocator::AllocationError) -> Error {
    match error {
        gpu_allocator::AllocationError::OutOfMemory
        | gpu_allocator::AllocationError::FailedToMap(_) => Error::OutOfMemory {
            what: what.to_string(),
            device: true,
            reason: error.to_string(),
        },
        error => Error::Allocation {
            what: what.to_string(),
            reason: error.to_string(),
        },
    }
}

// SAFETY: each buffer is made from the caller's create info and gets memory from `allocate`
// with the buffer's own requirements, bound to it; `CpuToGpu` and `GpuToCpu` memory is
// host-visible, host-coherent and persistently mapped by `gpu-allocator` (its `mapped_ptr`
// covers the allocation).
unsafe impl MemoryAllocator for Allocator {
    unsafe fn create_buffer(
        &mut self,
        device: &ash::Device,
        info: &vk::BufferCreateInfo<'_>,
        name: &str,
        usage: MemoryUse,
    ) -> Result<(vk::Buffer, BufferMemory)> {
        // SAFETY: the caller's device and create info; the buffer is destroyed on every
        // failure below, or later by `destroy_buffer`.
        let buffer = unsafe { device.create_buffer(info, None) }
            .map_err(|result| Error::creating(name, "vkCreateBuffer", result))?;
        let destroy = |device: &ash::Device| {
            // SAFETY: the buffer is unused: nothing was recorded with it.
            unsafe { device.destroy_buffer(buffer, None) }
        };
        // SAFETY: `buffer` was just made from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocation = match self.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: location(usage),
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(allocation) => allocation,
            Err(e) => {
                destroy(device);
                return Err(allocation_error(name, e));
            }
        };
        // SAFETY: memory and offset come from an allocation made for these requirements.
        let bound =
            unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) };
        let mapped = allocation.mapped_ptr().map(|p| p.cast::<u8>());
        let failure = match bound {
            Err(result) => Some(Error::creating(name, "vkBindBufferMemory", result)),
            Ok(()) if usage.mapped() && mapped.is_none() => Some(Error::Allocation {
                what: name.to_string(),
                reason: "host-visible memory came back unmapped".into(),
            }),
            Ok(()) => None,
        };
        if let Some(failure) = failure {
            destroy(device);
            if let Err(e) = self.free(allocation) {
                log::error!("freeing {name}: {e}");
            }
            return Err(failure);
        }
        let size = allocation.size();
        // SAFETY: gpu-allocator maps host-visible memory for the allocation's lifetime, and
        // its `CpuToGpu` and `GpuToCpu` memory types are host-coherent.
        Ok((buffer, unsafe {
            BufferMemory::new(allocation, size, mapped)
        }))
    }

    unsafe fn destroy_buffer(
        &mut self,
        device: &ash::Device,
        buffer: vk::Buffer,
        memory: BufferMemory,
    ) -> Result<()> {
        // SAFETY: caller contract: this allocator's buffer, unused by pending work. It goes
        // first, so even memory of the wrong kind below leaves no buffer behind.
        unsafe { device.destroy_buffer(buffer, None) };
        let allocation = memory.into_allocation::<Allocation>().map_err(|_| {
            Error::invalid("destroy_buffer", "the memory came from another allocator")
        })?;
        self.free(allocation).map_err(|e| Error::Allocation {
            what: "free".to_string(),
            reason: e.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn running_out_is_out_of_memory() {
        let error = allocation_error("instances", gpu_allocator::AllocationError::OutOfMemory);
        assert!(matches!(error, Error::OutOfMemory { .. }), "{error}");
        let unmapped =
            gpu_allocator::AllocationError::FailedToMap("ERROR_OUT_OF_HOST_MEMORY".into());
        let error = allocation_error("staging", unmapped);
        assert!(matches!(error, Error::OutOfMemory { .. }), "{error}");
        assert!(error.to_string().contains("staging"), "{error}");
    }
}
