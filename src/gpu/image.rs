//! A 2D image with one view and its memory, owned together and freed together.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};

/// A device-local 2D image with a full view. Free it with [`GpuImage::destroy`].
pub struct GpuImage {
    image: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    extent: vk::Extent2D,
    name: &'static str,
}

impl GpuImage {
    /// Creates an image of `samples` samples per pixel in `format`, with one mip level and
    /// layer, and a view of it.
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &'static str,
        (format, samples): (vk::Format, vk::SampleCountFlags),
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Self> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info; destroyed by `destroy` or on the error paths below.
        let image = unsafe { device.create_image(&info, None) }
            .map_err(|result| Error::creating(name, "vkCreateImage", result))?;
        // SAFETY: `image` was just created from `device`.
        let requirements = unsafe { device.get_image_memory_requirements(image) };
        let allocation = match allocator.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: unused, unbound image.
                unsafe { device.destroy_image(image, None) };
                return Err(crate::allocator::gpu_allocation_error(name, e));
            }
        };
        let cleanup = |device: &ash::Device, allocator: &mut Allocator, allocation| {
            // SAFETY: nothing uses the image yet.
            unsafe { device.destroy_image(image, None) };
            if let Err(e) = allocator.free(allocation) {
                log::error!("freeing {name}: {e}");
            }
        };
        // SAFETY: memory and offset come from an allocation made for these requirements.
        let bound =
            unsafe { device.bind_image_memory(image, allocation.memory(), allocation.offset()) };
        if let Err(result) = bound {
            cleanup(device, allocator, allocation);
            return Err(Error::creating(name, "vkBindImageMemory", result));
        }
        let view_info = vk::ImageViewCreateInfo::default()
            .image(image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(full_range(aspect));
        // SAFETY: `image` is bound to memory and has this format.
        let view = match unsafe { device.create_image_view(&view_info, None) } {
            Ok(v) => v,
            Err(result) => {
                cleanup(device, allocator, allocation);
                return Err(Error::creating(name, "vkCreateImageView", result));
            }
        };
        Ok(Self {
            image,
            view,
            allocation: Some(allocation),
            extent,
            name,
        })
    }

    /// The image handle.
    pub fn handle(&self) -> vk::Image {
        self.image
    }

    /// The view of the whole image.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// Size in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// Destroys view and image and frees the memory (a failure to free is logged).
    ///
    /// # Safety
    /// `device` and `allocator` made the image, and no pending GPU work uses it.
    pub unsafe fn destroy(mut self, device: &ash::Device, allocator: &mut Allocator) {
        if let Some(allocation) = self.allocation.take() {
            // SAFETY: caller contract; the image and view are owned here.
            unsafe {
                device.destroy_image_view(self.view, None);
                device.destroy_image(self.image, None);
            }
            if let Err(e) = allocator.free(allocation) {
                log::error!("freeing {}: {e}", self.name);
            }
        }
    }
}

impl Drop for GpuImage {
    fn drop(&mut self) {
        if self.allocation.is_some() {
            log::error!("image '{}' dropped without destroy(): leaked", self.name);
        }
    }
}

/// The whole subresource range of a single-level, single-layer image.
pub fn full_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}
