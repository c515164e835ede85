//! 2D single-mip images with gpu-allocator memory and a view.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, Allocator};
use gpu_allocator::MemoryLocation;

use crate::buffer::allocate;
use crate::{fail, Host, HostResult};

/// An image, its view and its memory (the view and memory are missing after a failed
/// creation).
pub(crate) struct OwnedImage {
    pub(crate) image: vk::Image,
    pub(crate) view: vk::ImageView,
    allocation: Option<Allocation>,
}

impl OwnedImage {
    /// A 2D single-mip image with GpuOnly memory and a view of `aspect`.
    pub(crate) fn new(
        host: &mut Host,
        name: &str,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        samples: vk::SampleCountFlags,
        extent: vk::Extent2D,
        aspect: vk::ImageAspectFlags,
    ) -> HostResult<OwnedImage> {
        let (device, allocator) = host.device_and_allocator();
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
        // SAFETY: valid device and create info.
        let image = unsafe { device.create_image(&info, None) }.map_err(fail("vkCreateImage"))?;
        let mut owned = OwnedImage {
            image,
            view: vk::ImageView::null(),
            allocation: None,
        };
        match owned.bind_and_view(device, allocator, name, format, aspect) {
            Ok(()) => Ok(owned),
            Err(e) => {
                owned.destroy(device, allocator);
                Err(e)
            }
        }
    }

    fn bind_and_view(
        &mut self,
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &str,
        format: vk::Format,
        aspect: vk::ImageAspectFlags,
    ) -> HostResult<()> {
        // SAFETY: the image was created from `device`.
        let requirements = unsafe { device.get_image_memory_requirements(self.image) };
        let allocation = allocate(
            allocator,
            name,
            requirements,
            MemoryLocation::GpuOnly,
            false,
        )?;
        // SAFETY: the allocation satisfies the image's requirements and outlives the image
        // (both are released together in `destroy`, image first).
        let bound = unsafe {
            device.bind_image_memory(self.image, allocation.memory(), allocation.offset())
        };
        self.allocation = Some(allocation);
        bound.map_err(fail("vkBindImageMemory"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(self.image)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: the image is bound to memory; the view covers its only mip and layer.
        self.view = unsafe { device.create_image_view(&view_info, None) }
            .map_err(fail("vkCreateImageView"))?;
        Ok(())
    }

    /// Destroys the view and the image and frees the memory. The GPU must be done with them.
    pub(crate) fn destroy(self, device: &ash::Device, allocator: &mut Allocator) {
        // SAFETY: the caller guarantees the GPU no longer uses the image; view before image
        // (a null view is ignored), image before its memory.
        unsafe {
            device.destroy_image_view(self.view, None);
            device.destroy_image(self.image, None);
        }
        if let Some(allocation) = self.allocation {
            let _ = allocator.free(allocation);
        }
    }
}

/// The one mip level and array layer of an image.
pub(crate) fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

/// The one mip level and array layer of a colour image, for copies.
pub(crate) fn color_layers() -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    }
}
