//! A buffer and its memory, owned together and freed together.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result, VkCall};

/// A `VkBuffer` bound to its own allocation. Free it with [`GpuBuffer::destroy`]; dropping it
/// without that leaks and is logged as an error (it cannot free: it holds no allocator).
pub struct GpuBuffer {
    buffer: vk::Buffer,
    allocation: Option<Allocation>,
    size: vk::DeviceSize,
    name: &'static str,
}

impl GpuBuffer {
    /// Creates a buffer of `size` bytes (at least 1) in `location`.
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &'static str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let size = size.max(1);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info; the buffer is destroyed by `destroy` or on error below.
        let buffer = unsafe { device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        // SAFETY: `buffer` was just created from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocation = allocator.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the buffer is unused and unbound.
                unsafe { device.destroy_buffer(buffer, None) };
                return Err(Error::allocation(name, e));
            }
        };
        // SAFETY: memory and offset come from an allocation made for these requirements.
        let bound =
            unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) };
        if let Err(result) = bound {
            // SAFETY: nothing uses the buffer yet.
            unsafe { device.destroy_buffer(buffer, None) };
            if let Err(e) = allocator.free(allocation) {
                log::error!("freeing {name}: {e}");
            }
            return Err(Error::vulkan("vkBindBufferMemory", result));
        }
        Ok(Self {
            buffer,
            allocation: Some(allocation),
            size,
            name,
        })
    }

    /// The handle.
    pub fn handle(&self) -> vk::Buffer {
        self.buffer
    }

    /// Size in bytes.
    pub fn size(&self) -> vk::DeviceSize {
        self.size
    }

    /// The mapped bytes, for host-visible buffers.
    #[cfg(feature = "offscreen")]
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.as_ref()?.mapped_slice()
    }

    /// The mapped bytes for writing, for host-visible buffers.
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.allocation.as_mut()?.mapped_slice_mut()
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&mut self, bytes: &[u8]) -> Result<()> {
        let name = self.name;
        let dst = self.mapped_mut().ok_or_else(|| Error::Allocation {
            what: name,
            reason: "buffer is not host-visible".into(),
        })?;
        if bytes.len() > dst.len() {
            return Err(Error::invalid(
                name,
                format!("{} bytes do not fit in {}", bytes.len(), dst.len()),
            ));
        }
        dst[..bytes.len()].copy_from_slice(bytes);
        Ok(())
    }

    /// Destroys the buffer and frees its memory (a failure to free is logged: the buffer is
    /// gone either way).
    ///
    /// # Safety
    /// `device` and `allocator` made the buffer, and no pending GPU work uses it.
    pub unsafe fn destroy(mut self, device: &ash::Device, allocator: &mut Allocator) {
        if let Some(allocation) = self.allocation.take() {
            // SAFETY: caller contract; the buffer is owned here.
            unsafe { device.destroy_buffer(self.buffer, None) };
            if let Err(e) = allocator.free(allocation) {
                log::error!("freeing {}: {e}", self.name);
            }
        }
    }
}

impl Drop for GpuBuffer {
    fn drop(&mut self) {
        if self.allocation.is_some() {
            log::error!("buffer '{}' dropped without destroy(): leaked", self.name);
        }
    }
}
