//! GPU memory from the host: callbacks that create and destroy a buffer with its memory (as
//! `vmaCreateBuffer` and `vmaDestroyBuffer` do), or the library's own allocator when the host
//! gives none.

use std::ffi::{c_char, c_void, CString};
use std::ptr::NonNull;

use ash::vk::{
    self, Buffer as VkBuffer, BufferCreateInfo as VkBufferCreateInfo, Result as VkResult,
};
use ellipsoid_splat::{BufferMemory, MemoryUse};
use ellipsoid_splat::{Error, MemoryAllocator, Result};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::device::LoadedDevice;
use crate::status::Failure;

/// What a buffer's memory is for.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EsMemoryUse {
    /// Read and written by the GPU only: device-local where the device has it.
    GpuOnly = 0,
    /// Written by the CPU, read by the GPU: host-visible, host-coherent, mapped for as long
    /// as the buffer lives.
    Upload = 1,
    /// Written by the GPU, read by the CPU: host-visible, host-coherent, mapped.
    Readback = 2,
}

impl From<MemoryUse> for EsMemoryUse {
    fn from(usage: MemoryUse) -> Self {
        match usage {
            MemoryUse::GpuOnly => EsMemoryUse::GpuOnly,
            MemoryUse::Upload => EsMemoryUse::Upload,
            MemoryUse::Readback => EsMemoryUse::Readback,
        }
    }
}

/// A buffer the host's allocator made: the buffer, the allocator's handle of its memory (a
/// `VmaAllocation`, or anything the host needs to free it), the mapping of host-visible
/// memory, and the memory's size in bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsBuffer {
    /// The buffer, with memory bound.
    pub buffer: VkBuffer,
    /// The host's handle of the buffer's memory, handed back to `destroy_buffer`.
    pub allocation: *mut c_void,
    /// The first mapped byte, for `ES_MEMORY_USE_UPLOAD` and `ES_MEMORY_USE_READBACK`
    /// (required there); may be null for `ES_MEMORY_USE_GPU_ONLY`.
    pub mapped: *mut c_void,
    /// The memory's size in bytes (at least the buffer's size).
    pub size: u64,
}

/// Creates a buffer from `info` with memory for `usage` bound to it (`vmaCreateBuffer` with
/// the usage's memory properties; `name` is for the host's debugging and memory budget), and
/// fills `out`. Returns `VK_SUCCESS` or the failure's `VkResult`.
pub type EsCreateBufferFn = Option<
    unsafe extern "C" fn(
        user_data: *mut c_void,
        info: *const VkBufferCreateInfo<'static>,
        usage: EsMemoryUse,
        name: *const c_char,
        out: *mut EsBuffer,
    ) -> VkResult,
>;

/// Destroys a buffer `create_buffer` made, and frees its memory (`vmaDestroyBuffer`). The GPU
/// no longer uses it.
pub type EsDestroyBufferFn =
    Option<unsafe extern "C" fn(user_data: *mut c_void, buffer: *const EsBuffer)>;

/// The host's allocator: both callbacks, or neither (the library then allocates with its own
/// allocator). They are called on the thread calling into the renderer (two renderers on two
/// threads may call them at once with the same `user_data`). They must return, not unwind or
/// `longjmp`, and must not call into the renderer that called them. After a failure the
/// library ignores `out`: the callback cleans up what it made. A callback that reports
/// success with a null buffer, no mapping where one is needed, or less memory than asked
/// for fails the call (`ES_STATUS_ERROR_VULKAN`) and what it made is handed back.
#[repr(C)]
pub struct EsAllocatorCallbacks {
    /// `sizeof(EsAllocatorCallbacks)`.
    pub struct_size: u32,
    /// Passed to both callbacks as their first argument.
    pub user_data: *mut c_void,
    /// Creates a buffer with its memory.
    pub create_buffer: EsCreateBufferFn,
    /// Destroys a buffer and frees its memory.
    pub destroy_buffer: EsDestroyBufferFn,
}

/// The size of the first version of [`EsAllocatorCallbacks`] (64-bit targets), frozen.
pub(crate) const ALLOCATOR_CALLBACKS_V1: usize = 32;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsAllocatorCallbacks>() == ALLOCATOR_CALLBACKS_V1);

/// The memory a callback gave, as the library keeps it.
struct HostAllocation(EsBuffer);

// SAFETY: the host's handles are plain values the library only hands back to the host, on
// the thread calling into the renderer (the renderer is used from one thread at a time).
unsafe impl Send for HostAllocation {}
// SAFETY: as above.
unsafe impl Sync for HostAllocation {}

/// The host's callbacks as a [`MemoryAllocator`].
pub(crate) struct HostCallbacks {
    user_data: *mut c_void,
    create: unsafe extern "C" fn(
        *mut c_void,
        *const VkBufferCreateInfo<'static>,
        EsMemoryUse,
        *const c_char,
        *mut EsBuffer,
    ) -> VkResult,
    destroy: unsafe extern "C" fn(*mut c_void, *const EsBuffer),
}

// SAFETY: the host's callbacks promise (by the header's contract) a buffer made from the
// create info with memory bound that meets its requirements and usage, host-visible,
// coherent and mapped for the upload and readback uses; `create_buffer` checks the mapping
// and the size it reports.
unsafe impl MemoryAllocator for HostCallbacks {
    unsafe fn create_buffer(
        &mut self,
        _device: &ash::Device,
        info: &vk::BufferCreateInfo<'_>,
        name: &str,
        usage: MemoryUse,
    ) -> Result<(vk::Buffer, BufferMemory)> {
        let c_name = CString::new(name.replace('\0', " ")).unwrap_or_default();
        let mut out = EsBuffer {
            buffer: VkBuffer::null(),
            allocation: std::ptr::null_mut(),
            mapped: std::ptr::null_mut(),
            size: 0,
        };
        let info: *const VkBufferCreateInfo<'_> = info;
        // SAFETY: the host's callback with a valid create info, a NUL-terminated name and an
        // output it may write; the lifetime is erased only for the call.
        let result = unsafe {
            (self.create)(
                self.user_data,
                info.cast(),
                usage.into(),
                c_name.as_ptr(),
                &mut out,
            )
        };
        if result != VkResult::SUCCESS {
            return Err(Error::creating(
                name,
                "EsAllocatorCallbacks.create_buffer",
                result,
            ));
        }
        // SAFETY: `info` is the caller's, read again for its size.
        let wanted = unsafe { (*info).size };
        let problem = if out.buffer == VkBuffer::null() {
            Some("returned VK_SUCCESS and a null buffer".to_string())
        } else if usage != MemoryUse::GpuOnly && out.mapped.is_null() {
            Some(format!("gave {name} ({usage:?}) no mapping"))
        } else if out.size < wanted {
            Some(format!(
                "gave {name} {} bytes, {wanted} asked for",
                out.size
            ))
        } else {
            None
        };
        if let Some(problem) = problem {
            if out.buffer != VkBuffer::null() || !out.allocation.is_null() {
                // SAFETY: what the host's callback made, unused: handed back.
                unsafe { (self.destroy)(self.user_data, &out) };
            }
            return Err(Error::Allocation {
                what: name.to_string(),
                reason: format!("the host's create_buffer {problem}"),
            });
        }
        let mapped = NonNull::new(out.mapped.cast::<u8>());
        // SAFETY: the host's contract: host-visible uses are coherent and mapped for the
        // allocation's lifetime, `out.size` bytes.
        let memory = unsafe { BufferMemory::new(HostAllocation(out), out.size, mapped) };
        Ok((out.buffer, memory))
    }

    unsafe fn destroy_buffer(
        &mut self,
        _device: &ash::Device,
        _buffer: vk::Buffer,
        memory: BufferMemory,
    ) -> Result<()> {
        let HostAllocation(buffer) = memory.into_allocation::<HostAllocation>().map_err(|_| {
            Error::invalid("destroy_buffer", "the memory came from another allocator")
        })?;
        // SAFETY: the host's callback with a buffer its create_buffer made, no longer used.
        unsafe { (self.destroy)(self.user_data, &buffer) };
        Ok(())
    }
}

/// Where a renderer's memory comes from.
pub(crate) enum RendererMemory {
    /// The host's callbacks.
    Host(HostCallbacks),
    /// The library's own allocator on the host's device.
    Own(Box<Allocator>),
}

impl RendererMemory {
    /// The host's callbacks, or (`callbacks` null) an allocator of the library's own.
    ///
    /// # Safety
    /// A non-null `callbacks` points at a valid `EsAllocatorCallbacks`; `device` is loaded.
    pub unsafe fn new(
        callbacks: Option<&EsAllocatorCallbacks>,
        device: &LoadedDevice,
    ) -> std::result::Result<Self, Failure> {
        match callbacks {
            Some(callbacks) => match (callbacks.create_buffer, callbacks.destroy_buffer) {
                (Some(create), Some(destroy)) => Ok(RendererMemory::Host(HostCallbacks {
                    user_data: callbacks.user_data,
                    create,
                    destroy,
                })),
                (None, None) => Self::own(device),
                _ => Err(Failure::invalid(
                    "EsAllocatorCallbacks",
                    "needs both create_buffer and destroy_buffer, or neither",
                )),
            },
            None => Self::own(device),
        }
    }

    /// An allocator of the library's own on the host's device.
    fn own(device: &LoadedDevice) -> std::result::Result<Self, Failure> {
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: device.instance.clone(),
            device: device.device.clone(),
            physical_device: device.physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| {
            Failure::from(Error::Allocation {
                what: "the library's allocator".into(),
                reason: e.to_string(),
            })
        })?;
        Ok(RendererMemory::Own(Box::new(allocator)))
    }

    /// The allocator the renderer's calls take.
    pub fn allocator(&mut self) -> &mut dyn MemoryAllocator {
        match self {
            RendererMemory::Host(callbacks) => callbacks,
            RendererMemory::Own(allocator) => allocator.as_mut(),
        }
    }
}
