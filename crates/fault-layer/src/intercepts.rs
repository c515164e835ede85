//! The device-level calls the layer intercepts: every call returning a `VkResult` that the
//! renderer, its allocators and the test hosts make. Each asks [`decide`] and then passes the
//! call down, fails it, or acts out a lost device as its class says.

use std::ffi::{c_void, CStr};

use ash::vk::{self, Handle};

use crate::control::{decide, Class, Decision};
use crate::dispatch;

/// An intercept of class [`Class::Creates`]: fails without passing the call down when the
/// fault hits it. `$first` is the dispatchable handle the call is made on.
macro_rules! creates {
    ($fn_name:ident, $name:literal, $pfn:ty, $first:ident: $first_ty:ty $(, $arg:ident: $ty:ty)*) => {
        unsafe extern "system" fn $fn_name($first: $first_ty $(, $arg: $ty)*) -> vk::Result {
            if let Decision::Fail(result) = decide(Class::Creates, $name) {
                return result;
            }
            // SAFETY: a live handle of a device made through this layer; the call's own type.
            let next: $pfn = unsafe { dispatch::next($first.as_raw() as *const c_void, $name) };
            // SAFETY: the caller's arguments, passed down.
            unsafe { next($first $(, $arg)*) }
        }
    };
}

creates!(allocate_memory, c"vkAllocateMemory", vk::PFN_vkAllocateMemory,
    device: vk::Device, info: *const vk::MemoryAllocateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, memory: *mut vk::DeviceMemory);
creates!(map_memory, c"vkMapMemory", vk::PFN_vkMapMemory,
    device: vk::Device, memory: vk::DeviceMemory, offset: vk::DeviceSize, size: vk::DeviceSize,
    flags: vk::MemoryMapFlags, data: *mut *mut c_void);
creates!(bind_buffer_memory, c"vkBindBufferMemory", vk::PFN_vkBindBufferMemory,
    device: vk::Device, buffer: vk::Buffer, memory: vk::DeviceMemory, offset: vk::DeviceSize);
creates!(bind_image_memory, c"vkBindImageMemory", vk::PFN_vkBindImageMemory,
    device: vk::Device, image: vk::Image, memory: vk::DeviceMemory, offset: vk::DeviceSize);
creates!(create_buffer, c"vkCreateBuffer", vk::PFN_vkCreateBuffer,
    device: vk::Device, info: *const vk::BufferCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Buffer);
creates!(create_image, c"vkCreateImage", vk::PFN_vkCreateImage,
    device: vk::Device, info: *const vk::ImageCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Image);
creates!(create_image_view, c"vkCreateImageView", vk::PFN_vkCreateImageView,
    device: vk::Device, info: *const vk::ImageViewCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::ImageView);
creates!(create_buffer_view, c"vkCreateBufferView", vk::PFN_vkCreateBufferView,
    device: vk::Device, info: *const vk::BufferViewCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::BufferView);
creates!(create_sampler, c"vkCreateSampler", vk::PFN_vkCreateSampler,
    device: vk::Device, info: *const vk::SamplerCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Sampler);
creates!(create_shader_module, c"vkCreateShaderModule", vk::PFN_vkCreateShaderModule,
    device: vk::Device, info: *const vk::ShaderModuleCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::ShaderModule);
creates!(create_pipeline_layout, c"vkCreatePipelineLayout", vk::PFN_vkCreatePipelineLayout,
    device: vk::Device, info: *const vk::PipelineLayoutCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::PipelineLayout);
creates!(create_pipeline_cache, c"vkCreatePipelineCache", vk::PFN_vkCreatePipelineCache,
    device: vk::Device, info: *const vk::PipelineCacheCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::PipelineCache);
creates!(create_descriptor_set_layout, c"vkCreateDescriptorSetLayout",
    vk::PFN_vkCreateDescriptorSetLayout,
    device: vk::Device, info: *const vk::DescriptorSetLayoutCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::DescriptorSetLayout);
creates!(create_descriptor_pool, c"vkCreateDescriptorPool", vk::PFN_vkCreateDescriptorPool,
    device: vk::Device, info: *const vk::DescriptorPoolCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::DescriptorPool);
creates!(create_command_pool, c"vkCreateCommandPool", vk::PFN_vkCreateCommandPool,
    device: vk::Device, info: *const vk::CommandPoolCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::CommandPool);
creates!(reset_command_pool, c"vkResetCommandPool", vk::PFN_vkResetCommandPool,
    device: vk::Device, pool: vk::CommandPool, flags: vk::CommandPoolResetFlags);
creates!(begin_command_buffer, c"vkBeginCommandBuffer", vk::PFN_vkBeginCommandBuffer,
    cmd: vk::CommandBuffer, info: *const vk::CommandBufferBeginInfo<'_>);
creates!(end_command_buffer, c"vkEndCommandBuffer", vk::PFN_vkEndCommandBuffer,
    cmd: vk::CommandBuffer);
creates!(create_fence, c"vkCreateFence", vk::PFN_vkCreateFence,
    device: vk::Device, info: *const vk::FenceCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Fence);
creates!(reset_fences, c"vkResetFences", vk::PFN_vkResetFences,
    device: vk::Device, count: u32, fences: *const vk::Fence);
creates!(create_semaphore, c"vkCreateSemaphore", vk::PFN_vkCreateSemaphore,
    device: vk::Device, info: *const vk::SemaphoreCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Semaphore);
creates!(create_query_pool, c"vkCreateQueryPool", vk::PFN_vkCreateQueryPool,
    device: vk::Device, info: *const vk::QueryPoolCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::QueryPool);
creates!(create_render_pass, c"vkCreateRenderPass", vk::PFN_vkCreateRenderPass,
    device: vk::Device, info: *const vk::RenderPassCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::RenderPass);
creates!(create_framebuffer, c"vkCreateFramebuffer", vk::PFN_vkCreateFramebuffer,
    device: vk::Device, info: *const vk::FramebufferCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>, out: *mut vk::Framebuffer);

/// Calls that return several handles: on an injected failure every one is set to
/// `VK_NULL_HANDLE`, as the spec requires of a failed call.
///
/// # Safety
/// `out` points at `count` writable handles.
unsafe fn null_all<T: Handle>(out: *mut T, count: u32) {
    for k in 0..count as usize {
        // SAFETY: caller contract.
        unsafe { out.add(k).write(T::from_raw(0)) };
    }
}

unsafe extern "system" fn allocate_command_buffers(
    device: vk::Device,
    info: *const vk::CommandBufferAllocateInfo<'_>,
    out: *mut vk::CommandBuffer,
) -> vk::Result {
    if let Decision::Fail(result) = decide(Class::Creates, c"vkAllocateCommandBuffers") {
        // SAFETY: the caller's array holds `commandBufferCount` handles.
        unsafe { null_all(out, (*info).command_buffer_count) };
        return result;
    }
    let next: vk::PFN_vkAllocateCommandBuffers =
        // SAFETY: a live device made through this layer; the call's own type.
        unsafe { dispatch::next(device.as_raw() as *const c_void, c"vkAllocateCommandBuffers") };
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(device, info, out) }
}

unsafe extern "system" fn allocate_descriptor_sets(
    device: vk::Device,
    info: *const vk::DescriptorSetAllocateInfo<'_>,
    out: *mut vk::DescriptorSet,
) -> vk::Result {
    if let Decision::Fail(result) = decide(Class::Creates, c"vkAllocateDescriptorSets") {
        // SAFETY: the caller's array holds `descriptorSetCount` handles.
        unsafe { null_all(out, (*info).descriptor_set_count) };
        return result;
    }
    let next: vk::PFN_vkAllocateDescriptorSets =
        // SAFETY: a live device made through this layer; the call's own type.
        unsafe { dispatch::next(device.as_raw() as *const c_void, c"vkAllocateDescriptorSets") };
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(device, info, out) }
}

unsafe extern "system" fn create_graphics_pipelines(
    device: vk::Device,
    cache: vk::PipelineCache,
    count: u32,
    infos: *const vk::GraphicsPipelineCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::Pipeline,
) -> vk::Result {
    if let Decision::Fail(result) = decide(Class::Creates, c"vkCreateGraphicsPipelines") {
        // SAFETY: the caller's array holds `count` handles.
        unsafe { null_all(out, count) };
        return result;
    }
    let next: vk::PFN_vkCreateGraphicsPipelines =
        // SAFETY: a live device made through this layer; the call's own type.
        unsafe { dispatch::next(device.as_raw() as *const c_void, c"vkCreateGraphicsPipelines") };
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(device, cache, count, infos, allocator, out) }
}

unsafe extern "system" fn create_compute_pipelines(
    device: vk::Device,
    cache: vk::PipelineCache,
    count: u32,
    infos: *const vk::ComputePipelineCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    out: *mut vk::Pipeline,
) -> vk::Result {
    if let Decision::Fail(result) = decide(Class::Creates, c"vkCreateComputePipelines") {
        // SAFETY: the caller's array holds `count` handles.
        unsafe { null_all(out, count) };
        return result;
    }
    let next: vk::PFN_vkCreateComputePipelines =
        // SAFETY: a live device made through this layer; the call's own type.
        unsafe { dispatch::next(device.as_raw() as *const c_void, c"vkCreateComputePipelines") };
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(device, cache, count, infos, allocator, out) }
}

/// A lost device's submission with `fence`: nothing runs, but the fence is signalled (by an
/// empty submission, waited for here), so that waiting for it ends as on a real lost device.
/// A fence already signalled is left so (submitting with it is the caller's mistake, which
/// the layers below never see: the call is not passed on).
///
/// # Safety
/// `queue` is a live queue of a device made through this layer; `fence` is null or its, not
/// in use by a pending submission.
unsafe fn signal_lost(queue: vk::Queue, fence: vk::Fence) {
    let handle = queue.as_raw() as *const c_void;
    let Some(device) = dispatch::device_of(handle) else {
        return;
    };
    if fence == vk::Fence::null() {
        return;
    }
    // SAFETY: caller contract; each call's own type.
    let (status, submit, wait): (
        vk::PFN_vkGetFenceStatus,
        vk::PFN_vkQueueSubmit,
        vk::PFN_vkWaitForFences,
    ) = unsafe {
        (
            dispatch::next(handle, c"vkGetFenceStatus"),
            dispatch::next(handle, c"vkQueueSubmit"),
            dispatch::next(handle, c"vkWaitForFences"),
        )
    };
    // SAFETY: the fence's own device and queue; the fence is unsignalled and not in use.
    unsafe {
        if status(device, fence) == vk::Result::NOT_READY {
            let _ = submit(queue, 0, std::ptr::null(), fence);
            let _ = wait(device, 1, &fence, vk::TRUE, u64::MAX);
        }
    }
}

/// A submission: on a lost device nothing runs, the fence is signalled ([`signal_lost`]).
unsafe extern "system" fn queue_submit(
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo<'_>,
    fence: vk::Fence,
) -> vk::Result {
    let decision = decide(Class::Submits, c"vkQueueSubmit");
    if let Decision::Fail(result) = decision {
        return result;
    }
    let next: vk::PFN_vkQueueSubmit =
        // SAFETY: a live queue of a device made through this layer; the call's own type.
        unsafe { dispatch::next(queue.as_raw() as *const c_void, c"vkQueueSubmit") };
    if decision == Decision::Lost {
        // SAFETY: a live queue and the caller's fence.
        unsafe { signal_lost(queue, fence) };
        return vk::Result::ERROR_DEVICE_LOST;
    }
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(queue, count, submits, fence) }
}

/// As [`queue_submit`], for `vkQueueSubmit2`.
unsafe extern "system" fn queue_submit2(
    queue: vk::Queue,
    count: u32,
    submits: *const vk::SubmitInfo2<'_>,
    fence: vk::Fence,
) -> vk::Result {
    let decision = decide(Class::Submits, c"vkQueueSubmit2");
    if let Decision::Fail(result) = decision {
        return result;
    }
    let next: vk::PFN_vkQueueSubmit2 =
        // SAFETY: a live queue of a device made through this layer; the call's own type.
        unsafe { dispatch::next(queue.as_raw() as *const c_void, c"vkQueueSubmit2") };
    if decision == Decision::Lost {
        // SAFETY: a live queue and the caller's fence.
        unsafe { signal_lost(queue, fence) };
        return vk::Result::ERROR_DEVICE_LOST;
    }
    // SAFETY: the caller's arguments, passed down.
    unsafe { next(queue, count, submits, fence) }
}

/// An intercept of class [`Class::Waits`]: the real wait always runs; a lost device then
/// reports the loss.
macro_rules! waits {
    ($fn_name:ident, $name:literal, $pfn:ty, $first:ident: $first_ty:ty $(, $arg:ident: $ty:ty)*) => {
        unsafe extern "system" fn $fn_name($first: $first_ty $(, $arg: $ty)*) -> vk::Result {
            let decision = decide(Class::Waits, $name);
            // SAFETY: a live handle of a device made through this layer; the call's own type.
            let next: $pfn = unsafe { dispatch::next($first.as_raw() as *const c_void, $name) };
            // SAFETY: the caller's arguments, passed down.
            let result = unsafe { next($first $(, $arg)*) };
            match decision {
                Decision::Lost => vk::Result::ERROR_DEVICE_LOST,
                _ => result,
            }
        }
    };
}

waits!(wait_for_fences, c"vkWaitForFences", vk::PFN_vkWaitForFences,
    device: vk::Device, count: u32, fences: *const vk::Fence, all: vk::Bool32, timeout: u64);
waits!(device_wait_idle, c"vkDeviceWaitIdle", vk::PFN_vkDeviceWaitIdle, device: vk::Device);
waits!(queue_wait_idle, c"vkQueueWaitIdle", vk::PFN_vkQueueWaitIdle, queue: vk::Queue);

/// An intercept of class [`Class::Queries`]: a lost device reports the loss without asking
/// the driver (whose results of work that never ran would not come).
macro_rules! queries {
    ($fn_name:ident, $name:literal, $pfn:ty, $first:ident: $first_ty:ty $(, $arg:ident: $ty:ty)*) => {
        unsafe extern "system" fn $fn_name($first: $first_ty $(, $arg: $ty)*) -> vk::Result {
            if decide(Class::Queries, $name) == Decision::Lost {
                return vk::Result::ERROR_DEVICE_LOST;
            }
            // SAFETY: a live handle of a device made through this layer; the call's own type.
            let next: $pfn = unsafe { dispatch::next($first.as_raw() as *const c_void, $name) };
            // SAFETY: the caller's arguments, passed down.
            unsafe { next($first $(, $arg)*) }
        }
    };
}

queries!(get_fence_status, c"vkGetFenceStatus", vk::PFN_vkGetFenceStatus,
    device: vk::Device, fence: vk::Fence);
queries!(get_query_pool_results, c"vkGetQueryPoolResults", vk::PFN_vkGetQueryPoolResults,
    device: vk::Device, pool: vk::QueryPool, first: u32, count: u32, size: usize,
    data: *mut c_void, stride: vk::DeviceSize, flags: vk::QueryResultFlags);

/// The layer's intercept of the device-level call `name`, if it has one.
pub(crate) fn entry(name: &CStr) -> vk::PFN_vkVoidFunction {
    let f: *const () = match name.to_bytes() {
        b"vkAllocateMemory" => allocate_memory as *const (),
        b"vkMapMemory" => map_memory as *const (),
        b"vkBindBufferMemory" => bind_buffer_memory as *const (),
        b"vkBindImageMemory" => bind_image_memory as *const (),
        b"vkCreateBuffer" => create_buffer as *const (),
        b"vkCreateImage" => create_image as *const (),
        b"vkCreateImageView" => create_image_view as *const (),
        b"vkCreateBufferView" => create_buffer_view as *const (),
        b"vkCreateSampler" => create_sampler as *const (),
        b"vkCreateShaderModule" => create_shader_module as *const (),
        b"vkCreatePipelineLayout" => create_pipeline_layout as *const (),
        b"vkCreatePipelineCache" => create_pipeline_cache as *const (),
        b"vkCreateDescriptorSetLayout" => create_descriptor_set_layout as *const (),
        b"vkCreateDescriptorPool" => create_descriptor_pool as *const (),
        b"vkAllocateDescriptorSets" => allocate_descriptor_sets as *const (),
        b"vkCreateGraphicsPipelines" => create_graphics_pipelines as *const (),
        b"vkCreateComputePipelines" => create_compute_pipelines as *const (),
        b"vkCreateCommandPool" => create_command_pool as *const (),
        b"vkAllocateCommandBuffers" => allocate_command_buffers as *const (),
        b"vkResetCommandPool" => reset_command_pool as *const (),
        b"vkBeginCommandBuffer" => begin_command_buffer as *const (),
        b"vkEndCommandBuffer" => end_command_buffer as *const (),
        b"vkCreateFence" => create_fence as *const (),
        b"vkResetFences" => reset_fences as *const (),
        b"vkCreateSemaphore" => create_semaphore as *const (),
        b"vkCreateQueryPool" => create_query_pool as *const (),
        b"vkCreateRenderPass" => create_render_pass as *const (),
        b"vkCreateFramebuffer" => create_framebuffer as *const (),
        b"vkQueueSubmit" => queue_submit as *const (),
        b"vkQueueSubmit2" => queue_submit2 as *const (),
        b"vkWaitForFences" => wait_for_fences as *const (),
        b"vkDeviceWaitIdle" => device_wait_idle as *const (),
        b"vkQueueWaitIdle" => queue_wait_idle as *const (),
        b"vkGetFenceStatus" => get_fence_status as *const (),
        b"vkGetQueryPoolResults" => get_query_pool_results as *const (),
        _ => return None,
    };
    // SAFETY: `f` is one of the `extern "system"` functions above, non-null.
    Some(unsafe { std::mem::transmute::<*const (), unsafe extern "system" fn()>(f) })
}
