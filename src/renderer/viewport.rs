//! The viewport and scissor of a camera's image: its size at its `viewport_origin`.

use ash::vk;

use crate::camera::Camera;

/// The viewport and scissor of `camera`'s image in the attachments: its size at its
/// `viewport_origin` (which `Camera::validate` keeps within 16384 pixels), depth range [0, 1].
pub(crate) fn viewport_and_scissor(camera: &Camera) -> (vk::Viewport, vk::Rect2D) {
    let [x, y] = camera.viewport_origin;
    let viewport = vk::Viewport {
        x: x as f32,
        y: y as f32,
        width: camera.width as f32,
        height: camera.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    let scissor = vk::Rect2D {
        offset: vk::Offset2D {
            x: x as i32,
            y: y as i32,
        },
        extent: vk::Extent2D {
            width: camera.width,
            height: camera.height,
        },
    };
    (viewport, scissor)
}
