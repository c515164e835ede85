//! The renderer handle and its calls, in the order a host makes them: create, per frame
//! begin a slot, upload or update glyphs, per view the pre-pass and the draw, destroy.
//!
//! Calls on one renderer are not synchronised: the threading rule is the C ABI's, stated once
//! in the header's rules (`docs/c-and-cpp.md`, "Threads").

use ash::vk::{CommandBuffer as VkCommandBuffer, PipelineCache as VkPipelineCache};
use ellipsoid_splat::{EllipsoidRenderer, MemoryAllocator, RendererOptions, Scene};

use crate::allocator::{EsAllocatorCallbacks, RendererMemory, ALLOCATOR_CALLBACKS_V1};
use crate::camera::{read_camera, EsCamera};
use crate::device::{EsDeviceInfo, LoadedDevice, DEVICE_INFO_V1};
use crate::glyphs::{ellipsoids, glyph_slice, EsGlyph};
use crate::settings::{read_settings, EsSettings};
use crate::status::{guard, output, versioned, EsStatus, Failure};
use crate::target::{target_from, EsTargetInfo, TARGET_INFO_V1};

/// A renderer: opaque to the host.
pub struct EsRenderer {
    device: LoadedDevice,
    memory: RendererMemory,
    renderer: Option<EllipsoidRenderer>,
    /// Set when a call panicked: the renderer's state is unknown, so only destruction is
    /// allowed.
    poisoned: bool,
}

impl EsRenderer {
    /// The library renderer (it is there until destruction).
    pub(crate) fn renderer(&mut self) -> Result<&mut EllipsoidRenderer, Failure> {
        self.renderer
            .as_mut()
            .ok_or_else(|| Failure::invalid("renderer", "was destroyed"))
    }

    /// The device, the library renderer and the allocator, borrowed together.
    fn parts(
        &mut self,
    ) -> Result<
        (
            &ash::Device,
            &mut EllipsoidRenderer,
            &mut dyn MemoryAllocator,
        ),
        Failure,
    > {
        let renderer = self
            .renderer
            .as_mut()
            .ok_or_else(|| Failure::invalid("renderer", "was destroyed"))?;
        Ok((&self.device.device, renderer, self.memory.allocator()))
    }
}

/// Runs `body` on the renderer behind `renderer` for the entry point `function`: a null or
/// poisoned renderer is an error, and a panic poisons it.
///
/// # Safety
/// A non-null `renderer` is a live renderer from `es_renderer_create`, used by no other
/// thread during the call.
pub(crate) unsafe fn with_renderer(
    renderer: *mut EsRenderer,
    function: &str,
    body: impl FnOnce(&mut EsRenderer) -> Result<(), Failure>,
) -> EsStatus {
    // SAFETY: caller contract.
    let Some(r) = (unsafe { renderer.as_mut() }) else {
        return guard(function, || Err(Failure::invalid("renderer", "is null")));
    };
    if r.poisoned {
        return guard(function, || {
            Err(Failure {
                status: EsStatus::ErrorPanic,
                message: "an earlier call on this renderer panicked: destroy it".into(),
            })
        });
    }
    let status = guard(function, || body(r));
    if status == EsStatus::ErrorPanic {
        r.poisoned = true;
    }
    status
}

/// What a renderer is made from.
#[repr(C)]
pub struct EsRendererCreateInfo {
    /// `sizeof(EsRendererCreateInfo)`.
    pub struct_size: u32,
    /// The host's device (borrowed).
    pub device: *const EsDeviceInfo,
    /// The pass the ellipsoids are drawn into first (`es_renderer_set_target` adds more).
    pub target: *const EsTargetInfo,
    /// The host's allocator callbacks, or null for the library's own allocator.
    pub allocator: *const EsAllocatorCallbacks,
    /// The settings, or null for `es_settings_default`'s.
    pub settings: *const EsSettings,
    /// How many frames the host records before waiting for the oldest (1 ..= 16).
    pub frames_in_flight: u32,
    /// The host's pipeline cache for every pipeline the renderer builds (borrowed), or
    /// `VK_NULL_HANDLE`.
    pub pipeline_cache: VkPipelineCache,
}

/// The size of the first version of [`EsRendererCreateInfo`] (64-bit targets), frozen.
const CREATE_INFO_V1: usize = 56;
// Growing the struct is a new version: the library must then read only the prefix a
// host of an older version allocated (its `struct_size`), not this whole struct.
const _: () = assert!(std::mem::size_of::<EsRendererCreateInfo>() == CREATE_INFO_V1);

/// Makes a renderer on the host's device and writes its handle to `out_renderer` (null on
/// failure). It checks the queue family, the enabled features, the target's formats and
/// sample count, and names what is missing. Any thread.
///
/// # Safety
/// `info` and what it points at are valid; the handles belong together, the device has the
/// features `enabled_features` names enabled, and they, the render pass and the pipeline
/// cache outlive the renderer; the allocator callbacks (if any) allocate from that device.
/// `out_renderer` points at a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_create(
    info: *const EsRendererCreateInfo,
    out_renderer: *mut *mut EsRenderer,
) -> EsStatus {
    guard("es_renderer_create", || {
        // SAFETY: caller contract.
        let out = unsafe { output(out_renderer, "out_renderer")? };
        *out = std::ptr::null_mut();
        // SAFETY: caller contract.
        let info = unsafe { versioned(info, "create info", CREATE_INFO_V1)? };
        // SAFETY: caller contract.
        let device_info = unsafe { versioned(info.device, "device", DEVICE_INFO_V1)? };
        // SAFETY: caller contract.
        let target_info = unsafe { versioned(info.target, "target", TARGET_INFO_V1)? };
        let callbacks = if info.allocator.is_null() {
            None
        } else {
            // SAFETY: caller contract.
            Some(unsafe { versioned(info.allocator, "allocator", ALLOCATOR_CALLBACKS_V1)? })
        };
        // SAFETY: caller contract on `color_formats`.
        let target = unsafe { target_from(target_info)? };
        let mut options = RendererOptions::new(target);
        options.frames_in_flight = info.frames_in_flight;
        options.pipeline_cache = info.pipeline_cache;
        // The plain values are checked before anything is loaded or made.
        if !info.settings.is_null() {
            // SAFETY: caller contract.
            options.settings = unsafe { read_settings(info.settings, &options.settings)? };
        }
        // SAFETY: caller contract: valid handles and loader.
        let device = unsafe { LoadedDevice::load(device_info)? };
        // SAFETY: caller contract: the device is loaded from the host's valid handles.
        let mut memory = unsafe { RendererMemory::new(callbacks, &device)? };
        // SAFETY: caller contract: the handles belong together, the features are enabled,
        // the allocator allocates from the device, the borrowed objects outlive the renderer.
        let renderer =
            unsafe { EllipsoidRenderer::new(&device.host(), memory.allocator(), options)? };
        *out = Box::into_raw(Box::new(EsRenderer {
            device,
            memory,
            renderer: Some(renderer),
            poisoned: false,
        }));
        Ok(())
    })
}

/// Destroys `renderer` and everything it made (a null `renderer` is fine). The GPU must be
/// done with every command buffer the renderer recorded into. Nothing of the host's is
/// destroyed. The handle is gone after the call whatever the status (a failure only reports
/// what could not be freed). Thread: the renderer's.
///
/// # Safety
/// A non-null `renderer` came from `es_renderer_create` and is not used again.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_destroy(renderer: *mut EsRenderer) -> EsStatus {
    if renderer.is_null() {
        return EsStatus::Success;
    }
    guard("es_renderer_destroy", || {
        // SAFETY: caller contract: made by `es_renderer_create` with `Box::into_raw`.
        let mut owned = unsafe { Box::from_raw(renderer) };
        if let Some(library) = owned.renderer.take() {
            let allocator = owned.memory.allocator();
            // SAFETY: caller contract: the GPU is done; the device and allocator are the
            // renderer's own.
            unsafe { library.destroy(&owned.device.device, allocator) };
        }
        // The library's own allocator (if any) goes after everything allocated from it.
        drop(owned);
        Ok(())
    })
}

/// Makes `target` the pass the next frames are drawn into (its pipelines are built on first
/// use and kept). Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `target` points at a valid `EsTargetInfo` whose render pass (if any)
/// outlives the renderer.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_set_target(
    renderer: *mut EsRenderer,
    target: *const EsTargetInfo,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_set_target", |r| {
            let target = target_from(versioned(target, "target", TARGET_INFO_V1)?)?;
            r.renderer()?.set_target(target)?;
            Ok(())
        })
    }
}

/// Replaces the settings (the material costs nothing; other changes build their pipelines
/// on first use). Fields of versions later than the struct's `struct_size` keep their
/// values. A bad value (an unknown `plan_mode`, say) is refused and changes nothing.
/// Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `settings` points at a valid `EsSettings` of its `struct_size`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_set_settings(
    renderer: *mut EsRenderer,
    settings: *const EsSettings,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_set_settings", |r| {
            let library = r.renderer()?;
            let settings = read_settings(settings, library.settings())?;
            library.set_settings(settings);
            Ok(())
        })
    }
}

/// Starts frame slot `slot` (in `0..frames_in_flight`), once the host has waited for that
/// slot's fence: frees what was replaced while earlier frames could still read it. Call it
/// first in every frame. Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; every command buffer recorded with it since `slot` last began has
/// finished executing.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_begin_frame(renderer: *mut EsRenderer, slot: u32) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_begin_frame", |r| {
            let (device, library, allocator) = r.parts()?;
            library.begin_frame(device, allocator, slot)?;
            Ok(())
        })
    }
}

/// Records the upload of a whole scene of `count` glyphs into `command_buffer` (outside any
/// pass): a staged copy between barriers. Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `glyphs` points at `count` glyphs (read during the call only);
/// `command_buffer` is recording outside any pass, for the renderer's queue family, and is
/// submitted before (or is) the command buffer that draws this scene.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_upload(
    renderer: *mut EsRenderer,
    command_buffer: VkCommandBuffer,
    glyphs: *const EsGlyph,
    count: usize,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_upload", |r| {
            let scene = Scene::new(ellipsoids(glyph_slice(glyphs, count)?, 0)?);
            let (device, library, allocator) = r.parts()?;
            library.upload(device, allocator, command_buffer, &scene)?;
            Ok(())
        })
    }
}

/// Records the replacement of glyphs `first .. first + count` of the uploaded scene (outside
/// any pass). Thread: the renderer's.
///
/// # Safety
/// As for `es_renderer_upload`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_update(
    renderer: *mut EsRenderer,
    command_buffer: VkCommandBuffer,
    first: u32,
    glyphs: *const EsGlyph,
    count: usize,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_update", |r| {
            let updated = ellipsoids(glyph_slice(glyphs, count)?, first as usize)?;
            let (device, library, allocator) = r.parts()?;
            library.update(device, allocator, command_buffer, first, &updated)?;
            Ok(())
        })
    }
}

/// Records the pre-pass of one view with `camera` into `command_buffer`, outside any pass.
/// The first call of a frame is view 0, the next view 1 (up to 64); each view's draw
/// (`es_renderer_record` with the same camera) follows in the host's pass. Thread: the
/// renderer's.
///
/// # Safety
/// `renderer` is live; `camera` points at a valid `EsCamera`; `command_buffer` is recording
/// outside any pass, for the renderer's queue family, and is submitted before the frame slot
/// that is current begins again.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_record_prepass(
    renderer: *mut EsRenderer,
    command_buffer: VkCommandBuffer,
    camera: *const EsCamera,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_record_prepass", |r| {
            let camera = read_camera(camera)?;
            let (device, library, allocator) = r.parts()?;
            library.record_prepass(device, allocator, command_buffer, &camera)?;
            Ok(())
        })
    }
}

/// Records the draw of the view whose pre-pass had `camera` into `command_buffer`, inside
/// the host's pass (render pass subpass or dynamic rendering matching the target of that
/// pre-pass). It binds its own pipeline, descriptor set and push constants and sets viewport
/// and scissor to the camera's rectangle: the host rebinds its own state afterwards.
/// Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `camera` points at a valid `EsCamera`; `command_buffer` is recording
/// inside a pass compatible with the view's target whose attachments hold the camera's
/// rectangle.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_record(
    renderer: *mut EsRenderer,
    command_buffer: VkCommandBuffer,
    camera: *const EsCamera,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_record", |r| {
            let camera = read_camera(camera)?;
            let (device, library, allocator) = r.parts()?;
            library.record(device, allocator, command_buffer, &camera)?;
            Ok(())
        })
    }
}

/// Writes the bytes of GPU memory the renderer's buffers take (as its allocator gave them)
/// to `out_bytes`. Thread: the renderer's.
///
/// # Safety
/// `renderer` is live; `out_bytes` points at a writable `uint64_t`.
#[no_mangle]
pub unsafe extern "C" fn es_renderer_gpu_memory_bytes(
    renderer: *mut EsRenderer,
    out_bytes: *mut u64,
) -> EsStatus {
    // SAFETY: caller contract.
    unsafe {
        with_renderer(renderer, "es_renderer_gpu_memory_bytes", |r| {
            *output(out_bytes, "out_bytes")? = r.renderer()?.gpu_memory_bytes();
            Ok(())
        })
    }
}
