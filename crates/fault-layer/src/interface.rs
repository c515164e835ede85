//! The loader-layer interface: the negotiation the loader calls first, the layer's
//! `vkGetInstanceProcAddr` and `vkGetDeviceProcAddr`, and instance and device creation, which
//! find the next layer in the loader's chain info and pass the chain on. The loader's structs
//! (`vk_layer.h`) are not in ash; the few fields read here are declared as that header lays
//! them out.

use std::ffi::{c_char, c_void, CStr};

use ash::vk::{self, Handle};

use crate::control::{arm_from_environment, decide, Class, Decision};
use crate::dispatch;
use crate::intercepts;

/// `VK_LAYER_LINK_INFO`: the chain-info struct that carries the next layer's entry points.
const LAYER_LINK_INFO: u32 = 0;
/// `LAYER_NEGOTIATE_INTERFACE_STRUCT`.
const NEGOTIATE_INTERFACE_STRUCT: u32 = 1;
/// The loader-layer interface version this layer speaks.
const INTERFACE_VERSION: u32 = 2;

/// `VkNegotiateLayerInterface`.
#[repr(C)]
pub struct NegotiateLayerInterface {
    s_type: u32,
    p_next: *mut c_void,
    loader_layer_interface_version: u32,
    get_instance_proc_addr: Option<vk::PFN_vkGetInstanceProcAddr>,
    get_device_proc_addr: Option<vk::PFN_vkGetDeviceProcAddr>,
    get_physical_device_proc_addr: vk::PFN_vkVoidFunction,
}

/// `VkLayerInstanceLink`.
#[repr(C)]
struct InstanceLink {
    next: *mut InstanceLink,
    next_get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    next_get_physical_device_proc_addr: vk::PFN_vkVoidFunction,
}

/// `VkLayerDeviceLink`.
#[repr(C)]
struct DeviceLink {
    next: *mut DeviceLink,
    next_get_instance_proc_addr: vk::PFN_vkGetInstanceProcAddr,
    next_get_device_proc_addr: vk::PFN_vkGetDeviceProcAddr,
}

/// `VkLayerInstanceCreateInfo` and `VkLayerDeviceCreateInfo` as far as the link: their union
/// starts with the link pointer when `function` is `VK_LAYER_LINK_INFO`.
#[repr(C)]
struct ChainInfo<L> {
    s_type: vk::StructureType,
    p_next: *const c_void,
    function: u32,
    link: *mut L,
}

/// The loader's link-info struct of type `s_type` in the `p_next` chain starting at `p_next`.
///
/// # Safety
/// `p_next` is a valid Vulkan `pNext` chain.
unsafe fn chain_info<L>(mut p_next: *const c_void, s_type: vk::StructureType) -> *mut ChainInfo<L> {
    while !p_next.is_null() {
        let info = p_next as *mut ChainInfo<L>;
        // SAFETY: every struct of a pNext chain starts with sType and pNext; the loader's
        // chain info of `s_type` has the layout of `ChainInfo`.
        unsafe {
            if (*info).s_type == s_type && (*info).function == LAYER_LINK_INFO {
                return info;
            }
            p_next = (*info).p_next;
        }
    }
    std::ptr::null_mut()
}

/// The loader's first call: agrees on interface version 2 and hands over the layer's two
/// `GetProcAddr`s.
///
/// # Safety
/// `interface` points at the loader's negotiation struct.
#[no_mangle]
pub unsafe extern "system" fn vkNegotiateLoaderLayerInterfaceVersion(
    interface: *mut NegotiateLayerInterface,
) -> vk::Result {
    // SAFETY: caller contract.
    let Some(interface) = (unsafe { interface.as_mut() }) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    if interface.s_type != NEGOTIATE_INTERFACE_STRUCT
        || interface.loader_layer_interface_version < 2
    {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    }
    interface.loader_layer_interface_version = INTERFACE_VERSION;
    interface.get_instance_proc_addr = Some(get_instance_proc_addr);
    interface.get_device_proc_addr = Some(get_device_proc_addr);
    interface.get_physical_device_proc_addr = None;
    vk::Result::SUCCESS
}

/// A function pointer as the loader receives it.
fn void_fn(f: *const ()) -> vk::PFN_vkVoidFunction {
    // SAFETY: `f` is one of this layer's `extern "system"` entry points, non-null.
    Some(unsafe { std::mem::transmute::<*const (), unsafe extern "system" fn()>(f) })
}

/// The layer's own instance-level entry points.
fn instance_entry(name: &CStr) -> vk::PFN_vkVoidFunction {
    match name.to_bytes() {
        b"vkGetInstanceProcAddr" => void_fn(get_instance_proc_addr as *const ()),
        b"vkGetDeviceProcAddr" => void_fn(get_device_proc_addr as *const ()),
        b"vkCreateInstance" => void_fn(create_instance as *const ()),
        b"vkDestroyInstance" => void_fn(destroy_instance as *const ()),
        b"vkCreateDevice" => void_fn(create_device as *const ()),
        _ => None,
    }
}

/// The layer's `vkGetInstanceProcAddr`: its own entry points, the rest from the next layer.
unsafe extern "system" fn get_instance_proc_addr(
    instance: vk::Instance,
    name: *const c_char,
) -> vk::PFN_vkVoidFunction {
    if name.is_null() {
        return None;
    }
    // SAFETY: the loader passes a NUL-terminated name.
    let name = unsafe { CStr::from_ptr(name) };
    if let Some(f) = instance_entry(name) {
        return Some(f);
    }
    if instance.is_null() {
        return None;
    }
    // SAFETY: a live instance the loader passes.
    let key = unsafe { dispatch::key(instance.as_raw() as *const c_void) };
    let next = dispatch::instance_next(key)?;
    // SAFETY: the next layer's entry point with its instance and a NUL-terminated name.
    unsafe { next(instance, name.as_ptr()) }
}

/// The layer's `vkGetDeviceProcAddr`: its intercepts where the layers below have the call,
/// the rest from the next layer.
unsafe extern "system" fn get_device_proc_addr(
    device: vk::Device,
    name: *const c_char,
) -> vk::PFN_vkVoidFunction {
    if name.is_null() || device.is_null() {
        return None;
    }
    // SAFETY: the loader passes a NUL-terminated name.
    let name = unsafe { CStr::from_ptr(name) };
    // SAFETY: a live device the loader passes.
    let key = unsafe { dispatch::key(device.as_raw() as *const c_void) };
    let below = dispatch::device_next(key, name);
    match name.to_bytes() {
        b"vkGetDeviceProcAddr" => void_fn(get_device_proc_addr as *const ()),
        b"vkDestroyDevice" => void_fn(destroy_device as *const ()),
        _ => below.and_then(|_| intercepts::entry(name)).or(below),
    }
}

unsafe extern "system" fn create_instance(
    info: *const vk::InstanceCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    instance: *mut vk::Instance,
) -> vk::Result {
    // SAFETY: the loader's create info carries its chain info.
    let chain = unsafe {
        chain_info::<InstanceLink>(
            (*info).p_next,
            vk::StructureType::LOADER_INSTANCE_CREATE_INFO,
        )
    };
    // SAFETY: non-null chain info from the loader holds a valid link.
    let Some(link) = (unsafe { chain.as_mut() }).and_then(|c| unsafe { c.link.as_ref() }) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let next_gipa = link.next_get_instance_proc_addr;
    // SAFETY: the next layer's entry point for a global command.
    let Some(next_create) =
        (unsafe { next_gipa(vk::Instance::null(), c"vkCreateInstance".as_ptr()) })
    else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    arm_from_environment();
    if let Decision::Fail(result) = decide(Class::Creates, c"vkCreateInstance") {
        return result;
    }
    // SAFETY: the layers below get the chain one link further on, as the loader requires.
    unsafe { (*chain).link = link.next };
    // SAFETY: `vkCreateInstance`'s pointer type; the caller's arguments.
    let next_create: vk::PFN_vkCreateInstance = unsafe { std::mem::transmute(next_create) };
    // SAFETY: the caller's arguments, passed down.
    let result = unsafe { next_create(info, allocator, instance) };
    if result == vk::Result::SUCCESS {
        // SAFETY: just created through `next_gipa`.
        unsafe { dispatch::add_instance(*instance, next_gipa) };
    }
    result
}

unsafe extern "system" fn destroy_instance(
    instance: vk::Instance,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    if instance.is_null() {
        return;
    }
    // SAFETY: a live instance.
    let key = unsafe { dispatch::key(instance.as_raw() as *const c_void) };
    let Some(next_gipa) = dispatch::instance_next(key) else {
        return;
    };
    dispatch::remove_instance(key);
    // SAFETY: the next layer's entry point.
    if let Some(f) = unsafe { next_gipa(instance, c"vkDestroyInstance".as_ptr()) } {
        // SAFETY: `vkDestroyInstance`'s pointer type; the caller's arguments.
        let f: vk::PFN_vkDestroyInstance = unsafe { std::mem::transmute(f) };
        // SAFETY: the caller's arguments.
        unsafe { f(instance, allocator) };
    }
}

unsafe extern "system" fn create_device(
    physical_device: vk::PhysicalDevice,
    info: *const vk::DeviceCreateInfo<'_>,
    allocator: *const vk::AllocationCallbacks<'_>,
    device: *mut vk::Device,
) -> vk::Result {
    // SAFETY: the loader's create info carries its chain info.
    let chain = unsafe {
        chain_info::<DeviceLink>((*info).p_next, vk::StructureType::LOADER_DEVICE_CREATE_INFO)
    };
    // SAFETY: non-null chain info from the loader holds a valid link.
    let Some(link) = (unsafe { chain.as_mut() }).and_then(|c| unsafe { c.link.as_ref() }) else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    let (next_gipa, next_gdpa) = (
        link.next_get_instance_proc_addr,
        link.next_get_device_proc_addr,
    );
    // SAFETY: the next layer's entry point (the loader resolves it without an instance).
    let Some(next_create) =
        (unsafe { next_gipa(vk::Instance::null(), c"vkCreateDevice".as_ptr()) })
    else {
        return vk::Result::ERROR_INITIALIZATION_FAILED;
    };
    match decide(Class::CreatesDevice, c"vkCreateDevice") {
        Decision::Fail(result) => return result,
        Decision::Lost => return vk::Result::ERROR_DEVICE_LOST,
        Decision::Pass => {}
    }
    // SAFETY: the layers below get the chain one link further on.
    unsafe { (*chain).link = link.next };
    // SAFETY: `vkCreateDevice`'s pointer type.
    let next_create: vk::PFN_vkCreateDevice = unsafe { std::mem::transmute(next_create) };
    // SAFETY: the caller's arguments, passed down.
    let result = unsafe { next_create(physical_device, info, allocator, device) };
    if result == vk::Result::SUCCESS {
        // SAFETY: just created through the layers below.
        unsafe { dispatch::add_device(*device, next_gdpa) };
    }
    result
}

unsafe extern "system" fn destroy_device(
    device: vk::Device,
    allocator: *const vk::AllocationCallbacks<'_>,
) {
    if device.is_null() {
        return;
    }
    let handle = device.as_raw() as *const c_void;
    // SAFETY: a live device made through this layer.
    let destroy: vk::PFN_vkDestroyDevice = unsafe { dispatch::next(handle, c"vkDestroyDevice") };
    // SAFETY: a live device.
    dispatch::remove_device(unsafe { dispatch::key(handle) });
    // SAFETY: the caller's arguments.
    unsafe { destroy(device, allocator) };
}
