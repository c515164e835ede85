//! The host's device, from raw handles and `vkGetInstanceProcAddr`, and the feature bits the
//! host enabled.

use std::ffi::c_char;

use ash::vk::{
    Device as VkDevice, Instance as VkInstance, PFN_vkVoidFunction,
    PhysicalDevice as VkPhysicalDevice,
};
use ellipsoid_splat::DeviceFeatures;

use crate::status::Failure;

/// `maintenance4` (Vulkan 1.3): every target needs it.
pub const ES_FEATURE_MAINTENANCE4: u32 = 1;
/// `dynamicRendering` (Vulkan 1.3): targets drawn with dynamic rendering need it.
pub const ES_FEATURE_DYNAMIC_RENDERING: u32 = 2;
/// `sampleRateShading`: multisampled targets need it.
pub const ES_FEATURE_SAMPLE_RATE_SHADING: u32 = 4;
/// `shaderInt64`: with the next, lets frames of many small glyphs take the compute splat.
pub const ES_FEATURE_SHADER_INT64: u32 = 8;
/// `shaderBufferInt64Atomics` (Vulkan 1.2): with the previous, the compute splat.
pub const ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS: u32 = 16;

/// `vkGetInstanceProcAddr`: the loader's (or the host's) entry point every other Vulkan
/// function is looked up through.
pub type EsGetInstanceProcAddr =
    Option<unsafe extern "system" fn(VkInstance, *const c_char) -> PFN_vkVoidFunction>;

/// The host's Vulkan objects (borrowed: never destroyed by the library; they must outlive
/// the renderer) and the features it enabled on the device.
#[repr(C)]
pub struct EsDeviceInfo {
    /// `sizeof(EsDeviceInfo)`.
    pub struct_size: u32,
    /// The loader's (or the host's) `vkGetInstanceProcAddr`; every other entry point is
    /// loaded through it.
    pub get_instance_proc_addr: EsGetInstanceProcAddr,
    /// The instance the device was created from.
    pub instance: VkInstance,
    /// The physical device behind `device`.
    pub physical_device: VkPhysicalDevice,
    /// The host's device.
    pub device: VkDevice,
    /// The family of the queue that will run the command buffers the renderer records into:
    /// graphics and compute.
    pub queue_family_index: u32,
    /// The `ES_FEATURE_*` bits the host enabled on `device` (at least
    /// `es_target_required_features` of every target).
    pub enabled_features: u32,
}

/// The size of the first version of [`EsDeviceInfo`] (64-bit targets), frozen.
pub(crate) const DEVICE_INFO_V1: usize = 48;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsDeviceInfo>() == DEVICE_INFO_V1);

/// The features of `bits`.
pub(crate) fn features_from_bits(bits: u32) -> Result<DeviceFeatures, Failure> {
    let known = ES_FEATURE_MAINTENANCE4
        | ES_FEATURE_DYNAMIC_RENDERING
        | ES_FEATURE_SAMPLE_RATE_SHADING
        | ES_FEATURE_SHADER_INT64
        | ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS;
    if bits & !known != 0 {
        return Err(Failure::invalid(
            "enabled_features",
            format!("unknown bits {:#x}", bits & !known),
        ));
    }
    let mut features = DeviceFeatures::default();
    features.maintenance4 = bits & ES_FEATURE_MAINTENANCE4 != 0;
    features.dynamic_rendering = bits & ES_FEATURE_DYNAMIC_RENDERING != 0;
    features.sample_rate_shading = bits & ES_FEATURE_SAMPLE_RATE_SHADING != 0;
    features.shader_int64 = bits & ES_FEATURE_SHADER_INT64 != 0;
    features.shader_buffer_int64_atomics = bits & ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS != 0;
    Ok(features)
}

/// The bits of `features`.
pub(crate) fn bits_from_features(features: DeviceFeatures) -> u32 {
    [
        (features.maintenance4, ES_FEATURE_MAINTENANCE4),
        (features.dynamic_rendering, ES_FEATURE_DYNAMIC_RENDERING),
        (features.sample_rate_shading, ES_FEATURE_SAMPLE_RATE_SHADING),
        (features.shader_int64, ES_FEATURE_SHADER_INT64),
        (
            features.shader_buffer_int64_atomics,
            ES_FEATURE_SHADER_BUFFER_INT64_ATOMICS,
        ),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .fold(0, |bits, (_, bit)| bits | bit)
}

/// The host's instance and device with their entry points loaded.
pub(crate) struct LoadedDevice {
    pub instance: ash::Instance,
    pub device: ash::Device,
    pub physical_device: VkPhysicalDevice,
    pub queue_family_index: u32,
    pub enabled: DeviceFeatures,
}

impl LoadedDevice {
    /// Loads the entry points of the host's handles.
    ///
    /// # Safety
    /// `info`'s handles are valid and belong together, and `get_instance_proc_addr` is a
    /// Vulkan loader's.
    pub unsafe fn load(info: &EsDeviceInfo) -> Result<Self, Failure> {
        let get_instance_proc_addr = info
            .get_instance_proc_addr
            .ok_or_else(|| Failure::invalid("EsDeviceInfo.get_instance_proc_addr", "is null"))?;
        for (name, null) in [
            ("instance", info.instance == VkInstance::null()),
            (
                "physical_device",
                info.physical_device == VkPhysicalDevice::null(),
            ),
            ("device", info.device == VkDevice::null()),
        ] {
            if null {
                return Err(Failure::invalid(&format!("EsDeviceInfo.{name}"), "is null"));
            }
        }
        let enabled = features_from_bits(info.enabled_features)?;
        let static_fn = ash::StaticFn {
            get_instance_proc_addr,
        };
        // SAFETY: the caller's handles and loader function; ash only looks entry points up.
        let (instance, device) = unsafe {
            let instance = ash::Instance::load(&static_fn, info.instance);
            let device = ash::Device::load(instance.fp_v1_0(), info.device);
            (instance, device)
        };
        Ok(Self {
            instance,
            device,
            physical_device: info.physical_device,
            queue_family_index: info.queue_family_index,
            enabled,
        })
    }

    /// The library's view of the host's device.
    pub fn host(&self) -> ellipsoid_splat::HostDevice<'_> {
        ellipsoid_splat::HostDevice::new(
            &self.instance,
            self.physical_device,
            &self.device,
            self.queue_family_index,
            self.enabled,
        )
    }
}
