//! Buffers with gpu-allocator memory, and the allocation shared with images.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::{fail, Host, HostResult};

/// Memory for an image or a buffer (`linear`) with `requirements`, at `location`.
pub(crate) fn allocate(
    allocator: &mut Allocator,
    name: &str,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> HostResult<Allocation> {
    allocator
        .allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .map_err(fail(if linear {
            "gpu_allocator allocate (buffer)"
        } else {
            "gpu_allocator allocate (image)"
        }))
}

/// A buffer and its memory (missing after a failed allocation).
pub(crate) struct OwnedBuffer {
    pub(crate) buffer: vk::Buffer,
    allocation: Option<Allocation>,
}

impl OwnedBuffer {
    /// A buffer of `size` bytes with memory at `location` (host-visible ones are mapped).
    pub(crate) fn new(
        host: &mut Host,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> HostResult<OwnedBuffer> {
        let (device, allocator) = host.device_and_allocator();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let buffer =
            unsafe { device.create_buffer(&info, None) }.map_err(fail("vkCreateBuffer"))?;
        let mut owned = OwnedBuffer {
            buffer,
            allocation: None,
        };
        match owned.bind(device, allocator, name, location) {
            Ok(()) => Ok(owned),
            Err(e) => {
                owned.destroy(device, allocator);
                Err(e)
            }
        }
    }

    fn bind(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &str,
        location: MemoryLocation,
    ) -> HostResult<()> {
        // SAFETY: the buffer was created from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(self.buffer) };
        let allocation = allocate(allocator, name, requirements, location, true)?;
        // SAFETY: the allocation satisfies the buffer's requirements and is freed only after
        // the buffer is destroyed (in `destroy`).
        let bound = unsafe {
            device.bind_buffer_memory(self.buffer, allocation.memory(), allocation.offset())
        };
        self.allocation = Some(allocation);
        bound.map_err(fail("vkBindBufferMemory"))
    }

    /// The buffer's bytes, for a host-visible buffer.
    pub(crate) fn mapped(&self) -> HostResult<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(Allocation::mapped_slice)
            .ok_or_else(|| "the buffer is not host-mapped".to_string())
    }

    /// The buffer's bytes to write, for a host-visible buffer.
    pub(crate) fn mapped_mut(&mut self) -> HostResult<&mut [u8]> {
        self.allocation
            .as_mut()
            .and_then(Allocation::mapped_slice_mut)
            .ok_or_else(|| "the buffer is not host-mapped".to_string())
    }

    /// Destroys the buffer and frees its memory. The GPU must be done with it.
    pub(crate) fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: the caller guarantees the GPU no longer uses the buffer; buffer before memory.
        unsafe { device.destroy_buffer(self.buffer, None) };
        if let Some(allocation) = self.allocation {
            let _ = allocator.free(allocation);
        }
    }
}
