//! The host's Vulkan instance and, with validation, its debug messenger.

use std::sync::{Arc, Mutex};

use ash::vk;

use crate::validation::{self, MessageLog, VALIDATION_LAYER};
use crate::{fail, HostResult};

/// A Vulkan 1.3 instance, its messenger, and the log the messenger writes into. Destroys the
/// messenger and the instance when dropped, after everything made from them (the [`Host`]
/// holding it drops its device first).
///
/// [`Host`]: crate::Host
pub(crate) struct HostInstance {
    /// The loaded Vulkan library; dropped (unloaded) after the instance is destroyed.
    entry: ash::Entry,
    instance: ash::Instance,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Dropped after the messenger and the instance that write into it.
    log: MessageLog,
}

impl HostInstance {
    /// Creates a Vulkan 1.3 instance. With `validation`, enables the Khronos validation layer
    /// with synchronization validation and collects every warning and error.
    pub(crate) fn new(validation: bool) -> HostResult<HostInstance> {
        // SAFETY: loading the system Vulkan loader; nothing else runs its initialisation.
        let entry = unsafe { ash::Entry::load() }.map_err(fail("loading the Vulkan loader"))?;
        // SAFETY: a global query with no inputs.
        let version = unsafe { entry.try_enumerate_instance_version() }
            .map_err(fail("vkEnumerateInstanceVersion"))?
            .unwrap_or(vk::API_VERSION_1_0);
        if version < vk::API_VERSION_1_3 {
            return Err("the Vulkan loader does not support Vulkan 1.3".into());
        }

        let log = Arc::new(Mutex::new(Vec::new()));
        let app_info = vk::ApplicationInfo::default()
            .application_name(c"embed-host")
            .api_version(vk::API_VERSION_1_3);
        let mut layers = Vec::new();
        let mut extensions = Vec::new();
        if validation {
            validation::require_layer(&entry)?;
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        let checks = validation::enabled_checks();
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&checks);
        let mut instance_messenger = validation::messenger_info(&log);
        let mut instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation {
            // Chained messenger: also reports problems in vkCreateInstance/vkDestroyInstance.
            instance_info = instance_info
                .push_next(&mut validation_features)
                .push_next(&mut instance_messenger);
        }
        // SAFETY: every pointer in `instance_info` refers to locals alive during the call; the
        // messenger's user data (`log`) is moved into the result and outlives the instance.
        let instance = unsafe { entry.create_instance(&instance_info, None) }
            .map_err(fail("vkCreateInstance"))?;
        // From here on `Drop` destroys the instance (and the messenger once there is one).
        let mut owned = HostInstance {
            entry,
            instance,
            messenger: None,
            log,
        };
        if validation {
            let utils = ash::ext::debug_utils::Instance::new(&owned.entry, &owned.instance);
            // A fresh create info: the one above is now linked into the instance's pNext chain.
            let info = validation::messenger_info(&owned.log);
            // SAFETY: the instance enables VK_EXT_debug_utils; the info's user data is the log,
            // which outlives the messenger.
            let messenger = unsafe { utils.create_debug_utils_messenger(&info, None) }
                .map_err(fail("vkCreateDebugUtilsMessengerEXT"))?;
            owned.messenger = Some((utils, messenger));
        }
        Ok(owned)
    }

    /// The Vulkan instance.
    pub(crate) fn instance(&self) -> &ash::Instance {
        &self.instance
    }

    /// The log itself, shared (it outlives the instance in the caller's hands).
    pub(crate) fn message_log(&self) -> MessageLog {
        self.log.clone()
    }

    /// A copy of the validation warnings and errors collected so far (`<id>: <message>`).
    pub(crate) fn messages(&self) -> Vec<String> {
        self.log.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

impl Drop for HostInstance {
    fn drop(&mut self) {
        // SAFETY: the messenger and the instance were created here, and the owner of this
        // instance destroyed everything it made from it first; child before parent.
        unsafe {
            if let Some((utils, messenger)) = self.messenger.take() {
                utils.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
