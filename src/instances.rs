//! The GPU instance record: how a scene becomes the bytes of the instance buffer.
//!
//! Two layouts (`load_instance` in `glsl/include/ellipsoid_common.glsl` reads both):
//! - **full**, 48 bytes (`Instance` in `src/gpu_layout.rs`): centre relative to the scene origin (3 x f32),
//!   sRGB colour as RGBA8 (u32), unit quaternion (x, y, z, w: 4 x f32), semi-axes (3 x f32) and
//!   one unused f32;
//! - **compact**, 32 bytes (`CompactInstance`): the same centre and colour, the quaternion as
//!   4 x snorm16, and the
//!   semi-axes as 3 x float16 in units of the scene's largest semi-axis (so every scene uses
//!   the half floats' full precision), one float16 unused. The quantisation moves the surface
//!   by at most about 2^-11 of a semi-axis (the float16 rounding) plus 2^-15 of a radian of
//!   rotation; `bench` reports what that costs in accuracy beside the time it saves.

// Without `research` the module is private, and the conveniences only the benchmark calls
// go unused.
use glam::DVec3;

use crate::ellipsoid::Ellipsoid;
use crate::error::{Error, Result};
use crate::gpu_layout::{CompactInstance, Instance};
use crate::scene::Scene;

/// How instances are stored on the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum InstanceFormat {
    /// 48 bytes, float32 throughout (exact to float32).
    #[default]
    Full,
    /// 32 bytes: snorm16 rotation, float16 semi-axes (see the module documentation).
    Compact,
}

impl InstanceFormat {
    /// Bytes per instance.
    pub fn bytes(self) -> usize {
        match self {
            InstanceFormat::Full => size_of::<Instance>(),
            InstanceFormat::Compact => size_of::<CompactInstance>(),
        }
    }
}

/// Instance records in one of the two formats.
#[derive(Clone, Debug, PartialEq)]
pub enum Records {
    /// [`InstanceFormat::Full`].
    Full(Vec<Instance>),
    /// [`InstanceFormat::Compact`].
    Compact(Vec<CompactInstance>),
}

impl Records {
    /// The records as the bytes the instance buffer holds.
    pub fn bytes(&self) -> &[u8] {
        match self {
            Records::Full(v) => bytemuck::cast_slice(v),
            Records::Compact(v) => bytemuck::cast_slice(v),
        }
    }

    /// Number of records.
    pub fn len(&self) -> usize {
        match self {
            Records::Full(v) => v.len(),
            Records::Compact(v) => v.len(),
        }
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A scene packed for the GPU.
#[derive(Clone, Debug, PartialEq)]
pub struct PackedInstances {
    /// Positions are stored relative to this point (the centre of the data's bounds), so
    /// float32 keeps its precision where the data is, however far from the world origin.
    pub origin: DVec3,
    /// One record per ellipsoid, in scene order.
    pub records: Records,
    /// Corners of a box holding every ellipsoid whole (centre +- largest semi-axis), in world
    /// coordinates; `None` for an empty scene.
    pub extent: Option<(DVec3, DVec3)>,
    /// Compact format: the unit of the stored semi-axes (the scene's largest semi-axis).
    pub radius_scale: f32,
}

impl PackedInstances {
    /// Number of instances.
    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// The layout of the records.
    pub fn format(&self) -> InstanceFormat {
        match self.records {
            Records::Full(_) => InstanceFormat::Full,
            Records::Compact(_) => InstanceFormat::Compact,
        }
    }
}

/// Packs every ellipsoid of `scene` in the full format; errors name the first ellipsoid
/// float32 cannot hold.
pub fn pack_instances(scene: &Scene) -> Result<PackedInstances> {
    pack_scene(scene, InstanceFormat::Full, Placement::of(scene))
}

/// Where an uploaded scene's glyphs are stored from: positions as float32 offsets from
/// `origin`, compact semi-axes in units of `radius_scale`. A scene's own placement
/// ([`Placement::of`]) keeps float32 precise where its data is; parts of one scene drawn apart
/// (by several processes) draw the whole scene's bits only when each is uploaded with the
/// whole's placement ([`Placement::enclosing`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// The point positions are stored relative to.
    pub origin: DVec3,
    /// The unit of compact semi-axes (the scene's largest semi-axis).
    pub radius_scale: f32,
}

impl Placement {
    /// `scene`'s own placement: the centre of its bounds ([`Scene::bounds`]) and its largest
    /// semi-axis.
    pub fn of(scene: &Scene) -> Self {
        let largest = scene
            .ellipsoids
            .iter()
            .map(|e| e.radii.max_element())
            .fold(0.0, f64::max);
        Self::enclosing(scene.bounds(), largest)
    }

    /// The placement of a scene with `bounds` (the union of its parts' [`Scene::bounds`];
    /// `None` when empty) and largest semi-axis `largest`: what [`Placement::of`] gives the
    /// whole scene.
    pub fn enclosing(bounds: Option<(DVec3, DVec3)>, largest: f64) -> Self {
        Self {
            origin: bounds
                .map(|(lo, hi)| (lo + hi) * 0.5)
                .unwrap_or(DVec3::ZERO),
            radius_scale: if largest > 0.0 { largest as f32 } else { 1.0 },
        }
    }
}

/// Packs every ellipsoid of `scene` in `format`, placed as `placement` says.
pub fn pack_scene(
    scene: &Scene,
    format: InstanceFormat,
    placement: Placement,
) -> Result<PackedInstances> {
    if u32::try_from(scene.len()).is_err() {
        return Err(Error::invalid(
            "scene",
            format!("{} ellipsoids exceed u32", scene.len()),
        ));
    }
    pack_relative(
        &scene.ellipsoids,
        placement.origin,
        0,
        format,
        placement.radius_scale,
    )
}

/// Packs `ellipsoids` relative to `origin` in `format` (an update of instances `first..` of a
/// scene already on the GPU keeps its origin and radius scale); errors name the scene index
/// `first + k`.
pub fn pack_relative(
    ellipsoids: &[Ellipsoid],
    origin: DVec3,
    first: usize,
    format: InstanceFormat,
    radius_scale: f32,
) -> Result<PackedInstances> {
    let mut records = match format {
        InstanceFormat::Full => Records::Full(Vec::with_capacity(ellipsoids.len())),
        InstanceFormat::Compact => Records::Compact(Vec::with_capacity(ellipsoids.len())),
    };
    let mut extent: Option<(DVec3, DVec3)> = None;
    for (k, e) in ellipsoids.iter().enumerate() {
        let index = first + k;
        let c = (e.center - origin).as_vec3();
        let r = e.radii.as_vec3();
        let sphere = r.x == r.y && r.y == r.z;
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
        let center = c.to_array();
        match &mut records {
            Records::Full(v) => v.push(Instance {
                center,
                color: packed,
                rotation: q.to_array(),
                radii: r.to_array(),
                unused: 0.0,
            }),
            Records::Compact(v) => {
                let snorm = |v: f32| ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16;
                let relative = r / radius_scale;
                let halves = [relative.x, relative.y, relative.z].map(f16_bits);
                if halves.iter().any(|&h| h == 0 || h >= 0x7c00) {
                    return Err(Error::invalid(
                        format!("ellipsoid {index}"),
                        format!(
                            "radii {} span too wide a range for the compact format's half floats \
                             (the scene's largest semi-axis is {radius_scale}); use the full format",
                            e.radii
                        ),
                    ));
                }
                let pair = |lo: u16, hi: u16| lo as u32 | (hi as u32) << 16;
                v.push(CompactInstance {
                    center,
                    color: packed,
                    rotation: [pair(snorm(q.x), snorm(q.y)), pair(snorm(q.z), snorm(q.w))],
                    radii: [pair(halves[0], halves[1]), halves[2] as u32],
                });
            }
        }
    }
    Ok(PackedInstances {
        origin,
        records,
        extent,
        radius_scale,
    })
}

/// The IEEE binary16 bits nearest to `v` (round to nearest even; overflow gives infinity,
/// values below the subnormal range give zero), as GLSL's `unpackHalf2x16` reads them.
fn f16_bits(v: f32) -> u16 {
    half::f16::from_f32(v).to_bits()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn half_floats_round_like_the_gpu_reads_them() {
        assert_eq!(f16_bits(1.0), 0x3c00);
        assert_eq!(f16_bits(0.5), 0x3800);
        assert_eq!(f16_bits(65504.0), 0x7bff);
        assert_eq!(f16_bits(1e6), 0x7c00);
        assert_eq!(f16_bits(2f32.powi(-24)), 0x0001); // smallest subnormal
        assert_eq!(f16_bits(1e-10), 0);
        // 1 + 2^-11 is halfway between 1 and the next half: ties go to even (1.0).
        assert_eq!(f16_bits(1.0 + 2f32.powi(-11)), 0x3c00);
        assert_eq!(f16_bits(1.0 + 3.0 * 2f32.powi(-11)), 0x3c02);
    }

    #[test]
    fn compact_records_are_32_bytes_and_refuse_a_too_wide_range() {
        let e =
            |r: f64| Ellipsoid::new(DVec3::ZERO, DVec3::new(r, 1.0, 1.0), DQuat::IDENTITY, None);
        let scene = Scene::new(vec![e(1.0).unwrap(), e(2.0).unwrap()]);
        let packed = pack_scene(&scene, InstanceFormat::Compact, Placement::of(&scene)).unwrap();
        assert_eq!(packed.records.bytes().len(), 64);
        assert_eq!(packed.radius_scale, 2.0);
        let wide = Scene::new(vec![e(1e-9).unwrap(), e(1.0).unwrap()]);
        let err = pack_scene(&wide, InstanceFormat::Compact, Placement::of(&wide)).unwrap_err();
        assert!(
            err.to_string().contains("ellipsoid 0") && err.to_string().contains("compact"),
            "{err}"
        );
    }

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
        let Records::Full(records) = &packed.records else {
            panic!("full format asked for");
        };
        assert_eq!(records[0].center[0], -2.0);
        assert_eq!(records[0].color, 255 | (128 << 8) | (255 << 24));
    }

    #[test]
    fn radii_that_underflow_float32_are_rejected() {
        let tiny = Ellipsoid::new(DVec3::ZERO, DVec3::splat(1e-60), DQuat::IDENTITY, None).unwrap();
        let err = pack_instances(&Scene::new(vec![tiny])).unwrap_err();
        assert!(err.to_string().contains("ellipsoid 0"), "{err}");
    }
}
