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

/// The error of a failed allocation of `what`.
pub(crate) fn allocation_error(what: &str, error: gpu_allocator::AllocationError) -> Error {
    match error {
        gpu_allocator::AllocationError::OutOfMemory => Error::OutOfMemory {
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

// SAFETY: memory comes from `allocate` with the buffer's own requirements and is bound to it;
// `CpuToGpu` and `GpuToCpu` memory is host-visible, host-coherent and persistently mapped
// by `gpu-allocator` (its `mapped_ptr` covers the allocation).
unsafe impl MemoryAllocator for Allocator {
    fn allocate_buffer_memory(
        &mut self,
        device: &ash::Device,
        buffer: vk::Buffer,
        name: &str,
        usage: MemoryUse,
    ) -> Result<BufferMemory> {
        // SAFETY: the caller made `buffer` from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocation = self
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: location(usage),
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|e| allocation_error(name, e))?;
        // SAFETY: memory and offset come from an allocation made for these requirements.
        let bound =
            unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) };
        if let Err(result) = bound {
            if let Err(e) = self.free(allocation) {
                log::error!("freeing {name}: {e}");
            }
            return Err(Error::vulkan("vkBindBufferMemory", result));
        }
        let mapped = allocation.mapped_ptr().map(|p| p.cast::<u8>());
        if usage.mapped() && mapped.is_none() {
            if let Err(e) = self.free(allocation) {
                log::error!("freeing {name}: {e}");
            }
            return Err(Error::Allocation {
                what: name.to_string(),
                reason: "host-visible memory came back unmapped".into(),
            });
        }
        let size = allocation.size();
        // SAFETY: gpu-allocator maps host-visible memory for the allocation's lifetime, and
        // its `CpuToGpu` and `GpuToCpu` memory types are host-coherent.
        Ok(unsafe { BufferMemory::new(allocation, size, mapped) })
    }

    fn free_buffer_memory(&mut self, memory: BufferMemory) -> Result<()> {
        let allocation = memory.into_allocation::<Allocation>().map_err(|_| {
            Error::invalid(
                "free_buffer_memory",
                "the memory came from another allocator",
            )
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
    }
}
