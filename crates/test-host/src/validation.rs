//! The Khronos validation layer: which checks are on, and the debug-utils messenger that
//! collects every warning and error into a log the host's user reads.

use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::vk;

use crate::{fail, HostResult};

/// The layer's name.
pub(crate) const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Where the messenger writes `<message id name>: <message>` for each warning and error. It
/// must outlive the messenger and the instance (whose create info chains a messenger too).
pub(crate) type MessageLog = Arc<Mutex<Vec<String>>>;

/// Fails unless the validation layer is installed.
pub(crate) fn require_layer(entry: &ash::Entry) -> HostResult<()> {
    // SAFETY: a global query with no inputs.
    let available = unsafe { entry.enumerate_instance_layer_properties() }
        .map_err(fail("vkEnumerateInstanceLayerProperties"))?;
    if available
        .iter()
        .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
    {
        return Ok(());
    }
    Err(
        "validation requested but VK_LAYER_KHRONOS_validation is not installed \
         (Debian: vulkan-validationlayers)"
            .into(),
    )
}

/// Synchronization validation always; the opt-in extra modes of the project's
/// `scripts/validation-modes.sh` through the same environment variable as its tests.
pub(crate) fn enabled_checks() -> Vec<vk::ValidationFeatureEnableEXT> {
    let mut enabled = vec![vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    match std::env::var("ELLIPSOID_SPLAT_EXTRA_VALIDATION").as_deref() {
        Ok("gpu-assisted") => enabled.push(vk::ValidationFeatureEnableEXT::GPU_ASSISTED),
        Ok("best-practices") => enabled.push(vk::ValidationFeatureEnableEXT::BEST_PRACTICES),
        _ => {}
    }
    enabled
}

/// A messenger reporting every warning and error into `log` through [`collect_message`].
/// `log` must outlive the messenger (see [`MessageLog`]).
pub(crate) fn messenger_info(log: &MessageLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
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
        .pfn_user_callback(Some(collect_message))
        .user_data(Arc::as_ptr(log) as *mut c_void)
}

/// Debug-utils callback: appends `<message id name>: <message>` to the [`MessageLog`] passed
/// as user data, skipping the loader's informational "Loader Message"s.
unsafe extern "system" fn collect_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user_data.is_null() {
        return vk::FALSE;
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call, and
    // `user_data` is `Arc::as_ptr` of the log's `Mutex`, which the host keeps alive longer
    // than the messenger and the instance.
    let (data, log) = unsafe { (&*data, &*(user_data as *const Mutex<Vec<String>>)) };
    // SAFETY: the strings are null or NUL-terminated and valid during the callback.
    let (id, text) = unsafe { (data.message_id_name_as_c_str(), data.message_as_c_str()) };
    let id = id.map(CStr::to_string_lossy).unwrap_or_default();
    if id == "Loader Message" {
        return vk::FALSE;
    }
    let text = text.map(CStr::to_string_lossy).unwrap_or_default();
    // The project's validation-modes script counts messages printed in this form.
    if std::env::var_os("ELLIPSOID_SPLAT_PRINT_VALIDATION").is_some() {
        let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            "ERROR"
        } else {
            "WARNING"
        };
        eprintln!("[{level}] {id}: {text}");
    }
    if let Ok(mut log) = log.lock() {
        log.push(format!("{id}: {text}"));
    }
    vk::FALSE
}
