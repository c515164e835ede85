//! The viewer's own Vulkan objects as an engine would make them: an instance with the
//! window system's surface extensions (and, with `--validation`, the Khronos layer with
//! synchronization validation), a surface for the window, a device with the renderer's
//! features and the swapchain extension, one queue and an allocator.

use std::ffi::c_char;
use std::mem::ManuallyDrop;

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

use crate::error::{Error, Result};
use ellipsoid_splat::internals::validation::{self, MessageLog};
// The viewer's own Vulkan plumbing fails as the renderer's does.
use ellipsoid_splat::Error as VulkanError;
use ellipsoid_splat::{DeviceFeatures, HostDevice};

use super::VkCall;

const VALIDATION_LAYER: &std::ffi::CStr = c"VK_LAYER_KHRONOS_validation";

/// Instance, surface, device, queue and allocator; dropped in reverse order of creation.
/// Everything made from the device must be destroyed before this is dropped.
pub struct Gpu {
    /// The device's allocator (dropped before the device).
    allocator: ManuallyDrop<Allocator>,
    /// The logical device.
    pub device: ash::Device,
    /// The graphics, compute and present queue.
    pub queue: vk::Queue,
    /// Its family.
    pub queue_family: u32,
    /// The physical device behind `device`.
    pub physical_device: vk::PhysicalDevice,
    /// The renderer's features the device enables: its dynamic-rendering target's, and the
    /// compute splat's where supported (as `render`'s context does).
    pub features: DeviceFeatures,
    /// The device's name, for the summary line.
    pub name: String,
    /// `VK_KHR_swapchain` entry points.
    pub swapchain_loader: ash::khr::swapchain::Device,
    /// `VK_KHR_surface` entry points.
    pub surface_loader: ash::khr::surface::Instance,
    /// The window's surface (destroyed before the instance).
    pub surface: vk::SurfaceKHR,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Validation messages so far (empty without `--validation`).
    log: MessageLog,
    /// The instance.
    pub instance: ash::Instance,
    _entry: ash::Entry,
}

impl Gpu {
    /// Everything for `window`: `device` picks a device by index or name (as `render`'s
    /// `--device`), `validation` turns the layer on.
    pub fn new(window: &Window, device: Option<&str>, validation: bool) -> Result<Self> {
        // SAFETY: loads the system's Vulkan loader; the entry lives in `Gpu`.
        let entry =
            unsafe { ash::Entry::load() }.map_err(|e| VulkanError::Loader(e.to_string()))?;
        let display = window
            .display_handle()
            .map_err(|e| Error::invalid("window", format!("no display handle: {e}")))?
            .as_raw();
        let window_handle = window
            .window_handle()
            .map_err(|e| Error::invalid("window", format!("no window handle: {e}")))?
            .as_raw();
        let mut extensions: Vec<*const c_char> = ash_window::enumerate_required_extensions(display)
            .call("vkEnumerateInstanceExtensionProperties (surface)")?
            .to_vec();
        let mut layers = Vec::new();
        if validation {
            // SAFETY: plain query of the loader.
            let available = unsafe { entry.enumerate_instance_layer_properties() }
                .call("vkEnumerateInstanceLayerProperties")?;
            let found = available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
            if !found {
                return Err(VulkanError::NoDevice(
                    "--validation needs VK_LAYER_KHRONOS_validation (on Debian: apt-get install \
                     vulkan-validationlayers)"
                        .into(),
                )
                .into());
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        let log = MessageLog::default();
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        // Also catches messages of instance creation and destruction.
        let mut messenger_info = validation::messenger_info(&log);
        let app = vk::ApplicationInfo::default()
            .application_name(c"ellipsoid-splat view")
            .api_version(vk::API_VERSION_1_3);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation {
            info = info.push_next(&mut messenger_info).push_next(&mut features);
        }
        // SAFETY: the create info points at locals that outlive the call.
        let instance = unsafe { entry.create_instance(&info, None) }.call("vkCreateInstance")?;
        let messenger = if validation {
            let utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let info = validation::messenger_info(&log);
            // SAFETY: valid create info; `log` outlives the messenger (both in `Gpu`).
            match unsafe { utils.create_debug_utils_messenger(&info, None) } {
                Ok(m) => Some((utils, m)),
                Err(e) => {
                    // SAFETY: nothing else was made from the instance.
                    unsafe { instance.destroy_instance(None) };
                    return Err(Error::vulkan("vkCreateDebugUtilsMessengerEXT", e));
                }
            }
        } else {
            None
        };
        let surface_loader = ash::khr::surface::Instance::new(&entry, &instance);
        // SAFETY: the handles come from a live window, which outlives the surface (the viewer
        // destroys the `Gpu` before it drops the window).
        let surface =
            unsafe { ash_window::create_surface(&entry, &instance, display, window_handle, None) };
        let destroy_instance = |messenger: Option<(ash::ext::debug_utils::Instance, _)>| {
            // SAFETY: only the messenger was made from the instance besides the surface,
            // which the caller destroyed already.
            unsafe {
                if let Some((utils, m)) = messenger {
                    utils.destroy_debug_utils_messenger(m, None);
                }
                instance.destroy_instance(None);
            }
        };
        let surface = match surface {
            Ok(s) => s,
            Err(e) => {
                destroy_instance(messenger);
                return Err(Error::vulkan("vkCreate*SurfaceKHR", e));
            }
        };
        let made = choose_device(&instance, &surface_loader, surface, device).and_then(
            |(physical, family, name)| {
                create_device(&instance, physical, family)
                    .map(|(d, features)| (physical, family, name, d, features))
            },
        );
        let (physical_device, queue_family, name, device, features) = match made {
            Ok(parts) => parts,
            Err(e) => {
                // SAFETY: nothing uses the surface.
                unsafe { surface_loader.destroy_surface(surface, None) };
                destroy_instance(messenger);
                return Err(e);
            }
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: nothing was made from the device; the surface is unused.
                unsafe {
                    device.destroy_device(None);
                    surface_loader.destroy_surface(surface, None);
                }
                destroy_instance(messenger);
                return Err(VulkanError::Allocation {
                    what: "allocator".into(),
                    reason: e.to_string(),
                }
                .into());
            }
        };
        // SAFETY: the device was created with one queue in `queue_family`.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let swapchain_loader = ash::khr::swapchain::Device::new(&instance, &device);
        Ok(Self {
            allocator: ManuallyDrop::new(allocator),
            device,
            queue,
            queue_family,
            physical_device,
            features,
            name,
            swapchain_loader,
            surface_loader,
            surface,
            messenger,
            log,
            instance,
            _entry: entry,
        })
    }

    /// The device and its allocator at once (calls need both).
    pub fn device_and_allocator(&mut self) -> (&ash::Device, &mut Allocator) {
        (&self.device, &mut self.allocator)
    }

    /// The allocator.
    pub fn allocator(&mut self) -> &mut Allocator {
        &mut self.allocator
    }

    /// The renderer's view of the device.
    pub fn host(&self) -> HostDevice<'_> {
        HostDevice::new(
            &self.instance,
            self.physical_device,
            &self.device,
            self.queue_family,
            self.features,
        )
    }

    /// Bytes of device memory the allocator holds for every object of the viewer (renderer,
    /// targets, readback buffers).
    pub fn allocated_bytes(&self) -> u64 {
        self.allocator.generate_report().total_capacity_bytes
    }

    /// The store of validation messages (shared: it outlives the `Gpu`).
    pub fn message_log(&self) -> MessageLog {
        self.log.clone()
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        // SAFETY: the viewer destroyed everything made from the device and waited for it to
        // be idle; each object goes once, children before parents.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            self.surface_loader.destroy_surface(self.surface, None);
            if let Some((utils, messenger)) = self.messenger.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// A Vulkan 1.3 device with a queue family for graphics, compute and presenting to
/// `surface`: the one `wanted` names (index or part of the name, else
/// `ELLIPSOID_SPLAT_DEVICE`), else the first discrete, integrated, virtual, then CPU device.
fn choose_device(
    instance: &ash::Instance,
    surface_loader: &ash::khr::surface::Instance,
    surface: vk::SurfaceKHR,
    wanted: Option<&str>,
) -> Result<(vk::PhysicalDevice, u32, String)> {
    // SAFETY: plain query of a live instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
    let wanted = wanted
        .map(str::to_owned)
        .or_else(|| std::env::var("ELLIPSOID_SPLAT_DEVICE").ok());
    let mut candidates = Vec::new();
    for (index, &physical) in devices.iter().enumerate() {
        // SAFETY: `physical` was enumerated from `instance`.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let name = props
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if let Some(w) = &wanted {
            if !(w.parse::<usize>().is_ok_and(|i| i == index) || name.contains(w.as_str())) {
                continue;
            }
        }
        if props.api_version < vk::API_VERSION_1_3 {
            continue;
        }
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let wanted_flags = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let family = (0..families.len() as u32).find(|&f| {
            families[f as usize].queue_flags.contains(wanted_flags)
                // SAFETY: `f` is a family of `physical`; the surface is live.
                && unsafe {
                    surface_loader.get_physical_device_surface_support(physical, f, surface)
                }
                .unwrap_or(false)
        });
        let Some(family) = family else { continue };
        let rank = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        };
        candidates.push((rank, physical, family, name));
    }
    candidates.sort_by_key(|c| c.0);
    candidates
        .into_iter()
        .next()
        .map(|(_, physical, family, name)| (physical, family, name))
        .ok_or_else(|| {
            Error::from(VulkanError::NoDevice(match wanted {
                Some(w) => format!(
                    "no Vulkan 1.3 device matching '{w}' can draw and present to this window"
                ),
                None => "no Vulkan 1.3 device can draw and present to this window (on Debian: \
                         apt-get install mesa-vulkan-drivers for lavapipe)"
                    .into(),
            }))
        })
}

/// The device with the features its target needs, the compute splat's where supported (the
/// same choice `render` makes, so both draw the same way), and `VK_KHR_swapchain`.
fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    family: u32,
) -> Result<(ash::Device, DeviceFeatures)> {
    // SAFETY: `physical` belongs to `instance`.
    let supported = unsafe { DeviceFeatures::supported(instance, physical) };
    // The viewer's one target: dynamic rendering, one sample.
    let mut needed = DeviceFeatures::default();
    needed.dynamic_rendering = true;
    needed.maintenance4 = true;
    let missing = needed.missing_from(supported);
    if !missing.is_empty() {
        return Err(VulkanError::NoDevice(format!("device lacks {}", missing.join(", "))).into());
    }
    let features = if supported.contains(DeviceFeatures::COMPUTE_SPLAT) {
        needed.union(DeviceFeatures::COMPUTE_SPLAT)
    } else {
        needed
    };
    let (core, mut vulkan12, mut vulkan13) = features.to_vk();
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let extensions = [ash::khr::swapchain::NAME.as_ptr()];
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .enabled_features(&core)
        .push_next(&mut vulkan13)
        .push_next(&mut vulkan12);
    // SAFETY: every pointer in `info` refers to locals that outlive the call.
    let device = unsafe { instance.create_device(physical, &info, None) }.call("vkCreateDevice")?;
    Ok((device, features))
}
