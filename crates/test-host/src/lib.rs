//! A minimal "foreign" Vulkan engine: the host that `examples/embed` embeds the ellipsoid renderer
//! into. It uses only `ash`, `gpu-allocator` and `glam` (nothing from `ellipsoid_splat`), and
//! owns everything an engine would: instance, device, allocator, command buffer, an offscreen
//! target (render pass or dynamic rendering, optional MSAA, reversed or standard depth) and a
//! pipeline drawing flat-coloured meshes.
//!
//! Also compiled into integration tests with `#[path = "../examples/embed/host.rs"] mod host;`.
#![allow(dead_code)]

use std::ffi::{c_void, CStr};
use std::path::Path;
use std::sync::{Arc, Mutex};

use ash::vk;
use glam::{DMat4, DVec3, DVec4};
use gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use gpu_allocator::MemoryLocation;

/// Result of every host operation; the error names the Vulkan call that failed.
pub type HostResult<T> = Result<T, String>;

/// Turns a Vulkan (or allocator) error into a message naming the failing call.
fn fail<E: std::fmt::Debug>(call: &'static str) -> impl FnOnce(E) -> String {
    move |e| format!("{call} failed: {e:?}")
}

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";
/// How long [`Host::submit_and_wait`] waits for the GPU before giving up.
const FENCE_TIMEOUT_NS: u64 = 60_000_000_000;

// ---------------------------------------------------------------------------------------------
// Host: instance, device, queue, allocator, one command buffer.
// ---------------------------------------------------------------------------------------------

/// The host engine's Vulkan context: everything from the instance to one command buffer.
pub struct Host {
    entry: ash::Entry,
    instance: ash::Instance,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Where the messenger writes; must outlive the messenger (and the instance it is chained to).
    messages: Arc<Mutex<Vec<String>>>,
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    /// `Some` until drop: dropped before the device is destroyed.
    allocator: Option<Allocator>,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
}

/// Debug-utils callback: appends "<message id name>: <message>" to the `Mutex<Vec<String>>`
/// passed as user data, skipping the loader's informational "Loader Message"s.
unsafe extern "system" fn collect_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user_data.is_null() {
        return vk::FALSE;
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call, and
    // `user_data` is `Arc::as_ptr` of the `Mutex` that `Host` keeps alive longer than the
    // messenger and the instance.
    let (data, log) = unsafe { (&*data, &*(user_data as *const Mutex<Vec<String>>)) };
    // SAFETY: the strings are null or NUL-terminated and valid during the callback.
    let (id, text) = unsafe { (data.message_id_name_as_c_str(), data.message_as_c_str()) };
    let id = id.map(CStr::to_string_lossy).unwrap_or_default();
    if id == "Loader Message" {
        return vk::FALSE;
    }
    let text = text.map(CStr::to_string_lossy).unwrap_or_default();
    // The project's validation-modes script counts messages printed in this form.
    if std::env::var_os("ELLIPSOID_SPLAT_PRINT_VALIDATION").is_some() {
        let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            "ERROR"
        } else {
            "WARNING"
        };
        eprintln!("[{level}] {id}: {text}");
    }
    if let Ok(mut log) = log.lock() {
        log.push(format!("{id}: {text}"));
    }
    vk::FALSE
}

/// A messenger reporting every warning and error into `messages` through [`collect_message`].
/// `messages` must outlive the messenger: `Host` owns it and drops it after the instance.
fn messenger_info(
    messages: &Arc<Mutex<Vec<String>>>,
) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(collect_message))
        .user_data(Arc::as_ptr(messages) as *mut c_void)
}

impl Host {
    /// Creates a Vulkan 1.3 instance and device. With `validation`, enables the Khronos
    /// validation layer with synchronization validation and collects every warning and error.
    pub fn new(validation: bool) -> HostResult<Host> {
        // SAFETY: loading the system Vulkan loader; nothing else runs its initialisation.
        let entry = unsafe { ash::Entry::load() }.map_err(fail("loading the Vulkan loader"))?;
        // SAFETY: a global query with no inputs.
        let version = unsafe { entry.try_enumerate_instance_version() }
            .map_err(fail("vkEnumerateInstanceVersion"))?
            .unwrap_or(vk::API_VERSION_1_0);
        if version < vk::API_VERSION_1_3 {
            return Err("the Vulkan loader does not support Vulkan 1.3".into());
        }

        let messages = Arc::new(Mutex::new(Vec::new()));
        let app_info = vk::ApplicationInfo::default()
            .application_name(c"embed-host")
            .api_version(vk::API_VERSION_1_3);
        let mut layers = Vec::new();
        let mut extensions = Vec::new();
        if validation {
            // SAFETY: a global query with no inputs.
            let available = unsafe { entry.enumerate_instance_layer_properties() }
                .map_err(fail("vkEnumerateInstanceLayerProperties"))?;
            if !available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
            {
                return Err(
                    "validation requested but VK_LAYER_KHRONOS_validation is not \
                            installed (Debian: vulkan-validationlayers)"
                        .into(),
                );
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        // Synchronization validation always; the opt-in extra modes of the project's
        // `scripts/validation-modes.sh` through the same environment variable as its tests.
        let mut enabled_validation =
            vec![vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        match std::env::var("ELLIPSOID_SPLAT_EXTRA_VALIDATION").as_deref() {
            Ok("gpu-assisted") => {
                enabled_validation.push(vk::ValidationFeatureEnableEXT::GPU_ASSISTED)
            }
            Ok("best-practices") => {
                enabled_validation.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES)
            }
            _ => {}
        }
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_validation);
        let mut instance_messenger = messenger_info(&messages);
        let mut instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation {
            // Chained messenger: also reports problems in vkCreateInstance/vkDestroyInstance.
            instance_info = instance_info
                .push_next(&mut validation_features)
                .push_next(&mut instance_messenger);
        }
        // SAFETY: every pointer in `instance_info` refers to locals alive during the call; the
        // messenger's user data (`messages`) is moved into the `Host` and outlives the instance.
        let instance = unsafe { entry.create_instance(&instance_info, None) }
            .map_err(fail("vkCreateInstance"))?;

        let messenger = if validation {
            let utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
            // A fresh create info: the one above is now linked into the instance's pNext chain.
            let info = messenger_info(&messages);
            // SAFETY: `instance` enables VK_EXT_debug_utils; the info's user data outlives the
            // messenger (see `messenger_info`).
            match unsafe { utils.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((utils, m)),
                Err(e) => {
                    // SAFETY: nothing else was created from the instance yet.
                    unsafe { instance.destroy_instance(None) };
                    return Err(format!("vkCreateDebugUtilsMessengerEXT failed: {e:?}"));
                }
            }
        } else {
            None
        };

        let (physical_device, queue_family, device) = match create_device(&instance) {
            Ok(created) => created,
            Err(e) => {
                // SAFETY: only the messenger and the instance exist; destroyed child first.
                unsafe {
                    if let Some((utils, m)) = &messenger {
                        utils.destroy_debug_utils_messenger(*m, None);
                    }
                    instance.destroy_instance(None);
                }
                return Err(e);
            }
        };
        // SAFETY: the device was created with one queue in `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };

        // From here on `Drop` cleans up whatever has been created (null handles are skipped).
        let mut host = Host {
            entry,
            instance,
            messenger,
            messages,
            physical_device,
            device,
            queue,
            queue_family,
            allocator: None,
            command_pool: vk::CommandPool::null(),
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
        };
        host.allocator = Some(
            Allocator::new(&AllocatorCreateDesc {
                instance: host.instance.clone(),
                device: host.device.clone(),
                physical_device,
                debug_settings: Default::default(),
                buffer_device_address: false,
                allocation_sizes: Default::default(),
            })
            .map_err(fail("gpu_allocator Allocator::new"))?,
        );
        let pool_info = vk::CommandPoolCreateInfo::default()
            .flags(vk::CommandPoolCreateFlags::empty())
            .queue_family_index(queue_family);
        // SAFETY: valid device and create info.
        host.command_pool = unsafe { host.device.create_command_pool(&pool_info, None) }
            .map_err(fail("vkCreateCommandPool"))?;
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(host.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool was created from this device.
        host.command_buffer = unsafe { host.device.allocate_command_buffers(&alloc_info) }
            .map_err(fail("vkAllocateCommandBuffers"))?[0];
        // SAFETY: valid device and create info.
        host.fence = unsafe {
            host.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .map_err(fail("vkCreateFence"))?;
        Ok(host)
    }

    /// The Vulkan instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.instance
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    /// The physical device the logical device was created on.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical_device
    }

    /// The queue all work is submitted to (GRAPHICS | COMPUTE).
    pub fn queue(&self) -> vk::Queue {
        self.queue
    }

    /// The index of the queue's family.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }

    /// The host's memory allocator.
    pub fn allocator_mut(&mut self) -> &mut Allocator {
        self.allocator
            .as_mut()
            .expect("the allocator lives until the host is dropped")
    }

    /// The device and the allocator at once (creating resources needs both).
    pub fn device_and_allocator(&mut self) -> (&ash::Device, &mut Allocator) {
        let allocator = self
            .allocator
            .as_mut()
            .expect("the allocator lives until the host is dropped");
        (&self.device, allocator)
    }

    /// The host's single primary command buffer.
    pub fn command_buffer(&self) -> vk::CommandBuffer {
        self.command_buffer
    }

    /// A copy of the validation warnings and errors collected so far ("<id>: <message>").
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    /// Resets the command pool and begins recording its buffer (one-time submit).
    pub fn begin(&mut self) -> HostResult<vk::CommandBuffer> {
        let cmd = self.command_buffer;
        // SAFETY: the pool's one buffer is not pending (every submission is waited for in
        // `submit_and_wait`), so the whole pool may be reset (best practice over resetting
        // the buffer).
        unsafe {
            self.device
                .reset_command_pool(self.command_pool, vk::CommandPoolResetFlags::empty())
                .map_err(fail("vkResetCommandPool"))?;
            let info = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            self.device
                .begin_command_buffer(cmd, &info)
                .map_err(fail("vkBeginCommandBuffer"))?;
        }
        Ok(cmd)
    }

    /// Ends the command buffer, submits it and waits for it (at most 60 s).
    pub fn submit_and_wait(&mut self) -> HostResult<()> {
        let cmds = [self.command_buffer];
        let submit = vk::SubmitInfo::default().command_buffers(&cmds);
        // SAFETY: the command buffer is recording (from `begin`), the fence is unsignalled, and
        // the queue is used from this thread only.
        unsafe {
            self.device
                .end_command_buffer(self.command_buffer)
                .map_err(fail("vkEndCommandBuffer"))?;
            self.device
                .queue_submit(self.queue, &[submit], self.fence)
                .map_err(fail("vkQueueSubmit"))?;
            match self
                .device
                .wait_for_fences(&[self.fence], true, FENCE_TIMEOUT_NS)
            {
                Ok(()) => {}
                Err(vk::Result::TIMEOUT) => {
                    return Err("vkWaitForFences timed out after 60 s".into());
                }
                Err(e) => return Err(format!("vkWaitForFences failed: {e:?}")),
            }
            self.device
                .reset_fences(&[self.fence])
                .map_err(fail("vkResetFences"))?;
        }
        Ok(())
    }
}

/// Picks the first Vulkan 1.3 physical device with the features the host and the embedded
/// renderer need and a GRAPHICS | COMPUTE queue family, and creates a device with one queue.
fn create_device(instance: &ash::Instance) -> HostResult<(vk::PhysicalDevice, u32, ash::Device)> {
    // SAFETY: valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(fail("vkEnumeratePhysicalDevices"))?;
    let mut rejected = Vec::new();
    for physical_device in devices {
        // SAFETY: `physical_device` was enumerated from `instance`.
        let properties = unsafe { instance.get_physical_device_properties(physical_device) };
        let name = properties
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if properties.api_version < vk::API_VERSION_1_3 {
            rejected.push(format!("{name}: Vulkan 1.3 not supported"));
            continue;
        }
        let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut supported = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13);
        // SAFETY: the chain points at locals that outlive the call.
        unsafe { instance.get_physical_device_features2(physical_device, &mut supported) };
        let core = supported.features;
        let mut missing = Vec::new();
        for (have, feature) in [
            (core.sample_rate_shading, "sampleRateShading"),
            (supported13.dynamic_rendering, "dynamicRendering"),
            (supported13.maintenance4, "maintenance4"),
            (supported13.synchronization2, "synchronization2"),
        ] {
            if have == vk::FALSE {
                missing.push(feature);
            }
        }
        if !missing.is_empty() {
            rejected.push(format!("{name}: lacks {}", missing.join(", ")));
            continue;
        }
        // SAFETY: `physical_device` was enumerated from `instance`.
        let families =
            unsafe { instance.get_physical_device_queue_family_properties(physical_device) };
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let Some(family) = families
            .iter()
            .position(|f| f.queue_flags.contains(wanted) && f.queue_count > 0)
        else {
            rejected.push(format!("{name}: no GRAPHICS|COMPUTE queue family"));
            continue;
        };
        let family = family as u32;

        let priorities = [1.0];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        // sampleRateShading, dynamicRendering and maintenance4 are what the ellipsoid renderer
        // requires; synchronization2 is for the host's own vkCmdPipelineBarrier2 calls.
        let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .maintenance4(true)
            .synchronization2(true);
        let mut features = vk::PhysicalDeviceFeatures2::default()
            .features(vk::PhysicalDeviceFeatures::default().sample_rate_shading(true))
            .push_next(&mut features13);
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .push_next(&mut features);
        // SAFETY: every pointer in `device_info` refers to locals alive during the call.
        let device = unsafe { instance.create_device(physical_device, &device_info, None) }
            .map_err(fail("vkCreateDevice"))?;
        return Ok((physical_device, family, device));
    }
    Err(format!(
        "no suitable Vulkan device (need Vulkan 1.3 with sampleRateShading, dynamicRendering, \
         maintenance4, synchronization2): {}",
        if rejected.is_empty() {
            "no devices found".to_string()
        } else {
            rejected.join("; ")
        }
    ))
}

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: everything below was created by this host; after vkDeviceWaitIdle nothing is
        // in use. Destroyed children first, null handles skipped (they are no-ops anyway), and
        // the allocator dropped (freeing its memory) before the device it allocates from.
        unsafe {
            let _ = self.device.device_wait_idle();
            if self.fence != vk::Fence::null() {
                self.device.destroy_fence(self.fence, None);
            }
            if self.command_pool != vk::CommandPool::null() {
                // Frees the command buffer too.
                self.device.destroy_command_pool(self.command_pool, None);
            }
            drop(self.allocator.take());
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.messenger.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Images and buffers with gpu-allocator memory.
// ---------------------------------------------------------------------------------------------

/// An image, its view and its memory (each part may be missing after a failed creation).
struct OwnedImage {
    image: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl OwnedImage {
    /// A 2D single-mip image with GpuOnly memory and a view of `aspect`.
    fn new(
        host: &mut Host,
        name: &str,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        samples: vk::SampleCountFlags,
        extent: vk::Extent2D,
        aspect: vk::ImageAspectFlags,
    ) -> HostResult<OwnedImage> {
        let (device, allocator) = host.device_and_allocator();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let image = unsafe { device.create_image(&info, None) }.map_err(fail("vkCreateImage"))?;
        let mut owned = OwnedImage {
            image,
            view: vk::ImageView::null(),
            allocation: None,
        };
        let result = owned.bind_and_view(device, allocator, name, format, aspect);
        match result {
            Ok(()) => Ok(owned),
            Err(e) => {
                owned.destroy(device, allocator);
                Err(e)
            }
        }
    }

    fn bind_and_view(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &str,
        format: vk::Format,
        aspect: vk::ImageAspectFlags,
    ) -> HostResult<()> {
        // SAFETY: the image was created from `device`.
        let requirements = unsafe { device.get_image_memory_requirements(self.image) };
        let allocation = allocator
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(fail("gpu_allocator allocate (image)"))?;
        // SAFETY: the allocation satisfies the image's requirements and outlives the image
        // (both are released together in `destroy`, image first).
        let bound = unsafe {
            device.bind_image_memory(self.image, allocation.memory(), allocation.offset())
        };
        self.allocation = Some(allocation);
        bound.map_err(fail("vkBindImageMemory"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(self.image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: the image is bound to memory; the view covers its only mip and layer.
        self.view = unsafe { device.create_image_view(&view_info, None) }
            .map_err(fail("vkCreateImageView"))?;
        Ok(())
    }

    fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: the caller guarantees the GPU no longer uses the image; view before image,
        // image before its memory.
        unsafe {
            if self.view != vk::ImageView::null() {
                device.destroy_image_view(self.view, None);
            }
            device.destroy_image(self.image, None);
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = allocator.free(allocation);
        }
    }
}

/// A buffer and its memory.
struct OwnedBuffer {
    buffer: vk::Buffer,
    allocation: Option<Allocation>,
}

impl OwnedBuffer {
    /// A buffer of `size` bytes with memory at `location` (host-visible ones are mapped).
    fn new(
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
        // SAFETY: the buffer was created from `device`.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocated = allocator
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(fail("gpu_allocator allocate (buffer)"));
        let bound = allocated.and_then(|allocation| {
            // SAFETY: the allocation satisfies the buffer's requirements and is freed only
            // after the buffer is destroyed.
            let result = unsafe {
                device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset())
            };
            owned.allocation = Some(allocation);
            result.map_err(fail("vkBindBufferMemory"))
        });
        match bound {
            Ok(()) => Ok(owned),
            Err(e) => {
                owned.destroy(device, allocator);
                Err(e)
            }
        }
    }

    fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: the caller guarantees the GPU no longer uses the buffer; buffer before memory.
        unsafe { device.destroy_buffer(self.buffer, None) };
        if let Some(allocation) = self.allocation.take() {
            let _ = allocator.free(allocation);
        }
    }
}

/// The one mip level and array layer of an image.
fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

// ---------------------------------------------------------------------------------------------
// HostTarget: offscreen colour + depth (+ MSAA resolve) with a readback buffer.
// ---------------------------------------------------------------------------------------------

/// How a [`HostTarget`] is rendered to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetKind {
    /// `vkCmdBeginRendering` (Vulkan 1.3 dynamic rendering) with explicit layout barriers.
    Dynamic,
    /// A classic `VkRenderPass` + `VkFramebuffer` with one subpass.
    RenderPass,
}

/// The depth convention of a [`HostTarget`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthKind {
    /// Reversed-Z, infinite far plane: cleared to 0, compare GREATER.
    ReversedInfinite,
    /// Standard Z in [0, 1] between near and far: cleared to 1, compare LESS.
    StandardFinite,
}

/// An offscreen render target of the host engine: colour, depth, optional MSAA resolve image,
/// and a host-visible buffer the final colour is copied into.
pub struct HostTarget {
    kind: TargetKind,
    depth_kind: DepthKind,
    samples: vk::SampleCountFlags,
    extent: vk::Extent2D,
    color: Option<OwnedImage>,
    depth: Option<OwnedImage>,
    /// Single-sample image the MSAA colour is resolved into (only when samples > 1).
    resolve: Option<OwnedImage>,
    readback: Option<OwnedBuffer>,
    render_pass: vk::RenderPass,
    framebuffer: vk::Framebuffer,
}

impl HostTarget {
    /// Format of the colour (and resolve) image.
    pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
    /// Format of the depth image.
    pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

    /// Creates the images, the readback buffer and, for [`TargetKind::RenderPass`], the render
    /// pass and framebuffer.
    pub fn new(
        host: &mut Host,
        kind: TargetKind,
        depth: DepthKind,
        samples: vk::SampleCountFlags,
        width: u32,
        height: u32,
    ) -> HostResult<HostTarget> {
        if samples.as_raw().count_ones() != 1 {
            return Err(format!("sample count {samples:?} is not a single count"));
        }
        if width == 0 || height == 0 {
            return Err(format!("empty target {width}x{height}"));
        }
        // SAFETY: the physical device comes from the host's instance.
        let limits = unsafe {
            host.instance
                .get_physical_device_properties(host.physical_device)
        }
        .limits;
        let supported =
            limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
        if !supported.contains(samples) {
            return Err(format!(
                "{samples:?} not supported for colour+depth (device supports {supported:?})"
            ));
        }
        let mut target = HostTarget {
            kind,
            depth_kind: depth,
            samples,
            extent: vk::Extent2D { width, height },
            color: None,
            depth: None,
            resolve: None,
            readback: None,
            render_pass: vk::RenderPass::null(),
            framebuffer: vk::Framebuffer::null(),
        };
        match target.create_resources(host) {
            Ok(()) => Ok(target),
            Err(e) => {
                target.destroy(host);
                Err(e)
            }
        }
    }

    fn create_resources(&mut self, host: &mut Host) -> HostResult<()> {
        let msaa = self.samples != vk::SampleCountFlags::TYPE_1;
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let copied = attachment | vk::ImageUsageFlags::TRANSFER_SRC;
        self.color = Some(OwnedImage::new(
            host,
            "host colour",
            Self::COLOR_FORMAT,
            if msaa { attachment } else { copied },
            self.samples,
            self.extent,
            vk::ImageAspectFlags::COLOR,
        )?);
        self.depth = Some(OwnedImage::new(
            host,
            "host depth",
            Self::DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            self.samples,
            self.extent,
            vk::ImageAspectFlags::DEPTH,
        )?);
        if msaa {
            self.resolve = Some(OwnedImage::new(
                host,
                "host resolve",
                Self::COLOR_FORMAT,
                copied,
                vk::SampleCountFlags::TYPE_1,
                self.extent,
                vk::ImageAspectFlags::COLOR,
            )?);
        }
        let bytes = u64::from(self.extent.width) * u64::from(self.extent.height) * 4;
        self.readback = Some(OwnedBuffer::new(
            host,
            "host readback",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?);
        if self.kind == TargetKind::RenderPass {
            self.create_render_pass(host.device())?;
        }
        Ok(())
    }

    /// One subpass: colour 0, depth 1 and, under MSAA, resolve 2. The image copied out
    /// afterwards (colour, or resolve under MSAA) ends in TRANSFER_SRC_OPTIMAL.
    fn create_render_pass(&mut self, device: &ash::Device) -> HostResult<()> {
        let msaa = self.resolve.is_some();
        let mut attachments = vec![
            vk::AttachmentDescription::default()
                .format(Self::COLOR_FORMAT)
                .samples(self.samples)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                // Multisampled: only the resolved image is kept.
                .store_op(if msaa {
                    vk::AttachmentStoreOp::DONT_CARE
                } else {
                    vk::AttachmentStoreOp::STORE
                })
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::UNDEFINED)
                .final_layout(if msaa {
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL
                } else {
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL
                }),
            vk::AttachmentDescription::default()
                .format(Self::DEPTH_FORMAT)
                .samples(self.samples)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                .initial_layout(vk::ImageLayout::UNDEFINED)
                .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL),
        ];
        if msaa {
            attachments.push(
                vk::AttachmentDescription::default()
                    .format(Self::COLOR_FORMAT)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .initial_layout(vk::ImageLayout::UNDEFINED)
                    .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL),
            );
        }
        let color_refs = [vk::AttachmentReference {
            attachment: 0,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let depth_ref = vk::AttachmentReference {
            attachment: 1,
            layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        };
        let resolve_refs = [vk::AttachmentReference {
            attachment: 2,
            layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        }];
        let mut subpass = vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&color_refs)
            .depth_stencil_attachment(&depth_ref);
        if msaa {
            subpass = subpass.resolve_attachments(&resolve_refs);
        }
        let attachment_stages = vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT
            | vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS;
        let dependencies = [
            // Earlier work on these images (last frame's attachment writes and the copy out)
            // before this pass's layout transitions, clears and writes.
            vk::SubpassDependency {
                src_subpass: vk::SUBPASS_EXTERNAL,
                dst_subpass: 0,
                src_stage_mask: attachment_stages | vk::PipelineStageFlags::TRANSFER,
                dst_stage_mask: attachment_stages,
                src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
                dst_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_READ
                    | vk::AccessFlags::COLOR_ATTACHMENT_WRITE
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                    | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
                dependency_flags: vk::DependencyFlags::empty(),
            },
            // Colour writes and the resolve before the copy out of the pass.
            vk::SubpassDependency {
                src_subpass: 0,
                dst_subpass: vk::SUBPASS_EXTERNAL,
                src_stage_mask: vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
                dst_stage_mask: vk::PipelineStageFlags::TRANSFER,
                src_access_mask: vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
                dst_access_mask: vk::AccessFlags::TRANSFER_READ,
                dependency_flags: vk::DependencyFlags::empty(),
            },
        ];
        let subpasses = [subpass];
        let info = vk::RenderPassCreateInfo::default()
            .attachments(&attachments)
            .subpasses(&subpasses)
            .dependencies(&dependencies);
        // SAFETY: every pointer in `info` refers to locals alive during the call.
        self.render_pass = unsafe { device.create_render_pass(&info, None) }
            .map_err(fail("vkCreateRenderPass"))?;

        let mut views = vec![self.color_image().view, self.depth_image().view];
        if let Some(resolve) = &self.resolve {
            views.push(resolve.view);
        }
        let framebuffer_info = vk::FramebufferCreateInfo::default()
            .render_pass(self.render_pass)
            .attachments(&views)
            .width(self.extent.width)
            .height(self.extent.height)
            .layers(1);
        // SAFETY: the views match the render pass's attachments in format and samples.
        self.framebuffer = unsafe { device.create_framebuffer(&framebuffer_info, None) }
            .map_err(fail("vkCreateFramebuffer"))?;
        Ok(())
    }

    fn color_image(&self) -> &OwnedImage {
        self.color.as_ref().expect("created in HostTarget::new")
    }

    fn depth_image(&self) -> &OwnedImage {
        self.depth.as_ref().expect("created in HostTarget::new")
    }

    /// The single-sample image read back: the resolve image under MSAA, else the colour image.
    fn copied_image(&self) -> &OwnedImage {
        self.resolve.as_ref().unwrap_or_else(|| self.color_image())
    }

    /// The depth compare op for this target's convention (GREATER reversed, LESS standard).
    pub fn depth_compare(&self) -> vk::CompareOp {
        match self.depth_kind {
            DepthKind::ReversedInfinite => vk::CompareOp::GREATER,
            DepthKind::StandardFinite => vk::CompareOp::LESS,
        }
    }

    /// The value depth is cleared to (the far plane): 0 reversed, 1 standard.
    pub fn depth_clear(&self) -> f32 {
        match self.depth_kind {
            DepthKind::ReversedInfinite => 0.0,
            DepthKind::StandardFinite => 1.0,
        }
    }

    /// Render pass or dynamic rendering.
    pub fn kind(&self) -> TargetKind {
        self.kind
    }

    /// The depth convention.
    pub fn depth_kind(&self) -> DepthKind {
        self.depth_kind
    }

    /// Samples per pixel of the colour and depth images.
    pub fn samples(&self) -> vk::SampleCountFlags {
        self.samples
    }

    /// Width and height in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The render pass (null for [`TargetKind::Dynamic`]); pipelines drawing into the target
    /// use its subpass 0.
    pub fn render_pass(&self) -> vk::RenderPass {
        self.render_pass
    }

    /// Starts drawing into the target: layout transitions (dynamic rendering only), then the
    /// render pass or `vkCmdBeginRendering` clearing colour to opaque black and depth to
    /// [`Self::depth_clear`], then a full viewport and scissor.
    pub fn begin_pass(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent: self.extent,
        };
        let clear_color = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [0.0, 0.0, 0.0, 1.0],
            },
        };
        let clear_depth = vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: self.depth_clear(),
                stencil: 0,
            },
        };
        match self.kind {
            TargetKind::RenderPass => {
                // One value per attachment: colour, depth and (ignored, DONT_CARE) resolve.
                let clears = [clear_color, clear_depth, clear_color];
                let count = if self.resolve.is_some() { 3 } else { 2 };
                let info = vk::RenderPassBeginInfo::default()
                    .render_pass(self.render_pass)
                    .framebuffer(self.framebuffer)
                    .render_area(area)
                    .clear_values(&clears[..count]);
                // SAFETY: `cmd` is recording outside a pass; the framebuffer matches the pass.
                unsafe { device.cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE) };
            }
            TargetKind::Dynamic => {
                let color_access = vk::AccessFlags2::COLOR_ATTACHMENT_READ
                    | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE;
                // Earlier uses (attachment writes, the copy out) complete before the
                // transitions; UNDEFINED discards the old contents, which are cleared anyway.
                let color_barrier = |image: vk::Image| {
                    vk::ImageMemoryBarrier2::default()
                        .src_stage_mask(
                            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT
                                | vk::PipelineStageFlags2::COPY,
                        )
                        .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
                        .dst_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
                        .dst_access_mask(color_access)
                        .old_layout(vk::ImageLayout::UNDEFINED)
                        .new_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                        .image(image)
                        .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR))
                };
                let tests = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
                let mut barriers = vec![
                    color_barrier(self.color_image().image),
                    vk::ImageMemoryBarrier2::default()
                        .src_stage_mask(tests)
                        .src_access_mask(vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE)
                        .dst_stage_mask(tests)
                        .dst_access_mask(
                            vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                                | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                        )
                        .old_layout(vk::ImageLayout::UNDEFINED)
                        .new_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                        .image(self.depth_image().image)
                        .subresource_range(subresource_range(vk::ImageAspectFlags::DEPTH)),
                ];
                if let Some(resolve) = &self.resolve {
                    barriers.push(color_barrier(resolve.image));
                }
                let dependency = vk::DependencyInfo::default().image_memory_barriers(&barriers);
                // SAFETY: `cmd` is recording outside a pass; the barriers name this target's
                // images.
                unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };

                let mut color = vk::RenderingAttachmentInfo::default()
                    .image_view(self.color_image().view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    // Multisampled: only the resolved image is kept.
                    .store_op(if self.resolve.is_some() {
                        vk::AttachmentStoreOp::DONT_CARE
                    } else {
                        vk::AttachmentStoreOp::STORE
                    })
                    .clear_value(clear_color);
                if let Some(resolve) = &self.resolve {
                    color = color
                        .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                        .resolve_image_view(resolve.view)
                        .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL);
                }
                let colors = [color];
                let depth = vk::RenderingAttachmentInfo::default()
                    .image_view(self.depth_image().view)
                    .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .clear_value(clear_depth);
                let info = vk::RenderingInfo::default()
                    .render_area(area)
                    .layer_count(1)
                    .color_attachments(&colors)
                    .depth_attachment(&depth);
                // SAFETY: the images were just transitioned to the layouts named here.
                unsafe { device.cmd_begin_rendering(cmd, &info) };
            }
        }
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: self.extent.width as f32,
            height: self.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: `cmd` is recording; dynamic state is valid to set at any time.
        unsafe {
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
        }
    }

    /// Ends the pass and copies the final single-sample colour (the resolve image under MSAA)
    /// into the readback buffer, made visible to the host. Read it with [`Self::read_rgba`]
    /// after [`Host::submit_and_wait`].
    pub fn end_pass(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        let copied = self.copied_image().image;
        match self.kind {
            // The render pass's final layout and its 0 -> EXTERNAL dependency already made the
            // copied image a TRANSFER_SRC_OPTIMAL transfer source.
            // SAFETY: `cmd` is inside the pass begun by `begin_pass`.
            TargetKind::RenderPass => unsafe { device.cmd_end_render_pass(cmd) },
            TargetKind::Dynamic => {
                let barrier = vk::ImageMemoryBarrier2::default()
                    .src_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
                    .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
                    .dst_stage_mask(vk::PipelineStageFlags2::COPY)
                    .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)
                    .old_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .new_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
                    .image(copied)
                    .subresource_range(subresource_range(vk::ImageAspectFlags::COLOR));
                let barriers = [barrier];
                let dependency = vk::DependencyInfo::default().image_memory_barriers(&barriers);
                // SAFETY: `cmd` is inside the rendering begun by `begin_pass`; the barrier
                // follows it, outside any pass.
                unsafe {
                    device.cmd_end_rendering(cmd);
                    device.cmd_pipeline_barrier2(cmd, &dependency);
                }
            }
        }
        let readback = self.readback.as_ref().expect("created in HostTarget::new");
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D {
                width: self.extent.width,
                height: self.extent.height,
                depth: 1,
            },
        };
        let to_host = [vk::BufferMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)
            .buffer(readback.buffer)
            .offset(0)
            .size(vk::WHOLE_SIZE)];
        let dependency = vk::DependencyInfo::default().buffer_memory_barriers(&to_host);
        // SAFETY: `cmd` is recording outside a pass; the image is in TRANSFER_SRC_OPTIMAL and
        // the buffer holds exactly width * height * 4 bytes.
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                copied,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.buffer,
                &[region],
            );
            device.cmd_pipeline_barrier2(cmd, &dependency);
        }
    }

    /// The pixels copied by [`Self::end_pass`]: tightly packed RGBA8 rows, row 0 at the top.
    /// Call after [`Host::submit_and_wait`].
    pub fn read_rgba(&self) -> HostResult<Vec<u8>> {
        let bytes = self.extent.width as usize * self.extent.height as usize * 4;
        self.readback
            .as_ref()
            .and_then(|b| b.allocation.as_ref())
            .and_then(|a| a.mapped_slice())
            .map(|mapped| mapped[..bytes].to_vec())
            .ok_or_else(|| "the readback buffer is not host-mapped".to_string())
    }

    /// Destroys everything the target created. The GPU must be done with it (call after
    /// [`Host::submit_and_wait`]).
    pub fn destroy(mut self, host: &mut Host) {
        let (device, allocator) = host.device_and_allocator();
        // SAFETY: the caller guarantees no pending work uses the target; framebuffer before
        // render pass and views, null handles are ignored by Vulkan.
        unsafe {
            device.destroy_framebuffer(self.framebuffer, None);
            device.destroy_render_pass(self.render_pass, None);
        }
        for image in [self.resolve.take(), self.depth.take(), self.color.take()]
            .into_iter()
            .flatten()
        {
            let mut image = image;
            image.destroy(device, allocator);
        }
        if let Some(mut readback) = self.readback.take() {
            readback.destroy(device, allocator);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes.
// ---------------------------------------------------------------------------------------------

/// One vertex of a host mesh: world position and flat colour (24 bytes, two `vec3`s).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshVertex {
    /// World-space position.
    pub position: [f32; 3],
    /// Linear RGB in [0, 1], written unlit.
    pub color: [f32; 3],
}

/// A square of side `2 * half_size` centred on `center` in the plane with `normal`, as two
/// triangles of one colour.
pub fn tilted_plane(
    center: DVec3,
    normal: DVec3,
    half_size: f64,
    color: [f32; 3],
) -> Vec<MeshVertex> {
    let n = normal.normalize();
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = n.cross(helper).normalize() * half_size;
    let v = n.cross(u);
    let corners = [
        center - u - v,
        center + u - v,
        center + u + v,
        center - u + v,
    ];
    [0, 1, 2, 0, 2, 3]
        .into_iter()
        .map(|i| MeshVertex {
            position: corners[i].as_vec3().to_array(),
            color,
        })
        .collect()
}

/// The grey levels of [`cube`]'s faces (+X, -X, +Y, -Y, +Z, -Z) when coloured per face: whole
/// multiples of 1/255, so an RGBA8 readback holds them exactly.
pub const CUBE_FACE_GREYS: [u8; 6] = [80, 112, 144, 176, 208, 240];
/// The grey of [`cube`] when not coloured per face.
pub const CUBE_GREY: u8 = 160;

/// An axis-aligned cube of 12 triangles. With `color_per_face`, each face has its own grey
/// ([`CUBE_FACE_GREYS`]); otherwise all are [`CUBE_GREY`].
pub fn cube(center: DVec3, half_size: f64, color_per_face: bool) -> Vec<MeshVertex> {
    let mut vertices = Vec::with_capacity(36);
    for (face, face_grey) in CUBE_FACE_GREYS.into_iter().enumerate() {
        let axis = face / 2;
        let sign = if face % 2 == 0 { 1.0 } else { -1.0 };
        let mut n = DVec3::ZERO;
        n[axis] = sign;
        let mut u = DVec3::ZERO;
        u[(axis + 1) % 3] = 1.0;
        let mut v = DVec3::ZERO;
        v[(axis + 2) % 3] = 1.0;
        let grey = if color_per_face { face_grey } else { CUBE_GREY };
        let level = f32::from(grey) / 255.0;
        let corner = |a: f64, b: f64| center + (n + u * a + v * b) * half_size;
        let corners = [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        vertices.extend([0, 1, 2, 0, 2, 3].into_iter().map(|i| MeshVertex {
            position: corners[i].as_vec3().to_array(),
            color: [level; 3],
        }));
    }
    vertices
}

// ---------------------------------------------------------------------------------------------
// Projections (Vulkan clip space: y down, z in [0, 1]; the camera looks down -Z).
// ---------------------------------------------------------------------------------------------

/// Reversed-Z perspective with an infinite far plane: a point at view depth `d = -z` gets clip
/// w = d and NDC z = near / d (1 at the near plane, 0 at infinity); NDC y points down.
pub fn reversed_infinite_perspective(fov_y_rad: f64, aspect: f64, near: f64) -> DMat4 {
    let f = 1.0 / (0.5 * fov_y_rad).tan();
    DMat4::from_cols(
        DVec4::new(f / aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, -f, 0.0, 0.0),
        DVec4::new(0.0, 0.0, 0.0, -1.0),
        DVec4::new(0.0, 0.0, near, 0.0),
    )
}

/// Standard perspective: NDC z = 0 at `near`, 1 at `far`; NDC y points down.
pub fn standard_finite_perspective(fov_y_rad: f64, aspect: f64, near: f64, far: f64) -> DMat4 {
    let f = 1.0 / (0.5 * fov_y_rad).tan();
    let range = near - far;
    DMat4::from_cols(
        DVec4::new(f / aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, -f, 0.0, 0.0),
        DVec4::new(0.0, 0.0, far / range, -1.0),
        DVec4::new(0.0, 0.0, near * far / range, 0.0),
    )
}

// ---------------------------------------------------------------------------------------------
// MeshPipeline: a vertex buffer and the graphics pipeline that draws it into a HostTarget.
// ---------------------------------------------------------------------------------------------

/// A triangle list in a vertex buffer plus a pipeline drawing it, unlit, into one kind of
/// [`HostTarget`] (its kind, formats, samples and depth compare op).
pub struct MeshPipeline {
    vertices: Option<OwnedBuffer>,
    vertex_count: u32,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
}

impl MeshPipeline {
    /// Uploads `vertices` (a triangle list) and builds a pipeline compatible with `target`.
    pub fn new(
        host: &mut Host,
        target: &HostTarget,
        vertices: &[MeshVertex],
    ) -> HostResult<MeshPipeline> {
        if vertices.is_empty() || vertices.len() % 3 != 0 {
            return Err(format!(
                "{} vertices is not a non-empty triangle list",
                vertices.len()
            ));
        }
        let bytes: Vec<u8> = vertices
            .iter()
            .flat_map(|v| v.position.into_iter().chain(v.color))
            .flat_map(f32::to_ne_bytes)
            .collect();
        let mut mesh = MeshPipeline {
            vertices: None,
            vertex_count: vertices.len() as u32,
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
        };
        let result = mesh.create(host, target, &bytes);
        match result {
            Ok(()) => Ok(mesh),
            Err(e) => {
                mesh.destroy(host);
                Err(e)
            }
        }
    }

    fn create(&mut self, host: &mut Host, target: &HostTarget, bytes: &[u8]) -> HostResult<()> {
        let mut buffer = OwnedBuffer::new(
            host,
            "host mesh vertices",
            bytes.len() as u64,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mapped = buffer
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut());
        // CpuToGpu memory is host-coherent: the write is visible to the GPU at submission.
        let uploaded = match mapped {
            Some(mapped) => {
                mapped[..bytes.len()].copy_from_slice(bytes);
                true
            }
            None => false,
        };
        self.vertices = Some(buffer);
        if !uploaded {
            return Err("the vertex buffer is not host-mapped".into());
        }

        let device = host.device();
        let push_constants = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: 64,
        }];
        let layout_info =
            vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&push_constants);
        // SAFETY: valid device and create info.
        self.layout = unsafe { device.create_pipeline_layout(&layout_info, None) }
            .map_err(fail("vkCreatePipelineLayout"))?;

        let vert = shader_module(
            device,
            include_bytes!(concat!(env!("OUT_DIR"), "/host_mesh.vert.spv")),
        )?;
        let frag = match shader_module(
            device,
            include_bytes!(concat!(env!("OUT_DIR"), "/host_mesh.frag.spv")),
        ) {
            Ok(frag) => frag,
            Err(e) => {
                // SAFETY: the module is not used by anything.
                unsafe { device.destroy_shader_module(vert, None) };
                return Err(e);
            }
        };
        let result = self.create_pipeline(device, target, vert, frag);
        // SAFETY: modules may be destroyed once the pipeline is created (or creation failed).
        unsafe {
            device.destroy_shader_module(vert, None);
            device.destroy_shader_module(frag, None);
        }
        result
    }

    fn create_pipeline(
        &mut self,
        device: &ash::Device,
        target: &HostTarget,
        vert: vk::ShaderModule,
        frag: vk::ShaderModule,
    ) -> HostResult<()> {
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag)
                .name(c"main"),
        ];
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<MeshVertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes = [
            vk::VertexInputAttributeDescription {
                location: 0,
                binding: 0,
                format: vk::Format::R32G32B32_SFLOAT,
                offset: std::mem::offset_of!(MeshVertex, position) as u32,
            },
            vk::VertexInputAttributeDescription {
                location: 1,
                binding: 0,
                format: vk::Format::R32G32B32_SFLOAT,
                offset: std::mem::offset_of!(MeshVertex, color) as u32,
            },
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes);
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let rasterization = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(target.samples());
        let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(target.depth_compare());
        let blend_attachments = [vk::PipelineColorBlendAttachmentState::default()
            .blend_enable(false)
            .color_write_mask(vk::ColorComponentFlags::RGBA)];
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let color_formats = [HostTarget::COLOR_FORMAT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&color_formats)
            .depth_attachment_format(HostTarget::DEPTH_FORMAT);
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&rasterization)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_stencil)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(self.layout);
        info = match target.kind() {
            TargetKind::Dynamic => info.push_next(&mut rendering),
            TargetKind::RenderPass => info.render_pass(target.render_pass()).subpass(0),
        };
        // SAFETY: every pointer in `info` refers to locals alive during the call; the layout,
        // modules and render pass are valid.
        let pipelines =
            unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
                .map_err(|(_, e)| format!("vkCreateGraphicsPipelines failed: {e:?}"))?;
        self.pipeline = pipelines[0];
        Ok(())
    }

    /// Records the draw: binds the pipeline and vertex buffer, pushes `view_projection` and
    /// draws every vertex. Call between [`HostTarget::begin_pass`] and
    /// [`HostTarget::end_pass`] of the target the pipeline was built for.
    pub fn record(&self, device: &ash::Device, cmd: vk::CommandBuffer, view_projection: DMat4) {
        let matrix: Vec<u8> = view_projection
            .as_mat4()
            .to_cols_array()
            .into_iter()
            .flat_map(f32::to_ne_bytes)
            .collect();
        let buffer = self
            .vertices
            .as_ref()
            .expect("created in MeshPipeline::new")
            .buffer;
        // SAFETY: `cmd` is recording inside a compatible pass with viewport and scissor set;
        // the push constant range is 64 bytes at offset 0 for the vertex stage.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            device.cmd_bind_vertex_buffers(cmd, 0, &[buffer], &[0]);
            device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, &matrix);
            device.cmd_draw(cmd, self.vertex_count, 1, 0, 0);
        }
    }

    /// Destroys the pipeline and frees the vertex buffer. The GPU must be done with them.
    pub fn destroy(mut self, host: &mut Host) {
        let (device, allocator) = host.device_and_allocator();
        // SAFETY: the caller guarantees no pending work uses the pipeline or the buffer; null
        // handles are ignored by Vulkan.
        unsafe {
            device.destroy_pipeline(self.pipeline, None);
            device.destroy_pipeline_layout(self.layout, None);
        }
        if let Some(mut vertices) = self.vertices.take() {
            vertices.destroy(device, allocator);
        }
    }
}

/// A shader module from SPIR-V bytes.
fn shader_module(device: &ash::Device, spv: &[u8]) -> HostResult<vk::ShaderModule> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spv))
        .map_err(|e| format!("invalid SPIR-V: {e}"))?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: `words` is SPIR-V compiled and validated by build.rs.
    unsafe { device.create_shader_module(&info, None) }.map_err(fail("vkCreateShaderModule"))
}

/// Writes tightly packed RGBA8 pixels (row 0 at the top) as a PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> HostResult<()> {
    let image = image::RgbaImage::from_raw(width, height, rgba.to_vec())
        .ok_or_else(|| format!("{} bytes is not a {width}x{height} RGBA8 image", rgba.len()))?;
    image
        .save(path)
        .map_err(|e| format!("writing {}: {e}", path.display()))
}
