//! What a device must enable for the renderer: a host creating its own device passes these to
//! `vkCreateDevice` (the crate's own context does the same).

use ash::vk;

/// The Vulkan 1.3 features the renderer needs: dynamic rendering (it draws inside
/// `vkCmdBeginRendering` passes) and maintenance4 (its compute shader declares its workgroup
/// size with `LocalSizeId`). No Vulkan 1.0 feature is required; `pipelineStatisticsQuery` and
/// `fragmentStoresAndAtomics` are used by `bench` when present.
pub fn required_vulkan13_features() -> vk::PhysicalDeviceVulkan13Features<'static> {
    vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .maintenance4(true)
}

/// The required features `supported` lacks, by name (empty: the device will do).
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
    }
}
