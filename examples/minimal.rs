//! The smallest complete host (`cargo run --release --example minimal`): its own instance and
//! device, a colour and a depth image, one frame drawn with dynamic rendering, the covered pixels
//! counted; only `ash`, `gpu-allocator`, `glam` and the library. Exits non-zero on any validation
//! message. Vulkan calls are kept one to a line (`rustfmt::skip`); `examples/embed` is the full host.

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use ash::vk::{self, ImageLayout as Layout};
#[rustfmt::skip]
use ellipsoid_splat::{Camera, Ellipsoid, EllipsoidRenderer, HostDevice, RendererOptions, Scene, Target};
use glam::{DQuat, DVec3};
#[rustfmt::skip]
use gpu_allocator::{vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc}, MemoryLocation};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;
#[rustfmt::skip]
const SIZE: vk::Extent2D = vk::Extent2D { width: 320, height: 240 };
const COLOR: vk::Format = vk::Format::R8G8B8A8_UNORM;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT;
static MESSAGES: AtomicU32 = AtomicU32::new(0);

/// Counts (and prints) every warning and error of the validation layer.
#[rustfmt::skip]
unsafe extern "system" fn on_message(_: vk::DebugUtilsMessageSeverityFlagsEXT, _: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>, _: *mut std::ffi::c_void) -> vk::Bool32 {
    MESSAGES.fetch_add(1, Relaxed);
    // SAFETY: the layer passes callback data valid for the call.
    eprintln!("{:?}", unsafe { (*data).message_as_c_str() });
    vk::FALSE
}

/// An image of the frame's size with memory and view. # Safety: `alloc` allocates from `device`; the caller frees all.
#[rustfmt::skip]
unsafe fn image(device: &ash::Device, alloc: &mut Allocator, format: vk::Format, usage: vk::ImageUsageFlags,
    aspect: vk::ImageAspectFlags) -> Result<(vk::Image, Allocation, vk::ImageView)> {
    let info = vk::ImageCreateInfo::default().image_type(vk::ImageType::TYPE_2D).format(format).extent(SIZE.into())
        .mip_levels(1).array_layers(1).samples(vk::SampleCountFlags::TYPE_1).usage(usage).tiling(vk::ImageTiling::OPTIMAL);
    // SAFETY: a valid create info; the memory is made for the image's requirements.
    unsafe {
        let image = device.create_image(&info, None)?;
        let requirements = device.get_image_memory_requirements(image);
        let memory = alloc.allocate(&AllocationCreateDesc { name: "image", requirements, location: MemoryLocation::GpuOnly, linear: false, allocation_scheme: AllocationScheme::GpuAllocatorManaged })?;
        device.bind_image_memory(image, memory.memory(), memory.offset())?;
        let range = vk::ImageSubresourceRange::default().aspect_mask(aspect).level_count(1).layer_count(1);
        let view = vk::ImageViewCreateInfo::default().image(image).format(format).view_type(vk::ImageViewType::TYPE_2D).subresource_range(range);
        Ok((image, memory, device.create_image_view(&view, None)?))
    }
}

#[rustfmt::skip]
fn main() -> Result<()> {
    // 1. An instance with the validation layer and a counting messenger.
    // SAFETY: loads the system's Vulkan loader.
    let entry = unsafe { ash::Entry::load() }?;
    let (layers, extensions) = ([c"VK_LAYER_KHRONOS_validation".as_ptr()], [ash::ext::debug_utils::NAME.as_ptr()]);
    let mut messenger = vk::DebugUtilsMessengerCreateInfoEXT::default().pfn_user_callback(Some(on_message))
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE);
    let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
    let info = vk::InstanceCreateInfo::default().application_info(&app).enabled_layer_names(&layers)
        .enabled_extension_names(&extensions).push_next(&mut messenger);
    // SAFETY: the create infos point at live locals; both objects are destroyed in step 5.
    let instance = unsafe { entry.create_instance(&info, None)? };
    let utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
    // SAFETY: as above.
    let messenger = unsafe { utils.create_debug_utils_messenger(&messenger, None)? };

    // 2. A device with a graphics+compute queue and the features the renderer's target needs.
    // SAFETY: queries of a live instance about a device it enumerated.
    let physical = *unsafe { instance.enumerate_physical_devices()? }.first().ok_or("no Vulkan device")?;
    // SAFETY: as above.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let family = families.iter().position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)).ok_or("no queue")? as u32;
    let target = Target::dynamic(COLOR, DEPTH);
    let (core, mut vulkan12, mut vulkan13) = target.required_features().to_vk();
    let mut features = vk::PhysicalDeviceFeatures2::default().features(core).push_next(&mut vulkan12).push_next(&mut vulkan13);
    let queues = [vk::DeviceQueueCreateInfo::default().queue_family_index(family).queue_priorities(&[1.0])];
    let info = vk::DeviceCreateInfo::default().queue_create_infos(&queues).push_next(&mut features);
    // SAFETY: the create info points at live locals.
    let device = unsafe { instance.create_device(physical, &info, None)? };
    // SAFETY: the device has one queue in `family`.
    let queue = unsafe { device.get_device_queue(family, 0) };
    let mut alloc = Allocator::new(&AllocatorCreateDesc { instance: instance.clone(), device: device.clone(),
        physical_device: physical, debug_settings: Default::default(), buffer_device_address: false, allocation_sizes: Default::default() })?;

    // 3. The attachments, a command buffer, the renderer, a scene and a camera that frames it.
    let host = HostDevice::new(&instance, physical, &device, family, target.required_features());
    // SAFETY: `alloc` allocates from `device`, which enables what `host` says; all goes in step 5.
    let (color, depth, pool, cmd, mut renderer) = unsafe {
        let color = image(&device, &mut alloc, COLOR, vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC, vk::ImageAspectFlags::COLOR)?;
        let depth = image(&device, &mut alloc, DEPTH, vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT, vk::ImageAspectFlags::DEPTH)?;
        let pool = device.create_command_pool(&vk::CommandPoolCreateInfo::default().queue_family_index(family), None)?;
        let cmd = device.allocate_command_buffers(&vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1))?[0];
        (color, depth, pool, cmd, EllipsoidRenderer::new(&host, &mut alloc, RendererOptions::new(target))?)
    };
    let glyph = |k: f64| Ellipsoid::new(DVec3::new(1.2 * k, 0.3 * k, 0.0), DVec3::new(0.5, 0.9, 0.3),
        DQuat::from_rotation_z(0.4 * k), Some([0.9, 0.5, 0.2]));
    let scene = Scene::new(vec![glyph(-1.0)?, glyph(0.0)?, glyph(1.0)?]);
    let (centre, radius) = scene.bounding_sphere().ok_or("empty scene")?;
    let camera = Camera::framing(centre, radius, SIZE.width, SIZE.height)?;

    // 4. One frame: upload and pre-pass outside the pass, the draw inside, then a copy to a host-visible buffer.
    let info = vk::BufferCreateInfo::default().size(4 * (SIZE.width * SIZE.height) as u64).usage(vk::BufferUsageFlags::TRANSFER_DST);
    // SAFETY: a valid create info; bound to memory made for it, freed in step 5.
    let (readback, pixels) = unsafe { let buffer = device.create_buffer(&info, None)?; let requirements = device.get_buffer_memory_requirements(buffer);
        let memory = alloc.allocate(&AllocationCreateDesc { name: "readback", requirements, location: MemoryLocation::GpuToCpu, linear: true, allocation_scheme: AllocationScheme::GpuAllocatorManaged })?;
        device.bind_buffer_memory(buffer, memory.memory(), memory.offset()).map(|_| (buffer, memory))? };
    let barrier = |image, aspect, new, access| vk::ImageMemoryBarrier::default().image(image).old_layout(Layout::UNDEFINED)
        .new_layout(new).dst_access_mask(access).subresource_range(vk::ImageSubresourceRange::default().aspect_mask(aspect).level_count(1).layer_count(1));
    let to_attachments = [barrier(color.0, vk::ImageAspectFlags::COLOR, Layout::COLOR_ATTACHMENT_OPTIMAL, vk::AccessFlags::COLOR_ATTACHMENT_WRITE),
        barrier(depth.0, vk::ImageAspectFlags::DEPTH, Layout::DEPTH_ATTACHMENT_OPTIMAL,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE)];
    let clear = |value| vk::RenderingAttachmentInfo::default().load_op(vk::AttachmentLoadOp::CLEAR).store_op(vk::AttachmentStoreOp::STORE).clear_value(value);
    let colors = [clear(vk::ClearValue::default()).image_view(color.2).image_layout(Layout::COLOR_ATTACHMENT_OPTIMAL)];
    let far = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: camera.depth.clear_value(), stencil: 0 } }; // reversed Z
    let depth_target = clear(far).image_view(depth.2).image_layout(Layout::DEPTH_ATTACHMENT_OPTIMAL);
    let rendering = vk::RenderingInfo::default().render_area(SIZE.into()).layer_count(1).color_attachments(&colors).depth_attachment(&depth_target);
    let to_copy = [barrier(color.0, vk::ImageAspectFlags::COLOR, Layout::TRANSFER_SRC_OPTIMAL, vk::AccessFlags::TRANSFER_READ).old_layout(Layout::COLOR_ATTACHMENT_OPTIMAL).src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)];
    let copy = vk::BufferImageCopy::default().image_extent(SIZE.into()).image_subresource(vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::COLOR).layer_count(1)); let to_host = [vk::MemoryBarrier::default().src_access_mask(vk::AccessFlags::TRANSFER_WRITE).dst_access_mask(vk::AccessFlags::HOST_READ)];
    let (stage, early, none) = (vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT, vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS, vk::DependencyFlags::empty());
    // SAFETY: the renderer draws inside the pass into attachments matching its target; the queue is waited for.
    unsafe {
        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
        renderer.begin_frame(&device, &mut alloc, 0)?;
        renderer.upload(&device, &mut alloc, cmd, &scene)?;
        renderer.record_prepass(&device, &mut alloc, cmd, &camera)?;
        device.cmd_pipeline_barrier(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, stage | early, none, &[], &[], &to_attachments);
        device.cmd_begin_rendering(cmd, &rendering);
        renderer.record(&device, &mut alloc, cmd, &camera)?;
        device.cmd_end_rendering(cmd);
        device.cmd_pipeline_barrier(cmd, stage, vk::PipelineStageFlags::TRANSFER, none, &[], &[], &to_copy);
        device.cmd_copy_image_to_buffer(cmd, color.0, Layout::TRANSFER_SRC_OPTIMAL, readback, &[copy]);
        device.cmd_pipeline_barrier(cmd, vk::PipelineStageFlags::TRANSFER, vk::PipelineStageFlags::HOST, none, &to_host, &[], &[]);
        device.end_command_buffer(cmd)?;
        device.queue_submit(queue, &[vk::SubmitInfo::default().command_buffers(&[cmd])], vk::Fence::null())?;
        device.queue_wait_idle(queue)?;
    }

    // 5. The pixels the ellipsoids cover (the background stays black), then teardown.
    let covered = pixels.mapped_slice().ok_or("not mapped")?[..4 * (SIZE.width * SIZE.height) as usize].chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
    println!("{} ellipsoids cover {covered} of {} pixels", scene.len(), SIZE.width * SIZE.height);
    // SAFETY: the queue is idle; each object goes once, after everything made from it.
    unsafe {
        renderer.destroy(&device, &mut alloc); device.destroy_command_pool(pool, None); device.destroy_buffer(readback, None); alloc.free(pixels)?;
        for (image, memory, view) in [color, depth] { device.destroy_image_view(view, None); device.destroy_image(image, None); alloc.free(memory)?; }
        drop(alloc); device.destroy_device(None); // The allocator's blocks go back before the device.
        utils.destroy_debug_utils_messenger(messenger, None); instance.destroy_instance(None);
    }
    match MESSAGES.load(Relaxed) { 0 => Ok(()), n => Err(format!("{n} validation message(s)").into()) }
}
