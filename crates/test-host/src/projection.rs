//! The host's projection matrices, in Vulkan clip space: y down, z in [0, 1], the camera
//! looking down -Z.

use glam::{DMat4, DVec4};

/// Reversed-Z perspective with an infinite far plane: a point at view depth `d = -z` gets clip
/// w = d and NDC z = near / d (1 at the near plane, 0 at infinity); NDC y points down.
pub fn reversed_infinite_perspective(fov_y_rad: f64, aspect: f64, near: f64) -> DMat4 {
    let f = 1.0 / (0.5 * fov_y_rad).tan();
    DMat4::from_cols(
        DVec4::new(f / aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, -f, 0.0, 0.0),
        DVec4::new(0.0, 0.0, 0.0, -1.0),
        DVec4::new(0.0, 0.0, near, 0.0),
    )
}

/// Standard perspective: NDC z = 0 at `near`, 1 at `far`; NDC y points down.
pub fn standard_finite_perspective(fov_y_rad: f64, aspect: f64, near: f64, far: f64) -> DMat4 {
    let f = 1.0 / (0.5 * fov_y_rad).tan();
    let range = near - far;
    DMat4::from_cols(
        DVec4::new(f / aspect, 0.0, 0.0, 0.0),
        DVec4::new(0.0, -f, 0.0, 0.0),
        DVec4::new(0.0, 0.0, far / range, -1.0),
        DVec4::new(0.0, 0.0, near * far / range, 0.0),
    )
}
