//! The validation layer's messages: collected by a debug-utils messenger so callers (and every
//! test) can fail on any warning or error.

use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::vk;

/// Messages that are never failures, each with the reason it is harmless.
/// Matched against the message ID name.
pub const ALLOWED_MESSAGES: &[(&str, &str)] = &[(
    "Loader Message",
    "the Vulkan loader reports layers forced on by environment variables; not a validation finding",
)];

/// One message from the validation layer (or the loader).
#[derive(Clone, Debug)]
pub struct ValidationMessage {
    /// `ERROR`, `WARNING`, ...
    pub severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    /// The VUID or message ID name.
    pub id_name: String,
    /// Full text.
    pub text: String,
}

impl std::fmt::Display for ValidationMessage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "[{:?}] {}: {}", self.severity, self.id_name, self.text)
    }
}

/// Shared store the messenger callback writes into.
pub type MessageLog = Arc<Mutex<Vec<ValidationMessage>>>;

/// The messenger's create info; `log` must outlive the messenger (it is kept alive by the
/// `Arc` in [`crate::gpu::Context`]).
pub fn messenger_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
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
        .pfn_user_callback(Some(on_message))
        .user_data(Arc::as_ptr(log) as *mut c_void)
}

/// Messages that count as failures (everything not allow-listed).
pub fn failures(log: &MessageLog) -> Vec<ValidationMessage> {
    let messages = log.lock().unwrap_or_else(|p| p.into_inner());
    messages
        .iter()
        .filter(|m| !ALLOWED_MESSAGES.iter().any(|(id, _)| m.id_name == *id))
        .cloned()
        .collect()
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user_data.is_null() {
        return vk::FALSE;
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call;
    // `user_data` is the `Mutex` inside the `Arc` that the context keeps alive until after the
    // messenger (and the instance, for the chained create info) is destroyed.
    let (data, log) = unsafe {
        (
            &*data,
            &*(user_data as *const Mutex<Vec<ValidationMessage>>),
        )
    };
    let text = |p: *const std::ffi::c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: non-null strings from the layer are NUL-terminated and live for the call.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    let message = ValidationMessage {
        severity,
        id_name: text(data.p_message_id_name),
        text: text(data.p_message),
    };
    // Every message is also logged as it arrives (`scripts/validation-modes.sh` prints them
    // through the test support's logger).
    match message.severity {
        s if s.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) => log::error!("{message}"),
        s if s.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) => log::warn!("{message}"),
        _ => log::info!("{message}"),
    }
    if let Ok(mut log) = log.lock() {
        log.push(message);
    }
    vk::FALSE
}
