//! Where each intercepted call goes next: the next layer's (or the driver's) entry points,
//! per instance and per device, keyed by the loader's dispatch pointer, which an instance
//! shares with its physical devices and a device with its queues and command buffers.

use std::collections::HashMap;
use std::ffi::{c_void, CStr};
use std::sync::Mutex;

use ash::vk;

/// The dispatch key of a dispatchable handle: the first pointer-sized word it points at.
///
/// # Safety
/// `handle` is a live dispatchable Vulkan handle made by the loader.
pub(crate) unsafe fn key(handle: *const c_void) -> usize {
    // SAFETY: caller contract: the loader's dispatchable objects begin with the dispatch
    // table pointer.
    unsafe { *(handle as *const usize) }
}

#[derive(Clone, Copy)]
struct DeviceNext {
    device: vk::Device,
    get_device_proc_addr: vk::PFN_vkGetDeviceProcAddr,
}

static INSTANCES: Mutex<Vec<(usize, vk::PFN_vkGetInstanceProcAddr)>> = Mutex::new(Vec::new());
static DEVICES: Mutex<Option<HashMap<usize, DeviceNext>>> = Mutex::new(None);

/// Remembers the next `vkGetInstanceProcAddr` of `instance`.
///
/// # Safety
/// `instance` was just created through `next`.
pub(crate) unsafe fn add_instance(instance: vk::Instance, next: vk::PFN_vkGetInstanceProcAddr) {
    use ash::vk::Handle;
    // SAFETY: caller contract.
    let key = unsafe { key(instance.as_raw() as *const c_void) };
    let mut instances = INSTANCES.lock().unwrap_or_else(|p| p.into_inner());
    instances.retain(|(k, _)| *k != key);
    instances.push((key, next));
}

/// The next `vkGetInstanceProcAddr` of the instance (or physical device) with dispatch `key`.
pub(crate) fn instance_next(key: usize) -> Option<vk::PFN_vkGetInstanceProcAddr> {
    let instances = INSTANCES.lock().unwrap_or_else(|p| p.into_inner());
    instances.iter().find(|(k, _)| *k == key).map(|(_, f)| *f)
}

/// Forgets the instance with dispatch `key`.
pub(crate) fn remove_instance(key: usize) {
    let mut instances = INSTANCES.lock().unwrap_or_else(|p| p.into_inner());
    instances.retain(|(k, _)| *k != key);
}

/// Remembers the next `vkGetDeviceProcAddr` of `device`.
///
/// # Safety
/// `device` was just created through the layers below.
pub(crate) unsafe fn add_device(device: vk::Device, next: vk::PFN_vkGetDeviceProcAddr) {
    use ash::vk::Handle;
    // SAFETY: caller contract.
    let key = unsafe { key(device.as_raw() as *const c_void) };
    let mut devices = DEVICES.lock().unwrap_or_else(|p| p.into_inner());
    devices.get_or_insert_with(HashMap::new).insert(
        key,
        DeviceNext {
            device,
            get_device_proc_addr: next,
        },
    );
}

/// Forgets the device with dispatch `key`.
pub(crate) fn remove_device(key: usize) {
    let mut devices = DEVICES.lock().unwrap_or_else(|p| p.into_inner());
    if let Some(devices) = devices.as_mut() {
        devices.remove(&key);
    }
}

/// The next layer's `name` for the device (or its queue or command buffer) with dispatch
/// `key`, if the layers below have it.
pub(crate) fn device_next(key: usize, name: &CStr) -> vk::PFN_vkVoidFunction {
    let next = {
        let devices = DEVICES.lock().unwrap_or_else(|p| p.into_inner());
        devices.as_ref().and_then(|d| d.get(&key)).copied()
    }?;
    // SAFETY: the next layer's entry point with its own live device and a NUL-terminated name.
    unsafe { (next.get_device_proc_addr)(next.device, name.as_ptr()) }
}

/// The device of the dispatchable `handle` (a device, queue or command buffer).
pub(crate) fn device_of(handle: *const c_void) -> Option<vk::Device> {
    // SAFETY: the callers pass live handles of devices made through this layer.
    let key = unsafe { key(handle) };
    let devices = DEVICES.lock().unwrap_or_else(|p| p.into_inner());
    devices.as_ref()?.get(&key).map(|d| d.device)
}

/// The next layer's `name` for the dispatchable `handle`, as the function type `F`.
///
/// # Safety
/// `handle` is a live device, queue or command buffer of a device made through this layer,
/// and `F` is the function pointer type of `name`.
pub(crate) unsafe fn next<F: Copy>(handle: *const c_void, name: &CStr) -> F {
    // SAFETY: caller contract.
    let key = unsafe { key(handle) };
    let Some(f) = device_next(key, name) else {
        // The layer only hands out its own entry points where the layers below have them.
        panic!("fault layer: no next {name:?} for the device");
    };
    assert_eq!(size_of::<F>(), size_of::<unsafe extern "system" fn()>());
    // SAFETY: caller contract: `F` is the pointer type of `name`, the same size as `f`.
    unsafe { std::mem::transmute_copy(&f) }
}
