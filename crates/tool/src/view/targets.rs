//! The images the renderer draws into (its outputs): colour in the swapchain's format, depth,
//! normal and instance ID, at the window's size, plus the host-visible buffer pixels are
//! read back through. Colour is copied to the swapchain image each frame; ID and depth stay
//! for picking and for zooming towards the point under the cursor.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use ellipsoid_splat::Error as VulkanError;
use ellipsoid_splat::Target;

use super::VkCall;

/// The depth format (occlusion culling needs `D32_SFLOAT`).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// An image with its memory and a view of its one level and layer.
pub struct OwnedImage {
    /// The image.
    pub image: vk::Image,
    /// Its view.
    pub view: vk::ImageView,
    memory: Option<Allocation>,
}

impl OwnedImage {
    /// A 2D single-sample image of `format` and `extent`.
    fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &str,
        (format, extent): (vk::Format, vk::Extent2D),
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(extent.into())
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage);
        // SAFETY: valid create info; the image is destroyed on every path below or by
        // `destroy`.
        let image = unsafe { device.create_image(&info, None) }.call("vkCreateImage")?;
        let mut this = Self {
            image,
            view: vk::ImageView::null(),
            memory: None,
        };
        // SAFETY: the image is live and unused.
        let requirements = unsafe { device.get_image_memory_requirements(image) };
        let desc = AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        };
        let made = allocator
            .allocate(&desc)
            .map_err(|e| {
                Error::from(VulkanError::Allocation {
                    what: "viewer image".into(),
                    reason: e.to_string(),
                })
            })
            .and_then(|memory| {
                // SAFETY: memory allocated for this image's requirements.
                let bound =
                    unsafe { device.bind_image_memory(image, memory.memory(), memory.offset()) };
                this.memory = Some(memory);
                bound.call("vkBindImageMemory")?;
                let range = vk::ImageSubresourceRange::default()
                    .aspect_mask(aspect)
                    .level_count(1)
                    .layer_count(1);
                let view = vk::ImageViewCreateInfo::default()
                    .image(image)
                    .view_type(vk::ImageViewType::TYPE_2D)
                    .format(format)
                    .subresource_range(range);
                // SAFETY: a view of a bound image's one level and layer.
                this.view =
                    unsafe { device.create_image_view(&view, None) }.call("vkCreateImageView")?;
                Ok(())
            });
        match made {
            Ok(()) => Ok(this),
            Err(e) => {
                // SAFETY: never used.
                unsafe { this.destroy(device, allocator) };
                Err(e)
            }
        }
    }

    /// Destroys the view and image and frees the memory.
    ///
    /// # Safety
    /// No pending work uses the image.
    unsafe fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: caller contract; null views are ignored by Vulkan.
        unsafe {
            device.destroy_image_view(self.view, None);
            device.destroy_image(self.image, None);
        }
        if let Some(memory) = self.memory {
            // A failed free leaks device memory until the allocator goes; nothing to do.
            let _ = allocator.free(memory);
        }
    }
}

/// A host-visible buffer the GPU copies pixels into.
pub struct ReadbackBuffer {
    /// The buffer.
    pub buffer: vk::Buffer,
    /// Its size in bytes.
    pub size: u64,
    memory: Option<Allocation>,
}

impl ReadbackBuffer {
    /// A host-visible transfer destination of `size` bytes.
    pub fn new(device: &ash::Device, allocator: &mut Allocator, size: u64) -> Result<Self> {
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(vk::BufferUsageFlags::TRANSFER_DST)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info.
        let buffer = unsafe { device.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        let mut this = Self {
            buffer,
            size,
            memory: None,
        };
        // SAFETY: live buffer.
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let desc = AllocationCreateDesc {
            name: "viewer readback",
            requirements,
            location: MemoryLocation::GpuToCpu,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        };
        let made = allocator
            .allocate(&desc)
            .map_err(|e| {
                Error::from(VulkanError::Allocation {
                    what: "viewer readback".into(),
                    reason: e.to_string(),
                })
            })
            .and_then(|memory| {
                // SAFETY: memory allocated for this buffer's requirements.
                let bound =
                    unsafe { device.bind_buffer_memory(buffer, memory.memory(), memory.offset()) };
                this.memory = Some(memory);
                bound.call("vkBindBufferMemory")
            });
        match made {
            Ok(()) => Ok(this),
            Err(e) => {
                // SAFETY: never used.
                unsafe { this.destroy(device, allocator) };
                Err(e)
            }
        }
    }

    /// The bytes the GPU wrote (read after waiting for the copy's fence).
    pub fn bytes(&self) -> Result<&[u8]> {
        self.memory
            .as_ref()
            .and_then(|m| m.mapped_slice())
            .map(|bytes| &bytes[..self.size as usize])
            .ok_or_else(|| Error::invalid("viewer readback", "memory is not host-visible"))
    }

    /// Destroys the buffer and frees its memory.
    ///
    /// # Safety
    /// No pending work uses the buffer.
    pub unsafe fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: caller contract.
        unsafe { device.destroy_buffer(self.buffer, None) };
        if let Some(memory) = self.memory {
            let _ = allocator.free(memory);
        }
    }
}

/// The renderer's outputs at one size. Between frames all four are in
/// `TRANSFER_SRC_OPTIMAL`: colour was copied to the swapchain, ID and depth can be probed.
pub struct Targets {
    /// Colour, in the swapchain's format.
    pub color: OwnedImage,
    /// World normals (the renderer writes them with the ID; the viewer does not read them).
    pub normal: OwnedImage,
    /// Instance index per pixel.
    pub id: OwnedImage,
    /// Depth.
    pub depth: OwnedImage,
    /// Their size.
    pub extent: vk::Extent2D,
}

impl Targets {
    /// The four images at `extent`, colour in `color_format`.
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        color_format: vk::Format,
        extent: vk::Extent2D,
    ) -> Result<Self> {
        let color_usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let depth_usage =
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let color_aspect = vk::ImageAspectFlags::COLOR;
        let specs = [
            ("viewer colour", color_format, color_usage, color_aspect),
            (
                "viewer normal",
                Target::NORMAL_FORMAT,
                color_usage,
                color_aspect,
            ),
            ("viewer id", Target::ID_FORMAT, color_usage, color_aspect),
            (
                "viewer depth",
                DEPTH_FORMAT,
                depth_usage,
                vk::ImageAspectFlags::DEPTH,
            ),
        ];
        let mut made = Vec::new();
        for (name, format, usage, aspect) in specs {
            match OwnedImage::new(device, allocator, name, (format, extent), usage, aspect) {
                Ok(image) => made.push(image),
                Err(e) => {
                    for image in made {
                        // SAFETY: just made, never used.
                        unsafe { image.destroy(device, allocator) };
                    }
                    return Err(e);
                }
            }
        }
        let mut images = made.into_iter();
        let mut next = || images.next().expect("four images were made");
        Ok(Self {
            color: next(),
            normal: next(),
            id: next(),
            depth: next(),
            extent,
        })
    }

    /// Destroys the four images.
    ///
    /// # Safety
    /// No pending work uses them.
    pub unsafe fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: caller contract.
        unsafe {
            for image in [self.color, self.normal, self.id, self.depth] {
                image.destroy(device, allocator);
            }
        }
    }
}
