//! The library's error type: every failure names where it happened and why. It has only what
//! the renderer itself can meet: Vulkan results, allocation failures (named), invalid arguments (naming where
//! and why), missing device support, shader and pipeline failures; device loss and running out of
//! memory have variants of their own (below, on [`Error`]). The loaders have their own
//! (`crates/loaders/src/error.rs`: parse errors with file and line, I/O, invalid scenes, and the
//! library's errors wrapped) and the tool its own (`crates/tool/src/error.rs`: the library's and
//! the loaders' wrapped, invalid arguments, I/O, image encoding).

use ash::vk;

/// Everything that can go wrong in `ellipsoid-splat`.
///
/// # Device loss and running out of memory
///
/// What a host sees when the GPU runs out of memory or is lost, through every API: the Rust
/// `Error`, the C ABI's `EsStatus` and `es_last_error()`, the Python package's exceptions. No panic
/// reaches the host in either case, and destroying the renderer frees everything it made and
/// nothing of the host's.
///
/// - **Out of memory** (`Error::OutOfMemory`, `ES_STATUS_ERROR_OUT_OF_MEMORY`, Python's
///   `OutOfMemoryError`, a `DeviceError`): a Vulkan call, or the host's allocator, ran out while
///   the renderer made something; the message names it (a buffer by its name, as in
///   `out of GPU memory while creating ellipsoid instances (vkCreateBuffer)`, else the kind of
///   object and the call). The call changed nothing the renderer draws, so it stays usable: free
///   memory (a smaller scene, fewer or smaller views) and go on. An upload or update is staged
///   first (its buffers made, its bytes in a staging buffer: `src/renderer/staged.rs`) and taken
///   in only once that succeeded -- by the offscreen renderer only once its submission completed --
///   so a failed one keeps the scene uploaded before; a buffer is replaced only once its
///   successor exists; and a failed `vkQueueSubmit` ran nothing (the spec says so), so the
///   offscreen renderer records again at the next call (`src/offscreen/submission.rs`).
/// - **Device lost** (`Error::DeviceLost { call }`, `ES_STATUS_ERROR_DEVICE_LOST`, Python's
///   `DeviceLostError`): `call` names the entry point that reported it (`vkQueueSubmit`,
///   `vkWaitForFences`, ...). The offscreen renderer and the Python package then fail every later
///   call that needs the GPU with the same error, and draw nothing. The embedded renderer never
///   submits or waits: it records as before, and the host sees the loss in its own submissions
///   and waits. Either way the renderer is done: wait for the device to be idle (on a lost device
///   the wait returns, reporting the loss), destroy the renderer, make a new device.
/// - **A host's own failures.** The embedded renderer takes an upload or update in when it is
///   recorded: if the host then does not submit that command buffer, or its submission fails, the
///   renderer draws glyphs that never reached the GPU -- upload them again.
///
/// `crates/fault-layer` tests this (`docs/testing.md`): a Vulkan layer of the tests' own makes the N-th call
/// of a typical host's run fail, for every N.
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
    /// meanwhile: the type's documentation).
    #[error("the Vulkan device was lost during {call}: create a new renderer (device) to go on")]
    DeviceLost {
        /// The Vulkan entry point that reported the loss, e.g. `vkQueueSubmit`.
        call: &'static str,
    },
    /// Device or host memory ran out while creating `what`. The call changed nothing (a failed
    /// upload keeps the scene uploaded before): the renderer stays usable
    /// (the type's documentation).
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
        "vkCreateBufferView" => "a texel view of a buffer",
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
