//! The smallest complete host: its own Vulkan instance and device, a colour and a depth image,
//! and one frame of ellipsoids drawn with dynamic rendering, copied back and counted. It uses
//! only `ash`, `gpu-allocator`, `glam` and what the library offers with its default features
//! off; `examples/embed` is the full host. Exits non-zero on any validation message (and, being
//! minimal, leaves cleaning up after an error to the operating system).
//!
//! ```sh
//! cargo run --release --example minimal   # prints the covered pixels, writes minimal.ppm
//! ```

use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

use ash::vk::{self, AccessFlags as Access, ImageLayout as Layout, PipelineStageFlags as Stage};
use ellipsoid_splat::features::required_device_features;
use ellipsoid_splat::{
    Camera, Ellipsoid, EllipsoidRenderer, HostDevice, RendererOptions, Scene, Target,
};
use glam::{DQuat, DVec3};
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;
const EXTENT: vk::Extent2D = vk::Extent2D {
    width: 320,
    height: 240,
};
const COLOR: vk::Format = vk::Format::R8G8B8A8_UNORM;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT;

/// Warnings and errors reported by the validation layer.
static MESSAGES: AtomicU32 = AtomicU32::new(0);

unsafe extern "system" fn on_message(
    _: vk::DebugUtilsMessageSeverityFlagsEXT,
    _: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _: *mut std::ffi::c_void,
) -> vk::Bool32 {
    MESSAGES.fetch_add(1, Relaxed);
    // SAFETY: the layer passes null or callback data valid for the call, with a C string.
    if let Some(text) = unsafe { data.as_ref().and_then(|d| d.message_as_c_str()) } {
        eprintln!("validation: {}", text.to_string_lossy());
    }
    vk::FALSE
}

/// Memory for an image or buffer with `requirements`, at `location`.
fn allocate(
    allocator: &mut Allocator,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
) -> Result<Allocation> {
    Ok(allocator.allocate(&AllocationCreateDesc {
        name: "minimal",
        requirements,
        location,
        linear: false,
        allocation_scheme: AllocationScheme::GpuAllocatorManaged,
    })?)
}

/// An attachment image of the frame's size, its memory, a view and its aspect.
struct Attachment(vk::Image, Allocation, vk::ImageView, vk::ImageAspectFlags);

impl Attachment {
    fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        let aspect = match format {
            DEPTH => vk::ImageAspectFlags::DEPTH,
            _ => vk::ImageAspectFlags::COLOR,
        };
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(EXTENT.into())
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        // SAFETY: valid create info; `main` destroys the image.
        let image = unsafe { device.create_image(&info, None) }?;
        // SAFETY: the image comes from `device`.
        let requirements = unsafe { device.get_image_memory_requirements(image) };
        let memory = allocate(allocator, requirements, MemoryLocation::GpuOnly)?;
        // SAFETY: the memory fits the image and is freed after it.
        unsafe { device.bind_image_memory(image, memory.memory(), memory.offset()) }?;
        let view = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(Self::range(aspect));
        // SAFETY: the image is bound to memory; the view covers its one mip and layer.
        let view = unsafe { device.create_image_view(&view, None) }?;
        Ok(Self(image, memory, view, aspect))
    }

    fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
        let range = vk::ImageSubresourceRange::default().aspect_mask(aspect);
        range.level_count(1).layer_count(1)
    }

    /// A layout transition, after the old layout's accesses and before the new one's.
    fn transition(&self, old: Layout, new: Layout) -> vk::ImageMemoryBarrier<'static> {
        let access = |layout| match layout {
            Layout::COLOR_ATTACHMENT_OPTIMAL => Access::COLOR_ATTACHMENT_WRITE,
            Layout::DEPTH_ATTACHMENT_OPTIMAL => {
                Access::DEPTH_STENCIL_ATTACHMENT_READ | Access::DEPTH_STENCIL_ATTACHMENT_WRITE
            }
            Layout::TRANSFER_SRC_OPTIMAL => Access::TRANSFER_READ,
            _ => Access::NONE,
        };
        vk::ImageMemoryBarrier::default()
            .image(self.0)
            .subresource_range(Self::range(self.3))
            .old_layout(old)
            .new_layout(new)
            .src_access_mask(access(old))
            .dst_access_mask(access(new))
    }
}

fn main() -> Result<()> {
    // 1. An instance, with the validation layer and a counting messenger when installed.
    // SAFETY: loads the system Vulkan loader; nothing else initialises it.
    let entry = unsafe { ash::Entry::load() }?;
    let layer = c"VK_LAYER_KHRONOS_validation";
    // SAFETY: a global query.
    let installed = unsafe { entry.enumerate_instance_layer_properties() }?;
    let validate = installed
        .iter()
        .any(|l| l.layer_name_as_c_str() == Ok(layer));
    let (layers, extensions) = match validate {
        true => (
            vec![layer.as_ptr()],
            vec![ash::ext::debug_utils::NAME.as_ptr()],
        ),
        false => (vec![], vec![]),
    };
    let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message));
    let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    if validate {
        // Chained, it also reports on vkCreateInstance and vkDestroyInstance.
        info = info.push_next(&mut messenger_info);
    } else {
        eprintln!("note: no validation layer installed; running without validation");
    }
    // SAFETY: every pointer in `info` refers to locals alive during the call.
    let instance = unsafe { entry.create_instance(&info, None) }?;
    let utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
    // SAFETY: the instance enables VK_EXT_debug_utils; the callback takes no user data.
    let messenger = validate
        .then(|| unsafe { utils.create_debug_utils_messenger(&messenger_info, None) })
        .transpose()?;

    // 2. A Vulkan 1.3 device with a graphics+compute queue and the renderer's features.
    let suitable = |physical| {
        // SAFETY: `physical` was enumerated from `instance`.
        let (properties, families) = unsafe {
            let families = instance.get_physical_device_queue_family_properties(physical);
            (instance.get_physical_device_properties(physical), families)
        };
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let family = families.iter().position(|f| f.queue_flags.contains(wanted));
        let family = family.filter(|_| properties.api_version >= vk::API_VERSION_1_3);
        family.map(|family| (physical, family as u32))
    };
    // SAFETY: a query of a valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }?;
    let found = devices.into_iter().find_map(suitable);
    let (physical_device, family) = found.ok_or("no Vulkan 1.3 device with graphics+compute")?;
    let (core, mut vulkan13) = required_device_features();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .features(core)
        .push_next(&mut vulkan13);
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&[1.0])];
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .push_next(&mut features);
    // SAFETY: every pointer in `info` refers to locals alive during the call.
    let device = unsafe { instance.create_device(physical_device, &info, None) }?;
    // SAFETY: the device has one queue in `family`.
    let queue = unsafe { device.get_device_queue(family, 0) };
    let mut allocator = Allocator::new(&gpu_allocator::vulkan::AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device,
        debug_settings: Default::default(),
        buffer_device_address: false,
        allocation_sizes: Default::default(),
    })?;

    // 3. Colour and depth images, a buffer to copy the colour into, a command buffer.
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    let color = Attachment::new(&device, &mut allocator, COLOR, usage)?;
    let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
    let depth = Attachment::new(&device, &mut allocator, DEPTH, usage)?;
    let info = vk::BufferCreateInfo::default()
        .size(u64::from(EXTENT.width * EXTENT.height * 4))
        .usage(vk::BufferUsageFlags::TRANSFER_DST);
    // SAFETY: valid create info; the buffer is destroyed before its memory is freed.
    let buffer = unsafe { device.create_buffer(&info, None) }?;
    // SAFETY: the buffer comes from `device`.
    let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
    let memory = allocate(&mut allocator, requirements, MemoryLocation::GpuToCpu)?;
    // SAFETY: the memory fits the buffer.
    unsafe { device.bind_buffer_memory(buffer, memory.memory(), memory.offset()) }?;
    let info = vk::CommandPoolCreateInfo::default().queue_family_index(family);
    // SAFETY: valid create info; destroying the pool frees its command buffer.
    let pool = unsafe { device.create_command_pool(&info, None) }?;
    let info = vk::CommandBufferAllocateInfo::default()
        .command_pool(pool)
        .command_buffer_count(1);
    // SAFETY: the pool comes from `device`.
    let cmd = unsafe { device.allocate_command_buffers(&info) }?[0];

    // 4. The renderer, drawing into dynamic rendering with one colour and a depth attachment,
    // and a few ellipsoids seen by a camera that frames them.
    let host = HostDevice {
        instance: &instance,
        physical_device,
        device: &device,
        queue_family_index: family,
    };
    let options = RendererOptions::new(Target::dynamic(COLOR, DEPTH));
    // SAFETY: the handles belong together; the device enables the required features.
    let mut renderer = unsafe { EllipsoidRenderer::new(&host, &mut allocator, options) }?;
    let ellipsoid = |k: f64| {
        let (center, radii) = (DVec3::new(1.2 * k, 0.3 * k, 0.0), DVec3::new(0.5, 0.9, 0.3));
        let color = [0.9, 0.5 - 0.2 * k as f32, 0.2];
        Ellipsoid::new(center, radii, DQuat::from_rotation_z(0.4 * k), Some(color))
    };
    let scene = Scene::new(vec![ellipsoid(-1.0)?, ellipsoid(0.0)?, ellipsoid(1.0)?]);
    let (center, radius) = scene.bounding_sphere().ok_or("empty scene")?;
    let camera = Camera::framing(center, radius, EXTENT.width, EXTENT.height)?;

    // 5. One frame: upload and culling outside the pass, the draw inside it, then the copy.
    let attachment = |image: &Attachment, layout, clear_value| {
        vk::RenderingAttachmentInfo::default()
            .image_view(image.2)
            .image_layout(layout)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(clear_value)
    };
    let black = vk::ClearValue {
        color: vk::ClearColorValue {
            float32: [0.0, 0.0, 0.0, 1.0],
        },
    };
    // The camera's depth convention (reversed Z here) says what "far" is.
    let far = vk::ClearValue {
        depth_stencil: vk::ClearDepthStencilValue {
            depth: camera.depth.clear_value(),
            stencil: 0,
        },
    };
    let colors = [attachment(&color, Layout::COLOR_ATTACHMENT_OPTIMAL, black)];
    let depth_attachment = attachment(&depth, Layout::DEPTH_ATTACHMENT_OPTIMAL, far);
    let rendering = vk::RenderingInfo::default()
        .render_area(EXTENT.into())
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth_attachment);
    let to_attachments = [
        color.transition(Layout::UNDEFINED, Layout::COLOR_ATTACHMENT_OPTIMAL),
        depth.transition(Layout::UNDEFINED, Layout::DEPTH_ATTACHMENT_OPTIMAL),
    ];
    let to_copy = [color.transition(
        Layout::COLOR_ATTACHMENT_OPTIMAL,
        Layout::TRANSFER_SRC_OPTIMAL,
    )];
    let to_host = [vk::BufferMemoryBarrier::default()
        .buffer(buffer)
        .size(vk::WHOLE_SIZE)
        .src_access_mask(Access::TRANSFER_WRITE)
        .dst_access_mask(Access::HOST_READ)];
    let copy = [vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            layer_count: 1,
            ..Default::default()
        })
        .image_extent(EXTENT.into())];
    let attachment_stages = Stage::COLOR_ATTACHMENT_OUTPUT | Stage::EARLY_FRAGMENT_TESTS;
    let cmds = [cmd];
    let submits = [vk::SubmitInfo::default().command_buffers(&cmds)];
    let barrier = |src, dst, buffers: &[_], images: &[_]| {
        let none = vk::DependencyFlags::empty();
        // SAFETY: `cmd` is recording, outside a pass.
        unsafe { device.cmd_pipeline_barrier(cmd, src, dst, none, &[], buffers, images) }
    };
    // SAFETY: `cmd` records outside a pass except between begin and end rendering, where the
    // renderer draws into attachments matching its target; the queue is waited for below.
    unsafe {
        device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
        renderer.begin_frame(&device, &mut allocator, 0)?;
        renderer.upload(&device, &mut allocator, cmd, &scene)?;
        renderer.record_prepass(&device, &mut allocator, cmd, &camera)?;
        barrier(Stage::TOP_OF_PIPE, attachment_stages, &[], &to_attachments);
        device.cmd_begin_rendering(cmd, &rendering);
        renderer.record(&device, &mut allocator, cmd, &camera)?;
        device.cmd_end_rendering(cmd);
        barrier(
            Stage::COLOR_ATTACHMENT_OUTPUT,
            Stage::TRANSFER,
            &[],
            &to_copy,
        );
        device.cmd_copy_image_to_buffer(cmd, color.0, Layout::TRANSFER_SRC_OPTIMAL, buffer, &copy);
        barrier(Stage::TRANSFER, Stage::HOST, &to_host, &[]);
        device.end_command_buffer(cmd)?;
        device.queue_submit(queue, &submits, vk::Fence::null())?;
        device.queue_wait_idle(queue)?;
    }

    // 6. How many pixels the ellipsoids cover (the rest stays black), and a binary PPM.
    let rgba = memory
        .mapped_slice()
        .ok_or("the readback buffer is not mapped")?;
    let covered = rgba.chunks(4).filter(|p| p[..3] != [0, 0, 0]).count();
    let (width, height) = (EXTENT.width, EXTENT.height);
    let count = scene.len();
    println!(
        "{count} ellipsoids cover {covered} of {} pixels",
        width * height
    );
    let mut ppm = format!("P6\n{width} {height}\n255\n").into_bytes();
    ppm.extend(rgba.chunks(4).flat_map(|p| &p[..3]));
    std::fs::write("minimal.ppm", ppm)?;

    // 7. Everything destroyed, each object once and after what was made from it.
    // SAFETY: the queue is idle, so the GPU uses none of these any more.
    unsafe {
        renderer.destroy(&device, &mut allocator);
        device.destroy_command_pool(pool, None);
        device.destroy_buffer(buffer, None);
        allocator.free(memory)?;
        for Attachment(image, memory, view, _) in [color, depth] {
            device.destroy_image_view(view, None);
            device.destroy_image(image, None);
            allocator.free(memory)?;
        }
        drop(allocator);
        device.destroy_device(None);
        if let Some(messenger) = messenger {
            utils.destroy_debug_utils_messenger(messenger, None);
        }
        instance.destroy_instance(None);
    }
    let count = MESSAGES.load(Relaxed);
    println!("wrote minimal.ppm; {count} validation message(s)");
    match count {
        0 => Ok(()),
        _ => Err(format!("the validation layer reported {count} message(s)").into()),
    }
}
