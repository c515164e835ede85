//! What a device must enable for the renderer: a host creating its own device passes these to
//! `vkCreateDevice` (the crate's own context does the same).

use ash::vk;

/// The Vulkan 1.3 features the renderer needs: dynamic rendering (its own offscreen path and
/// `Pass::Dynamic` targets draw inside `vkCmdBeginRendering` passes) and maintenance4 (its
/// compute shader declares its workgroup size with `LocalSizeId`).
pub fn required_vulkan13_features() -> vk::PhysicalDeviceVulkan13Features<'static> {
    vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .maintenance4(true)
}

/// The Vulkan 1.0 features the renderer needs: `sampleRateShading`, for multisampled targets
/// only (each sample is ray cast on its own). `pipelineStatisticsQuery` and
/// `fragmentStoresAndAtomics` are used by `bench` when present.
pub fn required_core_features() -> vk::PhysicalDeviceFeatures {
    vk::PhysicalDeviceFeatures::default().sample_rate_shading(true)
}

/// Everything a host enables for the renderer, in the structures `vkCreateDevice` takes:
/// `core` as `pEnabledFeatures` (or `VkPhysicalDeviceFeatures2::features`), `vulkan13` chained
/// into `pNext`. Merge them with the host's own features.
pub fn required_device_features() -> (
    vk::PhysicalDeviceFeatures,
    vk::PhysicalDeviceVulkan13Features<'static>,
) {
    (required_core_features(), required_vulkan13_features())
}

/// The features the compute splat path needs on top ([`crate::Settings::compute_splat`]):
/// `shaderInt64` (Vulkan 1.0) and `shaderBufferInt64Atomics` (Vulkan 1.2), for the 64-bit
/// atomic that keeps each pixel's nearest hit. A host enables them where the device has them,
/// and only then turns the path on.
pub fn compute_splat_features() -> (
    vk::PhysicalDeviceFeatures,
    vk::PhysicalDeviceVulkan12Features<'static>,
) {
    (
        vk::PhysicalDeviceFeatures::default().shader_int64(true),
        vk::PhysicalDeviceVulkan12Features::default().shader_buffer_int64_atomics(true),
    )
}

/// The features a physical device supports: Vulkan 1.0 and 1.3.
pub fn supported_features(
    instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
) -> (
    vk::PhysicalDeviceFeatures,
    vk::PhysicalDeviceVulkan13Features<'static>,
) {
    let mut vulkan13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut all = vk::PhysicalDeviceFeatures2::default().push_next(&mut vulkan13);
    // SAFETY: the caller guarantees `physical_device` comes from `instance`; the chain points
    // at locals that outlive the call.
    unsafe { instance.get_physical_device_features2(physical_device, &mut all) };
    let core = all.features;
    vulkan13.p_next = std::ptr::null_mut();
    (core, vulkan13)
}

/// The always-required features `supported` lacks, by name (empty: the device will do).
pub fn missing_features(supported: &vk::PhysicalDeviceVulkan13Features) -> Vec<&'static str> {
    let required = required_vulkan13_features();
    let mut missing = Vec::new();
    if required.dynamic_rendering == vk::TRUE && supported.dynamic_rendering == vk::FALSE {
        missing.push("dynamicRendering");
    }
    if required.maintenance4 == vk::TRUE && supported.maintenance4 == vk::FALSE {
        missing.push("maintenance4");
    }
    missing
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_what_a_device_lacks() {
        let none = vk::PhysicalDeviceVulkan13Features::default();
        assert_eq!(
            missing_features(&none),
            ["dynamicRendering", "maintenance4"]
        );
        assert!(missing_features(&required_vulkan13_features()).is_empty());
        assert_eq!(required_device_features().0.sample_rate_shading, vk::TRUE);
    }
}
