//! The standalone Vulkan context: instance, optional validation, device, queue and allocator,
//! all owned here and destroyed in reverse order of creation.

use std::ffi::{c_char, CStr};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{Error, Result, VkCall};
use crate::features::DeviceFeatures;
use crate::gpu::validation::{self, MessageLog, ValidationMessage};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to build a [`Context`].
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct ContextOptions {
    /// Enable `VK_LAYER_KHRONOS_validation` with a messenger that records every warning and error.
    pub validation: bool,
    /// Also enable synchronization validation (needs `validation`).
    pub synchronization_validation: bool,
    /// Also enable GPU-assisted validation (needs `validation`; slow, can hang on layer 1.3.239).
    pub gpu_assisted_validation: bool,
    /// Also enable the best-practices checks (needs `validation`); their warnings count as
    /// messages like any other.
    pub best_practices_validation: bool,
    /// Choose a device by index or by a substring of its name; `None` prefers a real GPU.
    /// The environment variable `ELLIPSOID_SPLAT_DEVICE` is used when this is `None`.
    pub device: Option<String>,
}

impl ContextOptions {
    /// Validation with synchronization checks, as every test runs. The opt-in runs of
    /// `scripts/validation-modes.sh` add GPU-assisted validation or the best-practices checks
    /// through `ELLIPSOID_SPLAT_EXTRA_VALIDATION` (`gpu-assisted` or `best-practices`).
    pub fn validated() -> Self {
        let extra = std::env::var("ELLIPSOID_SPLAT_EXTRA_VALIDATION").unwrap_or_default();
        Self {
            validation: true,
            synchronization_validation: true,
            gpu_assisted_validation: extra == "gpu-assisted",
            best_practices_validation: extra == "best-practices",
            ..Self::default()
        }
    }
}

/// Facts about the chosen device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Device name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Driver name and version string.
    pub driver: String,
    /// Physical-device type.
    pub device_type: vk::PhysicalDeviceType,
    /// Supported Vulkan version.
    pub api_version: u32,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period: f32,
    /// Largest storage-buffer binding in bytes.
    pub max_storage_buffer_range: u32,
    /// Whether pipeline-statistics queries were enabled.
    pub pipeline_statistics: bool,
    /// Whether fragment shaders may write storage buffers (the `bench` fragment counter).
    pub fragment_stores_and_atomics: bool,
    /// Whether `shaderInt64` and `shaderBufferInt64Atomics` were enabled: the compute splat
    /// path ([`crate::FramePath::Splat`]) needs both.
    pub compute_splat: bool,
    /// The renderer's features the device was created with.
    pub renderer_features: DeviceFeatures,
    /// Whether ray queries were enabled (with acceleration structures and buffer device
    /// addresses): the benchmark's traced path (`impostor-traced`) needs them.
    #[cfg(feature = "research")]
    pub ray_query: bool,
    /// Sample counts the device supports for the offscreen attachments: colour, depth and
    /// integer colour (the ID output) alike.
    pub sample_counts: vk::SampleCountFlags,
}

/// Owns every Vulkan object of the standalone path.
pub struct Context {
    // Field order does not drive destruction: `Drop` below does it explicitly.
    allocator: ManuallyDrop<Allocator>,
    device: ash::Device,
    physical_device: vk::PhysicalDevice,
    queue: vk::Queue,
    queue_family: u32,
    info: DeviceInfo,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    instance: ash::Instance,
    _entry: ash::Entry,
    log: MessageLog,
}

impl Context {
    /// Creates instance, device, queue and allocator.
    pub fn new(options: &ContextOptions) -> Result<Self> {
        // SAFETY: loading the system Vulkan loader runs its initialisation; nothing else in the
        // process depends on it being unloaded while `Entry` lives (it is kept in the context).
        let entry = unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))?;
        let log: MessageLog = Arc::new(Mutex::new(Vec::new()));

        if options.validation && !layer_available(&entry, VALIDATION_LAYER)? {
            return Err(Error::NoDevice(
                "validation requested but VK_LAYER_KHRONOS_validation is not installed \
                 (on Debian: apt-get install vulkan-validationlayers)"
                    .into(),
            ));
        }

        let app_name = c"ellipsoid-splat";
        let app = vk::ApplicationInfo::default()
            .application_name(app_name)
            .engine_name(app_name)
            .api_version(vk::API_VERSION_1_3);
        let mut layers: Vec<*const c_char> = Vec::new();
        let mut extensions: Vec<*const c_char> = Vec::new();
        let mut enabled_features = Vec::new();
        if options.validation {
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            if options.synchronization_validation {
                enabled_features.push(vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION);
            }
            if options.gpu_assisted_validation {
                enabled_features.push(vk::ValidationFeatureEnableEXT::GPU_ASSISTED);
            }
            if options.best_practices_validation {
                enabled_features.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES);
            }
        }
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        // Chained into instance creation so messages from vkCreateInstance/vkDestroyInstance
        // are caught too.
        let mut messenger_info = validation::messenger_info(&log);
        let mut create = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if options.validation {
            create = create
                .push_next(&mut messenger_info)
                .push_next(&mut validation_features);
        }
        // SAFETY: every pointer in `create` refers to locals that outlive the call.
        let instance = unsafe { entry.create_instance(&create, None) }.call("vkCreateInstance")?;

        // From here on, every error path destroys what it created, the instance included.
        Self::with_instance(entry, instance, log, options)
    }

    fn with_instance(
        entry: ash::Entry,
        instance: ash::Instance,
        log: MessageLog,
        options: &ContextOptions,
    ) -> Result<Self> {
        let destroy_instance = |instance: &ash::Instance,
                                messenger: Option<(
            ash::ext::debug_utils::Instance,
            vk::DebugUtilsMessengerEXT,
        )>| {
            // SAFETY: on this error path nothing created from the instance is alive any more.
            unsafe {
                if let Some((utils, m)) = messenger {
                    utils.destroy_debug_utils_messenger(m, None);
                }
                instance.destroy_instance(None);
            }
        };

        let messenger = if options.validation {
            let utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let info = validation::messenger_info(&log);
            // SAFETY: `info.user_data` points into `log`, which the context keeps alive.
            match unsafe { utils.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((utils, m)),
                Err(result) => {
                    destroy_instance(&instance, None);
                    return Err(Error::vulkan("vkCreateDebugUtilsMessengerEXT", result));
                }
            }
        } else {
            None
        };

        let device_parts = choose_device(&instance, options.device.as_deref())
            .and_then(|(pd, family)| create_device(&instance, pd, family).map(|d| (pd, family, d)));
        let (physical_device, queue_family, (device, enabled)) = match device_parts {
            Ok(parts) => parts,
            Err(e) => {
                destroy_instance(&instance, messenger);
                return Err(e);
            }
        };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            // The traced path's acceleration structures are built from device addresses.
            buffer_device_address: enabled.ray_query,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: the device was just created and nothing uses it yet.
                unsafe { device.destroy_device(None) };
                destroy_instance(&instance, messenger);
                return Err(Error::Allocation {
                    what: "allocator".into(),
                    reason: e.to_string(),
                });
            }
        };

        // SAFETY: `queue_family` was requested with one queue at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let info = device_info(&instance, physical_device, enabled);
        Ok(Self {
            allocator: ManuallyDrop::new(allocator),
            device,
            physical_device,
            queue,
            queue_family,
            info,
            messenger,
            instance,
            _entry: entry,
            log,
        })
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    /// The instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.instance
    }

    /// The physical device.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical_device
    }

    /// The graphics queue and its family index.
    pub fn queue(&self) -> (vk::Queue, u32) {
        (self.queue, self.queue_family)
    }

    /// The memory allocator.
    pub fn allocator(&mut self) -> &mut Allocator {
        &mut self.allocator
    }

    /// Device and allocator at once (the allocator needs `&mut`, calls need the device).
    pub fn device_and_allocator(&mut self) -> (&ash::Device, &mut Allocator) {
        (&self.device, &mut self.allocator)
    }

    /// Facts about the chosen device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// Every validation message that is not allow-listed, so far.
    pub fn validation_failures(&self) -> Vec<ValidationMessage> {
        validation::failures(&self.log)
    }

    /// `Err` naming the first message if the validation layer reported anything.
    pub fn check_validation(&self) -> Result<()> {
        let failures = self.validation_failures();
        match failures.first() {
            None => Ok(()),
            Some(first) => Err(Error::Validation {
                count: failures.len(),
                first: first.to_string(),
            }),
        }
    }

    /// Number of live allocations the allocator still tracks (0 after everything is freed).
    pub fn live_allocations(&self) -> usize {
        self.allocator.generate_report().allocations.len()
    }

    /// Waits until the device is idle (standalone path only).
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the device is valid; waiting has no other precondition.
        unsafe { self.device.device_wait_idle() }.call("vkDeviceWaitIdle")
    }

    /// Validation messages recorded during teardown can only be seen through this log; tests
    /// keep a clone to check after the context is dropped.
    pub fn message_log(&self) -> MessageLog {
        self.log.clone()
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: the context owns every handle below; all work is finished after the idle
        // wait, and the allocator (which frees its memory blocks) goes before the device.
        unsafe {
            if let Err(e) = self.device.device_wait_idle() {
                log::error!("vkDeviceWaitIdle before destroying the device: {e}");
            }
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((utils, messenger)) = self.messenger.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

fn layer_available(entry: &ash::Entry, name: &CStr) -> Result<bool> {
    // SAFETY: plain query on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .call("vkEnumerateInstanceLayerProperties")?;
    Ok(layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == name)))
}

fn device_name(instance: &ash::Instance, pd: vk::PhysicalDevice) -> String {
    // SAFETY: `pd` was enumerated from `instance`.
    let props = unsafe { instance.get_physical_device_properties(pd) };
    props
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Picks a device with Vulkan 1.3 and a graphics queue: the one named by `wanted` (or
/// `ELLIPSOID_SPLAT_DEVICE`), else a discrete GPU, integrated, virtual, then CPU (lavapipe).
fn choose_device(
    instance: &ash::Instance,
    wanted: Option<&str>,
) -> Result<(vk::PhysicalDevice, u32)> {
    // SAFETY: plain query on a valid instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
    let env = std::env::var("ELLIPSOID_SPLAT_DEVICE").ok();
    let wanted = wanted.map(str::to_owned).or(env);
    let mut candidates = Vec::new();
    for (index, &pd) in devices.iter().enumerate() {
        // SAFETY: `pd` was enumerated from `instance`.
        let props = unsafe { instance.get_physical_device_properties(pd) };
        if props.api_version < vk::API_VERSION_1_3 {
            continue;
        }
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
        let Some(family) = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        else {
            continue;
        };
        let name = device_name(instance, pd);
        if let Some(w) = &wanted {
            let matches = w.parse::<usize>().is_ok_and(|i| i == index) || name.contains(w.as_str());
            if !matches {
                continue;
            }
        }
        let rank = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        };
        candidates.push((rank, pd, family as u32));
    }
    candidates.sort_by_key(|c| c.0);
    match candidates.first() {
        Some(&(_, pd, family)) => Ok((pd, family)),
        None => Err(Error::NoDevice(match wanted {
            Some(w) => format!("no Vulkan 1.3 device with a graphics queue matches '{w}'"),
            None => "no Vulkan 1.3 device with a graphics queue (on Debian: apt-get install \
                     mesa-vulkan-drivers for lavapipe)"
                .into(),
        })),
    }
}

/// The device extensions ray queries need (the benchmark's traced path).
pub(crate) const RAY_QUERY_EXTENSIONS: [&std::ffi::CStr; 3] = [
    ash::khr::acceleration_structure::NAME,
    ash::khr::ray_query::NAME,
    ash::khr::deferred_host_operations::NAME,
];

/// Optional features that were enabled.
#[derive(Clone, Copy)]
struct EnabledFeatures {
    pipeline_statistics: bool,
    fragment_stores_and_atomics: bool,
    /// The renderer's features that were enabled.
    renderer: DeviceFeatures,
    /// Ray queries (the benchmark's traced path, `research` only).
    ray_query: bool,
}

/// Creates the device with dynamic rendering; returns it and the optional features enabled.
fn create_device(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    family: u32,
) -> Result<(ash::Device, EnabledFeatures)> {
    // SAFETY: `pd` was enumerated from `instance`.
    let supported = unsafe { instance.get_physical_device_features(pd) };
    let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut supported2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13);
    // SAFETY: as above; the chain points at locals.
    unsafe { instance.get_physical_device_features2(pd, &mut supported2) };
    // SAFETY: as above.
    let renderer_supported = unsafe { DeviceFeatures::supported(instance, pd) };
    // The offscreen targets are dynamic rendering, possibly multisampled; the compute splat
    // where the device has it.
    let needed = DeviceFeatures {
        dynamic_rendering: true,
        maintenance4: true,
        ..DeviceFeatures::default()
    };
    let missing = needed.missing_from(renderer_supported);
    if !missing.is_empty() {
        return Err(Error::NoDevice(format!(
            "device lacks {}",
            missing.join(", ")
        )));
    }
    let wanted = DeviceFeatures {
        sample_rate_shading: true,
        ..needed.union(DeviceFeatures::COMPUTE_SPLAT)
    };
    let mut renderer = wanted.intersection(renderer_supported);
    if !renderer.contains(DeviceFeatures::COMPUTE_SPLAT) {
        renderer.shader_int64 = false;
        renderer.shader_buffer_int64_atomics = false;
    }
    let enabled = EnabledFeatures {
        pipeline_statistics: supported.pipeline_statistics_query == vk::TRUE,
        fragment_stores_and_atomics: supported.fragment_stores_and_atomics == vk::TRUE,
        renderer,
        // SAFETY: `pd` was enumerated from `instance`.
        ray_query: unsafe { crate::research::ray_query_supported(instance, pd) },
    };
    let (core, features12, features13) = renderer.to_vk();
    let mut features12 = features12.buffer_device_address(enabled.ray_query);
    let features = core
        .pipeline_statistics_query(enabled.pipeline_statistics)
        .fragment_stores_and_atomics(enabled.fragment_stores_and_atomics);
    let mut features13 = features13.synchronization2(supported13.synchronization2 == vk::TRUE);
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let mut structures =
        vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut queries = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
    let extensions: Vec<*const c_char> = if enabled.ray_query {
        RAY_QUERY_EXTENSIONS
            .iter()
            .map(|name| name.as_ptr())
            .collect()
    } else {
        Vec::new()
    };
    let mut create = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_features(&features)
        .enabled_extension_names(&extensions)
        .push_next(&mut features13)
        .push_next(&mut features12);
    if enabled.ray_query {
        create = create.push_next(&mut structures).push_next(&mut queries);
    }
    // SAFETY: every pointer in `create` refers to locals that outlive the call.
    let device = unsafe { instance.create_device(pd, &create, None) }.call("vkCreateDevice")?;
    Ok((device, enabled))
}

fn device_info(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    enabled: EnabledFeatures,
) -> DeviceInfo {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    // SAFETY: `pd` belongs to `instance`; the chain points at locals.
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let props = props2.properties;
    let text = |s: Result<&CStr, _>| {
        s.map(|c: &CStr| c.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let driver_text = format!(
        "{} ({})",
        text(driver.driver_name_as_c_str()),
        text(driver.driver_info_as_c_str())
    );
    let transient =
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
    let sampled = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
    DeviceInfo {
        name: text(props.device_name_as_c_str()),
        driver: driver_text,
        device_type: props.device_type,
        api_version: props.api_version,
        timestamp_period: props.limits.timestamp_period,
        max_storage_buffer_range: props.limits.max_storage_buffer_range,
        pipeline_statistics: enabled.pipeline_statistics,
        fragment_stores_and_atomics: enabled.fragment_stores_and_atomics,
        compute_splat: enabled.renderer.contains(DeviceFeatures::COMPUTE_SPLAT),
        renderer_features: enabled.renderer,
        #[cfg(feature = "research")]
        ray_query: enabled.ray_query,
        // Multisampled depth and ID are sampled too: their sample 0 is fetched.
        sample_counts: props.limits.framebuffer_color_sample_counts
            & props.limits.framebuffer_depth_sample_counts
            & props.limits.sampled_image_depth_sample_counts
            & props.limits.sampled_image_integer_sample_counts
            & attachment_sample_counts(
                instance,
                pd,
                crate::target::Target::NORMAL_FORMAT,
                transient,
            )
            & attachment_sample_counts(instance, pd, crate::target::Target::ID_FORMAT, sampled),
    }
}

/// The sample counts a colour attachment of `format` with `usage` may have (the normal and ID
/// outputs' formats are not covered by the framebuffer limits: the ID is an integer format,
/// for which only one sample is guaranteed).
fn attachment_sample_counts(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    format: vk::Format,
    usage: vk::ImageUsageFlags,
) -> vk::SampleCountFlags {
    // SAFETY: `pd` belongs to `instance`.
    let properties = unsafe {
        instance.get_physical_device_image_format_properties(
            pd,
            format,
            vk::ImageType::TYPE_2D,
            vk::ImageTiling::OPTIMAL,
            usage,
            vk::ImageCreateFlags::empty(),
        )
    };
    properties.map_or(vk::SampleCountFlags::TYPE_1, |p| p.sample_counts)
}
