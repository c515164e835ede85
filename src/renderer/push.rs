//! The push constants of a frame, from the camera, the material and the scene's origin.

use glam::DVec3;

use crate::camera::Camera;
use crate::gpu_layout::PushConstants;
use crate::settings::Material;

/// The push constants for `camera`, relative to the scene `origin`, for the chunk whose first
/// instance is `first_instance`.
pub(crate) fn push_constants(
    camera: &Camera,
    material: &Material,
    origin: DVec3,
    radius_unit: f32,
    first_instance: u32,
) -> PushConstants {
    let b = camera.basis();
    let (sx, sy) = camera.ndc_scale();
    let (shift_x, shift_y) = camera.ndc_shift();
    // The eye in view axes, relative to the scene origin, in float64 then rounded once.
    let rel = camera.eye - origin;
    let eye = DVec3::new(rel.dot(b.right), rel.dot(b.up), rel.dot(b.forward)).as_vec3();
    let depth = camera.depth_map();
    PushConstants {
        eye_view: eye.to_array(),
        near_plane: camera.near as f32,
        right: b.right.as_vec3().to_array(),
        ndc_scale_x: sx as f32,
        up: b.up.as_vec3().to_array(),
        ndc_scale_y: sy as f32,
        forward: b.forward.as_vec3().to_array(),
        depth_a: depth.a as f32,
        ndc_per_pixel: [2.0 / camera.width as f32, 2.0 / camera.height as f32],
        ndc_shift: [shift_x as f32, shift_y as f32],
        depth_b: depth.b as f32,
        ambient: material.ambient,
        diffuse: material.diffuse,
        specular: material.specular,
        specular_color: material.specular_color,
        shininess: material.shininess,
        depth_c: depth.c as f32,
        first_instance,
        radius_unit,
        // Camera::validate keeps origin + size within 16384 on each axis.
        viewport_origin: camera.viewport_origin[0] | camera.viewport_origin[1] << 16,
    }
}
