//! The window's swapchain: its format, present mode and size, made again on resize or when
//! the window system says it is out of date.

use ash::vk;

use crate::error::Result;

use super::device::Gpu;
use super::VkCall;

/// The swapchain, its images and one "copy done" semaphore per image (waited by the present
/// of that image; per image rather than per frame, since an image's semaphore may only be
/// signalled again after its present was queued).
pub struct Swapchain {
    /// The swapchain.
    pub handle: vk::SwapchainKHR,
    /// Its images (owned by the swapchain).
    pub images: Vec<vk::Image>,
    /// Pixels of every image.
    pub extent: vk::Extent2D,
    /// What the images hold.
    pub format: vk::SurfaceFormatKHR,
    /// How images reach the screen.
    pub present_mode: vk::PresentModeKHR,
    /// The images can be copied from (for screenshots of exactly what is shown).
    pub readable: bool,
    /// Signalled when the frame's copy into image `k` is done.
    pub copied: Vec<vk::Semaphore>,
}

/// The surface format the viewer draws in: 8-bit sRGB (BGRA or RGBA), as `render`'s PNGs are;
/// otherwise the first one offered, with a warning that colours will differ.
pub fn choose_format(gpu: &Gpu) -> Result<vk::SurfaceFormatKHR> {
    // SAFETY: the surface and physical device belong to the `Gpu`'s instance.
    let formats = unsafe {
        gpu.surface_loader
            .get_physical_device_surface_formats(gpu.physical_device, gpu.surface)
    }
    .call("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
    let srgb = formats.iter().find(|f| {
        matches!(
            f.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
        ) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
    });
    // Else an 8-bit UNORM one (colours then differ from `render`'s): screenshots read 4
    // bytes a pixel in RGBA or BGRA order, so no other format will do.
    let unorm = formats.iter().find(|f| {
        matches!(
            f.format,
            vk::Format::B8G8R8A8_UNORM | vk::Format::R8G8B8A8_UNORM
        )
    });
    match (srgb, unorm) {
        (Some(f), _) => Ok(*f),
        (None, Some(f)) => {
            eprintln!(
                "warning: the window offers no 8-bit sRGB format; drawing in {:?}, so colours \
                 differ from `render`'s",
                f.format
            );
            Ok(*f)
        }
        (None, None) => Err(ellipsoid_splat::Error::NoDevice(format!(
            "the window's surface offers no 8-bit RGBA or BGRA format (it offers {:?})",
            formats.iter().map(|f| f.format).collect::<Vec<_>>()
        ))
        .into()),
    }
}

impl Swapchain {
    /// A swapchain of `format` for the surface's current size (`window` when the surface
    /// leaves it to the swapchain), replacing `old` if given (which the caller destroys
    /// after this returns). `None` when the size is zero: a minimised window, nothing to
    /// draw into. `vsync` asks for FIFO; without it, mailbox or immediate where offered.
    pub fn new(
        gpu: &Gpu,
        format: vk::SurfaceFormatKHR,
        window: vk::Extent2D,
        vsync: bool,
        old: vk::SwapchainKHR,
    ) -> Result<Option<Self>> {
        let (physical, surface) = (gpu.physical_device, gpu.surface);
        // SAFETY: queries of a live surface.
        let (caps, modes) = unsafe {
            (
                gpu.surface_loader
                    .get_physical_device_surface_capabilities(physical, surface)
                    .call("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                gpu.surface_loader
                    .get_physical_device_surface_present_modes(physical, surface)
                    .call("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: window
                    .width
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: window
                    .height
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let present_mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let readable = caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_SRC);
        let mut usage = vk::ImageUsageFlags::TRANSFER_DST;
        if readable {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old);
        // SAFETY: valid create info for the `Gpu`'s surface and device; `old` (if any) is
        // retired by this call and destroyed by the caller.
        let handle = unsafe { gpu.swapchain_loader.create_swapchain(&info, None) }
            .call("vkCreateSwapchainKHR")?;
        let mut this = Self {
            handle,
            images: Vec::new(),
            extent,
            format,
            present_mode,
            readable,
            copied: Vec::new(),
        };
        // SAFETY: the swapchain was just made from this device.
        match unsafe { this.fill(gpu) } {
            Ok(()) => Ok(Some(this)),
            Err(e) => {
                // SAFETY: nothing used the swapchain or its semaphores yet.
                unsafe { this.destroy(gpu) };
                Err(e)
            }
        }
    }

    /// Gets the images and makes their semaphores.
    ///
    /// # Safety
    /// `self.handle` is a live swapchain of `gpu`'s device.
    unsafe fn fill(&mut self, gpu: &Gpu) -> Result<()> {
        // SAFETY: caller contract.
        self.images = unsafe { gpu.swapchain_loader.get_swapchain_images(self.handle) }
            .call("vkGetSwapchainImagesKHR")?;
        for _ in 0..self.images.len() {
            let info = vk::SemaphoreCreateInfo::default();
            // SAFETY: valid create info; destroyed with the swapchain.
            let semaphore =
                unsafe { gpu.device.create_semaphore(&info, None) }.call("vkCreateSemaphore")?;
            self.copied.push(semaphore);
        }
        Ok(())
    }

    /// Destroys the semaphores and the swapchain (its images go with it).
    ///
    /// # Safety
    /// The device is idle as far as this swapchain is concerned: no submitted work waits
    /// on or signals its semaphores, and no present of its images is pending.
    pub unsafe fn destroy(self, gpu: &Gpu) {
        // SAFETY: caller contract; each object goes once.
        unsafe {
            for semaphore in self.copied {
                gpu.device.destroy_semaphore(semaphore, None);
            }
            gpu.swapchain_loader.destroy_swapchain(self.handle, None);
        }
    }
}
