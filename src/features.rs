//! The device features the renderer uses, by name: what a target needs
//! ([`crate::Target::required_features`]), what the compute splat needs on top
//! ([`DeviceFeatures::COMPUTE_SPLAT`]), what a host enabled ([`crate::HostDevice`]) and what a
//! device supports, and the structures `vkCreateDevice` takes for them.

use ash::vk;

/// A set of the device features the renderer may use. A host creating its device enables the
/// union of its targets' [`crate::Target::required_features`] (and
/// [`DeviceFeatures::COMPUTE_SPLAT`] where supported) with its own, and tells the renderer
/// what it enabled in [`crate::HostDevice::enabled_features`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct DeviceFeatures {
    /// Vulkan 1.3 `dynamicRendering`: targets drawn inside `vkCmdBeginRendering`
    /// (`Pass::Dynamic`).
    pub dynamic_rendering: bool,
    /// Vulkan 1.3 `maintenance4`: the pre-pass's compute shaders (culling, the compute
    /// splat) declare their workgroup size with SPIR-V 1.6's `LocalSizeId`.
    pub maintenance4: bool,
    /// Vulkan 1.0 `sampleRateShading`: multisampled targets where the renderer shades every
    /// sample (`Settings::per_sample_shading`, or sample counts and devices without the
    /// standard sample locations).
    pub sample_rate_shading: bool,
    /// Vulkan 1.0 `shaderInt64`: the compute splat's 64-bit keys.
    pub shader_int64: bool,
    /// Vulkan 1.2 `shaderBufferInt64Atomics`: the compute splat's atomic nearest hit.
    pub shader_buffer_int64_atomics: bool,
}

impl DeviceFeatures {
    /// What the compute splat needs on top of a target's features (the plan splats only
    /// where the host enabled them).
    pub const COMPUTE_SPLAT: Self = Self {
        dynamic_rendering: false,
        maintenance4: false,
        sample_rate_shading: false,
        shader_int64: true,
        shader_buffer_int64_atomics: true,
    };

    /// Every feature of `self` or `other`.
    pub fn union(self, other: Self) -> Self {
        Self {
            dynamic_rendering: self.dynamic_rendering || other.dynamic_rendering,
            maintenance4: self.maintenance4 || other.maintenance4,
            sample_rate_shading: self.sample_rate_shading || other.sample_rate_shading,
            shader_int64: self.shader_int64 || other.shader_int64,
            shader_buffer_int64_atomics: self.shader_buffer_int64_atomics
                || other.shader_buffer_int64_atomics,
        }
    }

    /// Every feature of both.
    pub fn intersection(self, other: Self) -> Self {
        Self {
            dynamic_rendering: self.dynamic_rendering && other.dynamic_rendering,
            maintenance4: self.maintenance4 && other.maintenance4,
            sample_rate_shading: self.sample_rate_shading && other.sample_rate_shading,
            shader_int64: self.shader_int64 && other.shader_int64,
            shader_buffer_int64_atomics: self.shader_buffer_int64_atomics
                && other.shader_buffer_int64_atomics,
        }
    }

    /// Whether every feature of `other` is in `self`.
    pub fn contains(self, other: Self) -> bool {
        self.union(other) == self
    }

    /// The Vulkan names of the features in the set.
    pub fn names(self) -> Vec<&'static str> {
        [
            (self.dynamic_rendering, "dynamicRendering"),
            (self.maintenance4, "maintenance4"),
            (self.sample_rate_shading, "sampleRateShading"),
            (self.shader_int64, "shaderInt64"),
            (self.shader_buffer_int64_atomics, "shaderBufferInt64Atomics"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }

    /// The features of `self` that `enabled` lacks, by name (empty: all there).
    pub fn missing_from(self, enabled: Self) -> Vec<&'static str> {
        let mut lacking = self;
        lacking.dynamic_rendering &= !enabled.dynamic_rendering;
        lacking.maintenance4 &= !enabled.maintenance4;
        lacking.sample_rate_shading &= !enabled.sample_rate_shading;
        lacking.shader_int64 &= !enabled.shader_int64;
        lacking.shader_buffer_int64_atomics &= !enabled.shader_buffer_int64_atomics;
        lacking.names()
    }

    /// The features `physical_device` supports.
    ///
    /// # Safety
    /// `physical_device` was enumerated from `instance`.
    pub unsafe fn supported(instance: &ash::Instance, physical_device: vk::PhysicalDevice) -> Self {
        let mut vulkan12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut vulkan13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut all = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut vulkan12)
            .push_next(&mut vulkan13);
        // SAFETY: caller contract; the chain points at locals that outlive the call.
        unsafe { instance.get_physical_device_features2(physical_device, &mut all) };
        let core = all.features;
        Self {
            dynamic_rendering: vulkan13.dynamic_rendering == vk::TRUE,
            maintenance4: vulkan13.maintenance4 == vk::TRUE,
            sample_rate_shading: core.sample_rate_shading == vk::TRUE,
            shader_int64: core.shader_int64 == vk::TRUE,
            shader_buffer_int64_atomics: vulkan12.shader_buffer_int64_atomics == vk::TRUE,
        }
    }

    /// The set as the structures `vkCreateDevice` takes: `core` as `pEnabledFeatures` (or
    /// `VkPhysicalDeviceFeatures2::features`), `vulkan12` and `vulkan13` chained into
    /// `pNext`. Merge them with the host's own features.
    pub fn to_vk(
        self,
    ) -> (
        vk::PhysicalDeviceFeatures,
        vk::PhysicalDeviceVulkan12Features<'static>,
        vk::PhysicalDeviceVulkan13Features<'static>,
    ) {
        (
            vk::PhysicalDeviceFeatures::default()
                .sample_rate_shading(self.sample_rate_shading)
                .shader_int64(self.shader_int64),
            vk::PhysicalDeviceVulkan12Features::default()
                .shader_buffer_int64_atomics(self.shader_buffer_int64_atomics),
            vk::PhysicalDeviceVulkan13Features::default()
                .dynamic_rendering(self.dynamic_rendering)
                .maintenance4(self.maintenance4),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_what_is_missing() {
        let target = DeviceFeatures {
            dynamic_rendering: true,
            maintenance4: true,
            ..DeviceFeatures::default()
        };
        assert_eq!(
            target.missing_from(DeviceFeatures::default()),
            ["dynamicRendering", "maintenance4"]
        );
        assert!(target.missing_from(target).is_empty());
        let all = target.union(DeviceFeatures::COMPUTE_SPLAT);
        assert!(all.contains(target) && all.contains(DeviceFeatures::COMPUTE_SPLAT));
        assert!(!target.contains(all));
        assert_eq!(all.intersection(target), target);
        let (core, vulkan12, vulkan13) = all.to_vk();
        assert_eq!(core.shader_int64, vk::TRUE);
        assert_eq!(core.sample_rate_shading, vk::FALSE);
        assert_eq!(vulkan12.shader_buffer_int64_atomics, vk::TRUE);
        assert_eq!(vulkan13.dynamic_rendering, vk::TRUE);
    }
}
