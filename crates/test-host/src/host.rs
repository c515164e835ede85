//! [`Host`]: the engine's Vulkan context, from the device to one command buffer.

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::instance::HostInstance;
use crate::{fail, HostResult};

/// How long [`Host::submit_and_wait`] waits for the GPU before giving up.
const FENCE_TIMEOUT_NS: u64 = 60_000_000_000;

/// The host engine's Vulkan context: instance, device, one GRAPHICS | COMPUTE queue, a
/// gpu-allocator, and one command buffer with a fence to wait for its submissions.
pub struct Host {
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue: vk::Queue,
    queue_family: u32,
    /// The device has 64-bit buffer atomics enabled (what the renderer's compute splat needs).
    int64_atomics: bool,
    /// The device has dynamicRendering and sampleRateShading enabled (a render-pass-only host
    /// has neither).
    dynamic_rendering: bool,
    /// `Some` until drop: dropped before the device is destroyed.
    allocator: Option<Allocator>,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    /// Dropped after `Drop::drop` destroyed the device.
    instance: HostInstance,
}

/// The host's Vulkan objects, borrowed together (see [`Host::handles`]).
pub struct HostHandles<'a> {
    /// The Vulkan instance.
    pub instance: &'a ash::Instance,
    /// The physical device behind `device`.
    pub physical_device: vk::PhysicalDevice,
    /// The logical device.
    pub device: &'a ash::Device,
    /// The family of the host's one queue (GRAPHICS | COMPUTE).
    pub queue_family: u32,
    /// The host's memory allocator.
    pub allocator: &'a mut Allocator,
}

impl Host {
    /// Creates a Vulkan 1.3 instance and device. With `validation`, enables the Khronos
    /// validation layer with synchronization validation and collects every warning and error
    /// (read them with [`Host::messages`]).
    pub fn new(validation: bool) -> HostResult<Host> {
        Self::create(validation, true)
    }

    /// As [`Host::new`], but the device enables neither dynamicRendering nor
    /// sampleRateShading: such a host draws only into [`crate::TargetKind::RenderPass`]
    /// targets, single-sampled or shaded once per pixel.
    pub fn render_pass_only(validation: bool) -> HostResult<Host> {
        Self::create(validation, false)
    }

    fn create(validation: bool, dynamic_rendering: bool) -> HostResult<Host> {
        let instance = HostInstance::new(validation)?;
        let (physical_device, queue_family, device, int64_atomics) =
            create_device(instance.instance(), dynamic_rendering)?;
        // SAFETY: the device was created with one queue in `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };

        // From here on `Drop` cleans up whatever has been created (null handles are skipped).
        let mut host = Host {
            physical_device,
            device,
            queue,
            queue_family,
            int64_atomics,
            dynamic_rendering,
            allocator: None,
            command_pool: vk::CommandPool::null(),
            command_buffer: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            instance,
        };
        host.allocator = Some(
            Allocator::new(&AllocatorCreateDesc {
                instance: host.instance().clone(),
                device: host.device.clone(),
                physical_device,
                debug_settings: Default::default(),
                buffer_device_address: false,
                allocation_sizes: Default::default(),
            })
            .map_err(fail("gpu_allocator Allocator::new"))?,
        );
        let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(queue_family);
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
        let fence_info = vk::FenceCreateInfo::default();
        // SAFETY: valid device and create info.
        host.fence = unsafe { host.device.create_fence(&fence_info, None) }
            .map_err(fail("vkCreateFence"))?;
        Ok(host)
    }

    /// The Vulkan instance.
    pub fn instance(&self) -> &ash::Instance {
        self.instance.instance()
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

    /// Whether the device was created with `shaderInt64` and `shaderBufferInt64Atomics`
    /// (enabled wherever the device has them).
    pub fn int64_atomics(&self) -> bool {
        self.int64_atomics
    }

    /// Whether the device enables dynamicRendering and sampleRateShading
    /// ([`Host::render_pass_only`] enables neither).
    pub fn dynamic_rendering(&self) -> bool {
        self.dynamic_rendering
    }

    /// The host's memory allocator.
    pub fn allocator_mut(&mut self) -> &mut Allocator {
        self.device_and_allocator().1
    }

    /// Everything an embedded renderer borrows from the host, at once.
    pub fn handles(&mut self) -> HostHandles<'_> {
        HostHandles {
            instance: self.instance.instance(),
            physical_device: self.physical_device,
            device: &self.device,
            queue_family: self.queue_family,
            allocator: self
                .allocator
                .as_mut()
                .expect("the allocator lives until the host is dropped"),
        }
    }

    /// The device and the allocator at once (creating resources and recording frames need
    /// both).
    pub fn device_and_allocator(&mut self) -> (&ash::Device, &mut Allocator) {
        let handles = self.handles();
        (handles.device, handles.allocator)
    }

    /// The host's single primary command buffer.
    pub fn command_buffer(&self) -> vk::CommandBuffer {
        self.command_buffer
    }

    /// A copy of the validation warnings and errors collected so far (`<id>: <message>`).
    pub fn messages(&self) -> Vec<String> {
        self.instance.messages()
    }

    /// The log [`Host::messages`] copies, kept by the caller past the host: the messages
    /// raised while the device and instance are destroyed (objects left alive, say) arrive
    /// there after the host is gone.
    pub fn message_log(&self) -> std::sync::Arc<std::sync::Mutex<Vec<String>>> {
        self.instance.message_log()
    }

    /// Resets the command pool and begins recording its buffer (one-time submit).
    pub fn begin(&mut self) -> HostResult<vk::CommandBuffer> {
        let cmd = self.command_buffer;
        let info = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the pool's one buffer is not pending (every submission is waited for in
        // `submit_and_wait`), so the whole pool may be reset (best practice over resetting
        // the buffer).
        unsafe {
            self.device
                .reset_command_pool(self.command_pool, vk::CommandPoolResetFlags::empty())
                .map_err(fail("vkResetCommandPool"))?;
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

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: everything below was created by this host; after vkDeviceWaitIdle nothing is
        // in use. Destroyed children first, null handles skipped (they are no-ops anyway), and
        // the allocator dropped (freeing its memory) before the device it allocates from. The
        // instance is destroyed afterwards, when the `instance` field is dropped.
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
        }
    }
}

/// The device features the host enables: sampleRateShading, dynamicRendering and maintenance4
/// are what the ellipsoid renderer requires; synchronization2 is for the host's own
/// vkCmdPipelineBarrier2 calls.
const FEATURES: [&str; 4] = [
    "sampleRateShading",
    "dynamicRendering",
    "maintenance4",
    "synchronization2",
];

/// Whether a device has each of [`FEATURES`], in that order.
fn has_features(
    core: &vk::PhysicalDeviceFeatures,
    v13: &vk::PhysicalDeviceVulkan13Features,
) -> [bool; 4] {
    [
        core.sample_rate_shading,
        v13.dynamic_rendering,
        v13.maintenance4,
        v13.synchronization2,
    ]
    .map(|have| have == vk::TRUE)
}

/// Picks the first Vulkan 1.3 physical device with [`FEATURES`] and a GRAPHICS | COMPUTE
/// queue family, and creates a device with one queue and those features.
fn create_device(
    instance: &ash::Instance,
    dynamic_rendering: bool,
) -> HostResult<(vk::PhysicalDevice, u32, ash::Device, bool)> {
    // SAFETY: valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }
        .map_err(fail("vkEnumeratePhysicalDevices"))?;
    let mut rejected = Vec::new();
    for physical_device in devices {
        match suitable_queue_family(instance, physical_device) {
            Ok(family) => {
                let int64_atomics = has_int64_atomics(instance, physical_device);
                let device = create_logical_device(
                    instance,
                    physical_device,
                    family,
                    int64_atomics,
                    dynamic_rendering,
                )?;
                return Ok((physical_device, family, device, int64_atomics));
            }
            Err(why) => rejected.push(why),
        }
    }
    Err(format!(
        "no suitable Vulkan device (need Vulkan 1.3 with {}): {}",
        FEATURES.join(", "),
        if rejected.is_empty() {
            "no devices found".to_string()
        } else {
            rejected.join("; ")
        }
    ))
}

/// The GRAPHICS | COMPUTE queue family of a device that has everything the host needs, or
/// why the device will not do (`<name>: <reason>`).
fn suitable_queue_family(
    instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
) -> Result<u32, String> {
    // SAFETY: `physical_device` was enumerated from `instance`.
    let properties = unsafe { instance.get_physical_device_properties(physical_device) };
    let name = properties
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    if properties.api_version < vk::API_VERSION_1_3 {
        return Err(format!("{name}: Vulkan 1.3 not supported"));
    }
    let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut supported = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13);
    // SAFETY: the chain points at locals that outlive the call.
    unsafe { instance.get_physical_device_features2(physical_device, &mut supported) };
    let core = supported.features;
    let have = has_features(&core, &supported13);
    let missing: Vec<_> = FEATURES
        .into_iter()
        .zip(have)
        .filter_map(|(name, have)| (!have).then_some(name))
        .collect();
    if !missing.is_empty() {
        return Err(format!("{name}: lacks {}", missing.join(", ")));
    }
    // SAFETY: `physical_device` was enumerated from `instance`.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical_device) };
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    families
        .iter()
        .position(|f| f.queue_flags.contains(wanted) && f.queue_count > 0)
        .map(|family| family as u32)
        .ok_or_else(|| format!("{name}: no GRAPHICS|COMPUTE queue family"))
}

/// Whether the device has `shaderInt64` and `shaderBufferInt64Atomics`.
fn has_int64_atomics(instance: &ash::Instance, physical_device: vk::PhysicalDevice) -> bool {
    let mut vulkan12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut supported = vk::PhysicalDeviceFeatures2::default().push_next(&mut vulkan12);
    // SAFETY: `physical_device` was enumerated from `instance`; the chain points at locals.
    unsafe { instance.get_physical_device_features2(physical_device, &mut supported) };
    supported.features.shader_int64 == vk::TRUE && vulkan12.shader_buffer_int64_atomics == vk::TRUE
}

/// A device with one queue in `family` and [`FEATURES`] enabled (without dynamicRendering and
/// sampleRateShading unless `dynamic_rendering`), plus 64-bit buffer atomics with
/// `int64_atomics`.
fn create_logical_device(
    instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
    family: u32,
    int64_atomics: bool,
    dynamic_rendering: bool,
) -> HostResult<ash::Device> {
    let priorities = [1.0];
    let queue_infos = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(dynamic_rendering)
        .maintenance4(true)
        .synchronization2(true);
    let mut features12 =
        vk::PhysicalDeviceVulkan12Features::default().shader_buffer_int64_atomics(int64_atomics);
    let core = vk::PhysicalDeviceFeatures::default()
        .sample_rate_shading(dynamic_rendering)
        .shader_int64(int64_atomics);
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .features(core)
        .push_next(&mut features13)
        .push_next(&mut features12);
    let device_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .push_next(&mut features2);
    // SAFETY: every pointer in `device_info` refers to locals alive during the call.
    unsafe { instance.create_device(physical_device, &device_info, None) }
        .map_err(fail("vkCreateDevice"))
}
