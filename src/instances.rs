//! The GPU instance record: how a scene becomes the bytes of the instance buffer.
//!
//! Layout (std430, 48 bytes, `Instance` in `glsl/include/ellipsoid_common.glsl`): centre
//! relative to the scene origin (3 x f32), sRGB colour as RGBA8 (u32), unit quaternion
//! (x, y, z, w: 4 x f32), semi-axes (3 x f32) and one unused f32.

use glam::DVec3;

use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result};
use crate::scene::Scene;

/// Bytes per instance on the GPU.
pub const INSTANCE_BYTES: usize = 48;

/// A scene packed for the GPU.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedInstances {
    /// Positions are stored relative to this point (the centre of the data's bounds), so
    /// float32 keeps its precision where the data is, however far from the world origin.
    pub origin: DVec3,
    /// `INSTANCE_BYTES` per ellipsoid, in scene order.
    pub bytes: Vec<u8>,
    /// Every instance is a sphere (equal float32 semi-axes): the shaders may take the sphere
    /// path. Spheres are stored with the identity rotation, so both paths compute the same
    /// bits.
    pub all_spheres: bool,
    /// Corners of a box holding every ellipsoid whole (centre +- largest semi-axis), in world
    /// coordinates; `None` for an empty scene.
    pub extent: Option<(DVec3, DVec3)>,
}

impl PackedInstances {
    /// Number of instances.
    pub fn len(&self) -> usize {
        self.bytes.len() / INSTANCE_BYTES
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }
}

/// Packs every ellipsoid of `scene`; errors name the first ellipsoid float32 cannot hold.
pub fn pack_instances(scene: &Scene) -> Result<PackedInstances> {
    if u32::try_from(scene.len()).is_err() {
        return Err(Error::invalid(
            "scene",
            format!("{} ellipsoids exceed u32", scene.len()),
        ));
    }
    let origin = scene
        .bounds()
        .map(|(lo, hi)| (lo + hi) * 0.5)
        .unwrap_or(DVec3::ZERO);
    pack_relative(&scene.ellipsoids, origin, 0)
}

/// Packs `ellipsoids` relative to `origin` (an update of instances `first..` of a scene
/// already on the GPU keeps its origin); errors name the scene index `first + k`.
pub fn pack_relative(
    ellipsoids: &[Ellipsoid],
    origin: DVec3,
    first: usize,
) -> Result<PackedInstances> {
    let mut bytes = Vec::with_capacity(INSTANCE_BYTES * ellipsoids.len());
    let mut all_spheres = true;
    let mut extent: Option<(DVec3, DVec3)> = None;
    for (k, e) in ellipsoids.iter().enumerate() {
        let index = first + k;
        let c = (e.center - origin).as_vec3();
        let r = e.radii.as_vec3();
        let sphere = r.x == r.y && r.y == r.z;
        all_spheres &= sphere;
        // A sphere's orientation changes nothing but rounding: store none.
        let q = if sphere {
            glam::Quat::IDENTITY
        } else {
            e.rotation.as_quat()
        };
        let reach = DVec3::splat(e.radii.max_element());
        extent = Some(match extent {
            None => (e.center - reach, e.center + reach),
            Some((lo, hi)) => (lo.min(e.center - reach), hi.max(e.center + reach)),
        });
        if !(r.is_finite() && r.min_element() > 0.0 && c.is_finite()) {
            return Err(Error::invalid(
                format!("ellipsoid {index}"),
                format!(
                    "centre {} or radii {} do not fit float32 (radii must stay > 0)",
                    e.center, e.radii
                ),
            ));
        }
        let color = e.color.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u32);
        let packed = color[0] | (color[1] << 8) | (color[2] << 16) | (255 << 24);
        for v in [c.x, c.y, c.z] {
            bytes.extend_from_slice(&v.to_ne_bytes());
        }
        bytes.extend_from_slice(&packed.to_ne_bytes());
        for v in [q.x, q.y, q.z, q.w, r.x, r.y, r.z, 0.0] {
            bytes.extend_from_slice(&v.to_ne_bytes());
        }
    }
    Ok(PackedInstances {
        origin,
        bytes,
        all_spheres: all_spheres && !ellipsoids.is_empty(),
        extent,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn packs_relative_to_the_bounds_centre() {
        let e = |x: f64| {
            Ellipsoid::new(
                DVec3::new(x, 0.0, 0.0),
                DVec3::ONE,
                DQuat::IDENTITY,
                Some([1.0, 0.5, 0.0]),
            )
            .unwrap()
        };
        let packed = pack_instances(&Scene::new(vec![e(1e7), e(1e7 + 4.0)])).unwrap();
        assert_eq!(packed.len(), 2);
        assert_eq!(packed.origin, DVec3::new(1e7 + 2.0, 0.0, 0.0));
        let x0 = f32::from_ne_bytes(packed.bytes[0..4].try_into().unwrap());
        assert_eq!(x0, -2.0);
        let color = u32::from_ne_bytes(packed.bytes[12..16].try_into().unwrap());
        assert_eq!(color, 255 | (128 << 8) | (255 << 24));
    }

    #[test]
    fn radii_that_underflow_float32_are_rejected() {
        let tiny = Ellipsoid::new(DVec3::ZERO, DVec3::splat(1e-60), DQuat::IDENTITY, None).unwrap();
        let err = pack_instances(&Scene::new(vec![tiny])).unwrap_err();
        assert!(err.to_string().contains("ellipsoid 0"), "{err}");
    }
}
