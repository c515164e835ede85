//! A buffer and its memory, owned together and freed together.

use ash::vk;

use crate::allocator::{BufferMemory, MemoryAllocator, MemoryUse};
use crate::error::{Error, Result};

/// A `VkBuffer` bound to memory of its own from the host's allocator. Free it with
/// [`GpuBuffer::destroy`]; dropping it without that leaks and is logged as an error (it
/// cannot free: it holds no allocator).
pub struct GpuBuffer {
    buffer: vk::Buffer,
    memory: Option<BufferMemory>,
    size: vk::DeviceSize,
    name: &'static str,
}

impl GpuBuffer {
    /// Creates a buffer of `size` bytes (at least 1) with memory for `memory_use`.
    pub fn new(
        device: &ash::Device,
        allocator: &mut dyn MemoryAllocator,
        name: &'static str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        memory_use: MemoryUse,
    ) -> Result<Self> {
        let size = size.max(1);
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: the renderer's device and a valid create info; the buffer goes back through
        // `destroy`.
        let (buffer, memory) = unsafe { allocator.create_buffer(device, &info, name, memory_use) }?;
        Ok(Self {
            buffer,
            memory: Some(memory),
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

    /// Bytes of memory the allocator gave it (at least `size`).
    pub fn memory_bytes(&self) -> u64 {
        self.memory.as_ref().map_or(0, BufferMemory::size)
    }

    /// The mapped bytes, for host-visible buffers.
    #[cfg(feature = "offscreen")]
    pub fn mapped(&self) -> Option<&[u8]> {
        self.memory.as_ref()?.mapped()
    }

    /// The mapped bytes for writing, for host-visible buffers.
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        self.memory.as_mut()?.mapped_mut()
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&mut self, bytes: &[u8]) -> Result<()> {
        let name = self.name;
        let dst = self.mapped_mut().ok_or_else(|| Error::Allocation {
            what: name.to_string(),
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
    pub unsafe fn destroy(mut self, device: &ash::Device, allocator: &mut dyn MemoryAllocator) {
        if let Some(memory) = self.memory.take() {
            // SAFETY: caller contract: the allocator made the buffer with this memory, and no
            // pending work uses it.
            if let Err(e) = unsafe { allocator.destroy_buffer(device, self.buffer, memory) } {
                log::error!("freeing {}: {e}", self.name);
            }
        }
    }
}

impl Drop for GpuBuffer {
    fn drop(&mut self) {
        if self.memory.is_some() {
            log::error!("buffer '{}' dropped without destroy(): leaked", self.name);
        }
    }
}
