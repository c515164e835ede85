//! What the viewer reads back: a screenshot of the swapchain image as shown, and the ID and
//! depth under the cursor (a pick, and the point a wheel notch zooms towards).

use std::path::Path;

use ash::vk;

use crate::error::Result;

use super::{to_host, Drawn, Probe, Viewer, NO_INSTANCE};
use crate::view::targets::ReadbackBuffer;
use crate::view::VkCall;

impl Viewer {
    /// Waits for frame `slot` and writes the screenshot buffer as an RGBA PNG.
    pub(super) fn write_screenshot(
        &mut self,
        shot: &ReadbackBuffer,
        slot: usize,
        extent: vk::Extent2D,
        path: &Path,
    ) -> Result<()> {
        let fence = self.frames.as_ref().expect("frames exist").slots[slot].fence;
        // SAFETY: the fence belongs to the device.
        unsafe {
            self.gpu
                .device
                .wait_for_fences(&[fence], true, u64::MAX)
                .call("vkWaitForFences")?;
        }
        let bytes = shot.bytes()?;
        let bgra = matches!(
            self.format.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        );
        let rgba: Vec<u8> = bytes
            .chunks_exact(4)
            .flat_map(|p| {
                if bgra {
                    [p[2], p[1], p[0], p[3]]
                } else {
                    [p[0], p[1], p[2], p[3]]
                }
            })
            .collect();
        crate::output::write_rgba8_png(path, &rgba, extent.width, extent.height)
    }

    /// Reads the ID and depth outputs of the last frame drawn at pixel `(x, y)`: submits a
    /// copy of two texels and waits for it (the frames in flight finish first, in queue
    /// order). `None` before the first frame at this size or outside the image.
    pub fn probe(&mut self, x: f64, y: f64) -> Result<Option<Probe>> {
        let (Some((camera, sampled)), Some(targets)) = (self.last, self.targets.as_ref()) else {
            return Ok(None);
        };
        let extent = targets.extent;
        if !(x >= 0.0 && y >= 0.0 && x < f64::from(extent.width) && y < f64::from(extent.height)) {
            return Ok(None);
        }
        let (id_image, depth_image) = (targets.id.image, targets.depth.image);
        let buffer = self.probe_buffer.as_ref().expect("made in create").buffer;
        let offset = vk::Offset3D {
            x: x as i32,
            y: y as i32,
            z: 0,
        };
        self.submit_and_wait(|device, _, cmd| {
            let texel = |aspect, at| {
                vk::BufferImageCopy::default()
                    .buffer_offset(at)
                    .image_subresource(
                        vk::ImageSubresourceLayers::default()
                            .aspect_mask(aspect)
                            .layer_count(1),
                    )
                    .image_offset(offset)
                    .image_extent(vk::Extent3D {
                        width: 1,
                        height: 1,
                        depth: 1,
                    })
            };
            // SAFETY: both images are in TRANSFER_SRC_OPTIMAL since the last frame, whose
            // closing barrier made its writes visible to transfers after it.
            unsafe {
                let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                let id_copy = [texel(vk::ImageAspectFlags::COLOR, 0)];
                let depth_copy = [texel(vk::ImageAspectFlags::DEPTH, 4)];
                device.cmd_copy_image_to_buffer(cmd, id_image, layout, buffer, &id_copy);
                device.cmd_copy_image_to_buffer(cmd, depth_image, layout, buffer, &depth_copy);
                to_host(device, cmd);
            }
            Ok(())
        })?;
        let bytes = self.probe_buffer.as_ref().expect("made").bytes()?;
        let id = u32::from_ne_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
        let z = f32::from_ne_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]);
        let glyph = (id != NO_INSTANCE).then(|| match (&self.moving, sampled) {
            (
                Some(Drawn {
                    sample: Some(s), ..
                }),
                true,
            ) => s.indices[id as usize],
            _ => id,
        });
        let depth =
            (z != camera.depth.clear_value()).then(|| camera.depth_map().view_depth(f64::from(z)));
        Ok(Some(Probe { glyph, depth }))
    }
}
