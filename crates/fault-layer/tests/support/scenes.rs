//! The scenes and cameras of the typical run: a cloud of glyphs, a part of it changed, and a
//! larger cloud uploaded later, seen by cameras of a few sizes.

use ellipsoid_splat::{Camera, Ellipsoid, Frame, Scene};
use glam::{DQuat, DVec3};

/// `count` glyphs around the origin in a cube of half-size 3, from a fixed `seed`.
pub fn glyphs(count: usize, seed: u64) -> Vec<Ellipsoid> {
    let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    (0..count)
        .map(|_| {
            let center = DVec3::new(3.0 * next(), 3.0 * next(), 3.0 * next());
            let radii = DVec3::new(0.35 + 0.2 * next(), 0.3 + 0.15 * next(), 0.2 + 0.1 * next());
            let rotation = DQuat::from_xyzw(next(), next(), next(), next() + 1.5).normalize();
            let color = [0.5 + 0.4 * next() as f32, 0.5, 0.5 - 0.4 * next() as f32];
            Ellipsoid::new(center, radii, rotation, Some(color)).expect("a valid glyph")
        })
        .collect()
}

/// The first scene.
pub fn first_scene() -> Scene {
    Scene::new(glyphs(300, 1))
}

/// The glyphs an update writes at [`UPDATE_FIRST`]: moved and shrunk, inside the scene's
/// bounds.
pub fn updated_glyphs() -> Vec<Ellipsoid> {
    glyphs(40, 2)
        .into_iter()
        .map(|e| {
            Ellipsoid::new(
                e.center * 0.7,
                e.radii * 0.8,
                e.rotation,
                Some([0.9, 0.9, 0.2]),
            )
            .expect("a valid glyph")
        })
        .collect()
}

/// Where the update writes.
pub const UPDATE_FIRST: u32 = 100;

/// The larger scene uploaded later (its buffers grow).
pub fn second_scene() -> Scene {
    Scene::new(glyphs(900, 3))
}

/// A camera looking at the origin from `eye`, `width` x `height` pixels.
pub fn camera(eye: DVec3, width: u32, height: u32) -> Camera {
    Camera::look_at(eye, DVec3::ZERO, 50.0, 0.5, width, height).expect("a valid camera")
}

/// Every output of a frame as bits.
pub fn bits(frame: &Frame) -> Vec<u32> {
    let mut bits: Vec<u32> = frame.color.iter().map(|c| u32::from_le_bytes(*c)).collect();
    bits.extend(frame.depth.iter().map(|v| v.to_bits()));
    bits.extend(frame.normal.iter().flatten().map(|v| v.to_bits()));
    bits.extend(&frame.id);
    bits
}
