//! The library's error type: every failure names where it happened and why. (The loaders
//! and the tool have their own, for files.)

use ash::vk;

/// Everything that can go wrong in `ellipsoid-splat`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A Vulkan call failed; `call` is the entry point's name.
    #[error("{call} failed: {result:?}")]
    Vulkan {
        /// The Vulkan entry point, e.g. `vkCreateDevice`.
        call: &'static str,
        /// What the driver returned.
        result: vk::Result,
    },
    /// The Vulkan loader (`libvulkan.so.1`) could not be opened.
    #[error(
        "cannot load the Vulkan library: {0} (on Debian: apt-get install mesa-vulkan-drivers)"
    )]
    Loader(String),
    /// No usable physical device or a missing capability.
    #[error("no suitable Vulkan device: {0}")]
    NoDevice(String),
    /// The device was lost (a GPU fault, reset or driver crash) during `call`: nothing more can
    /// be done with it; destroy the renderer and make a new device (what each call does
    /// meanwhile: `docs/design.md` §6.10).
    #[error("the Vulkan device was lost during {call}: create a new renderer (device) to go on")]
    DeviceLost {
        /// The Vulkan entry point that reported the loss, e.g. `vkQueueSubmit`.
        call: &'static str,
    },
    /// Device or host memory ran out while creating `what`. The call changed nothing (a failed
    /// upload keeps the scene uploaded before): the renderer stays usable
    /// (`docs/design.md` §6.10).
    #[error("out of {} memory while creating {what}: {reason}", if *.device { "GPU" } else { "host" })]
    OutOfMemory {
        /// What was being allocated (a buffer's name, or the kind of object) and the Vulkan
        /// call that ran out, e.g. `ellipsoid instances (vkCreateBuffer)`.
        what: String,
        /// GPU (device) memory rather than host memory.
        device: bool,
        /// The driver's or allocator's words.
        reason: String,
    },
    /// GPU memory allocation failed for another reason than running out.
    #[error("GPU allocation of {what} failed: {reason}")]
    Allocation {
        /// What was being allocated.
        what: String,
        /// The allocator's message.
        reason: String,
    },
    /// The validation layer reported a message while validation was required to be clean.
    #[error("validation layer reported {count} message(s); first: {first}")]
    Validation {
        /// How many messages were recorded.
        count: usize,
        /// The first message's text.
        first: String,
    },
    /// An argument or value is outside what the renderer accepts.
    #[error("invalid {what}: {reason}")]
    Invalid {
        /// What was invalid (e.g. `camera.near`, `ellipsoid 12 radii`).
        what: String,
        /// Why.
        reason: String,
    },
}

/// Shorthand for `Result<T, ellipsoid_splat::Error>`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// The error of a failed Vulkan call: device loss and out-of-memory get their own
    /// variants, so callers can react (recreate the device, shrink the scene). Out of memory
    /// names the kind of object the call makes.
    pub fn vulkan(call: &'static str, result: vk::Result) -> Self {
        Self::creating(allocated_by(call), call, result)
    }

    /// As [`Error::vulkan`], for a call made to create `what` (a buffer's name, say), which
    /// running out of memory names.
    pub fn creating(what: &str, call: &'static str, result: vk::Result) -> Self {
        match result {
            vk::Result::ERROR_DEVICE_LOST => Error::DeviceLost { call },
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
                Error::OutOfMemory {
                    what: format!("{what} ({call})"),
                    device: result == vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
                    reason: format!("{result:?}"),
                }
            }
            result => Error::Vulkan { call, result },
        }
    }

    /// An `Invalid` error from two displayable parts.
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Invalid {
            what: what.into(),
            reason: reason.into(),
        }
    }
}

/// What the Vulkan entry point `call` allocates, for an out-of-memory error.
fn allocated_by(call: &str) -> &'static str {
    match call {
        "vkCreateInstance" => "the Vulkan instance",
        "vkCreateDevice" => "the Vulkan device",
        "vkCreateDebugUtilsMessengerEXT" => "the validation messenger",
        "vkAllocateMemory" => "device memory",
        "vkMapMemory" => "a mapping of device memory",
        "vkBindBufferMemory" | "vkBindImageMemory" => "a memory binding",
        "vkCreateBuffer" => "a buffer",
        "vkCreateImage" => "an image",
        "vkCreateImageView" => "an image view",
        "vkCreateSampler" => "a sampler",
        "vkCreateShaderModule" => "a shader module",
        "vkCreatePipelineLayout" => "a pipeline layout",
        "vkCreateDescriptorSetLayout" => "a descriptor set layout",
        "vkCreateGraphicsPipelines" => "a graphics pipeline",
        "vkCreateComputePipelines" => "a compute pipeline",
        "vkCreateDescriptorPool" => "a descriptor pool",
        "vkAllocateDescriptorSets" => "descriptor sets",
        "vkCreateQueryPool" => "a query pool",
        "vkCreateCommandPool" => "a command pool",
        "vkAllocateCommandBuffers" => "a command buffer",
        "vkResetCommandPool" | "vkBeginCommandBuffer" | "vkEndCommandBuffer" => "recorded commands",
        "vkCreateFence" | "vkResetFences" => "a fence",
        "vkQueueSubmit" | "vkQueueSubmit2" => "a queue submission",
        _ => "what the call makes",
    }
}

/// Extension to name the Vulkan call on a `VkResult`.
pub(crate) trait VkCall<T> {
    /// Turns a raw `VkResult` into the crate error naming `call`.
    fn call(self, call: &'static str) -> Result<T>;
}

impl<T> VkCall<T> for std::result::Result<T, vk::Result> {
    fn call(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::vulkan(call, result))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn device_loss_and_memory_exhaustion_are_typed() {
        let lost = Err::<(), _>(vk::Result::ERROR_DEVICE_LOST).call("vkQueueSubmit");
        assert!(matches!(
            lost,
            Err(Error::DeviceLost {
                call: "vkQueueSubmit"
            })
        ));
        let oom = Error::vulkan("vkAllocateMemory", vk::Result::ERROR_OUT_OF_DEVICE_MEMORY);
        assert!(
            matches!(oom, Error::OutOfMemory { device: true, .. }),
            "{oom}"
        );
        assert!(oom.to_string().contains("out of GPU memory"), "{oom}");
        assert!(
            oom.to_string().contains("device memory (vkAllocateMemory)"),
            "{oom}"
        );
        let named = Error::creating(
            "ellipsoid instances",
            "vkCreateBuffer",
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
        );
        assert!(
            named
                .to_string()
                .contains("creating ellipsoid instances (vkCreateBuffer)"),
            "{named}"
        );
        let host = Error::vulkan("vkCreateBuffer", vk::Result::ERROR_OUT_OF_HOST_MEMORY);
        assert!(
            matches!(host, Error::OutOfMemory { device: false, .. }),
            "{host}"
        );
        let other = Error::vulkan("vkCreateBuffer", vk::Result::ERROR_UNKNOWN);
        assert!(matches!(other, Error::Vulkan { .. }));
    }
}
