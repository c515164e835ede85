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
//!
//! `Ellipsoid`'s fields are public, so packing checks each glyph's own fields before anything
//! else and refuses, naming it (`Invalid`, "ellipsoid k"), a centre that is not finite, semi-axes
//! float32 does not hold above 0, a zero or non-finite quaternion, a colour outside [0, 1]; a
//! quaternion off unit length is stored normalised. A scene whose glyphs lie too far apart for
//! float32 offsets from one origin is refused as "scene", naming the glyphs at both ends.

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
    for (k, e) in scene.ellipsoids.iter().enumerate() {
        check_fields(e, k)?;
    }
    if let Some(error) = span_beyond_float32(scene, placement.origin) {
        return Err(error);
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
    // Each glyph's own fields first: one no renderer can draw must be named, not another
    // whose offset it spoiled through the placement (which takes every centre).
    for (k, e) in ellipsoids.iter().enumerate() {
        check_fields(e, first + k)?;
    }
    let mut extent: Option<(DVec3, DVec3)> = None;
    for (k, e) in ellipsoids.iter().enumerate() {
        let index = first + k;
        let c = (e.center - origin).as_vec3();
        if !c.is_finite() {
            return Err(Error::invalid(
                format!("ellipsoid {index}"),
                format!(
                    "centre {} lies {:e} from the scene origin {origin}: beyond float32",
                    e.center,
                    (e.center - origin).abs().max_element()
                ),
            ));
        }
        let r = e.radii.as_vec3();
        let rotation = unit_rotation(e, index)?;
        let sphere = r.x == r.y && r.y == r.z;
        // A sphere's orientation changes nothing but rounding: store none.
        let q = if sphere {
            glam::Quat::IDENTITY
        } else {
            rotation.as_quat()
        };
        let reach = DVec3::splat(e.radii.max_element());
        extent = Some(match extent {
            None => (e.center - reach, e.center + reach),
            Some((lo, hi)) => (lo.min(e.center - reach), hi.max(e.center + reach)),
        });
        let color = e.color.map(|v| (v * 255.0).round() as u32);
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

/// Refuses, naming ellipsoid `index`, fields no renderer can draw: a centre that is not
/// finite, semi-axes float32 does not hold above zero, a rotation that is no quaternion, a
/// colour outside [0, 1]. The fields are public, so a host may have written anything there.
fn check_fields(e: &Ellipsoid, index: usize) -> Result<()> {
    let r = e.radii.as_vec3();
    let why = if !e.center.is_finite() {
        format!("centre {} is not finite", e.center)
    } else if !(r.is_finite() && r.min_element() > 0.0) {
        format!("radii {} do not fit float32 above 0", e.radii)
    } else if e.color.iter().any(|v| !(0.0..=1.0).contains(v)) {
        format!("colour {:?} has a component outside [0, 1]", e.color)
    } else {
        return unit_rotation(e, index).map(|_| ());
    };
    Err(Error::invalid(format!("ellipsoid {index}"), why))
}

/// The error for a scene whose glyphs lie too far apart for float32 offsets from `origin`:
/// it names the two farthest apart along the axis where one does not fit, not a glyph that
/// merely shares the scene with an outlier.
fn span_beyond_float32(scene: &Scene, origin: DVec3) -> Option<Error> {
    let fits = |p: DVec3| (p - origin).as_vec3().is_finite();
    let outside = scene.ellipsoids.iter().find(|e| !fits(e.center))?;
    let axis = (0..3)
        .find(|&a| !((outside.center[a] - origin[a]) as f32).is_finite())
        .unwrap_or(0);
    let along = |e: &&Ellipsoid| e.center[axis];
    let indexed = || scene.ellipsoids.iter().enumerate();
    let (low, a) = indexed().min_by(|x, y| along(&x.1).total_cmp(&along(&y.1)))?;
    let (high, b) = indexed().max_by(|x, y| along(&x.1).total_cmp(&along(&y.1)))?;
    Some(Error::invalid(
        "scene",
        format!(
            "ellipsoid {low} at {} and ellipsoid {high} at {} lie {:e} apart: float32 offsets \
             from one origin cannot hold both",
            a.center,
            b.center,
            b.center[axis] - a.center[axis]
        ),
    ))
}

/// `e`'s rotation as the unit quaternion the shaders assume: its fields are public, so a
/// host may have written any quaternion there; one that is not finite or has no length is
/// refused, naming the glyph, and one off unit length by more than float64 rounding (what
/// `Ellipsoid::new` leaves) is normalised.
fn unit_rotation(e: &Ellipsoid, index: usize) -> Result<glam::DQuat> {
    let length = e.rotation.length();
    if !(length.is_finite() && length >= 1e-12) {
        return Err(Error::invalid(
            format!("ellipsoid {index}"),
            format!(
                "rotation {} is not a finite, non-zero quaternion",
                e.rotation
            ),
        ));
    }
    Ok(if (length - 1.0).abs() > 1e-12 {
        e.rotation / length
    } else {
        e.rotation
    })
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

    /// The fields are public: a rotation no shader can use, or a colour outside [0, 1], is
    /// refused naming the glyph; a quaternion off unit length is stored normalised.
    #[test]
    fn written_fields_are_refused_or_normalised() {
        let good = Ellipsoid::new(
            DVec3::ZERO,
            DVec3::new(1.0, 0.5, 0.3),
            DQuat::from_rotation_z(0.7),
            Some([0.5; 3]),
        )
        .unwrap();
        let pack = |e: Ellipsoid| pack_instances(&Scene::new(vec![good, e]));
        for rotation in [
            DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0),
        ] {
            let err = pack(Ellipsoid { rotation, ..good }).unwrap_err();
            assert!(
                err.to_string().contains("ellipsoid 1") && err.to_string().contains("rotation"),
                "{err}"
            );
        }
        for color in [[0.5, f32::NAN, 0.5], [0.5, 0.5, 1.5], [-0.1, 0.5, 0.5]] {
            let err = pack(Ellipsoid { color, ..good }).unwrap_err();
            assert!(
                err.to_string().contains("ellipsoid 1") && err.to_string().contains("colour"),
                "{err}"
            );
        }
        // An outlier float32 offsets cannot reach from the others: the scene is refused
        // naming both ends, not the first glyph its placement spoiled; alone it packs.
        let far = Ellipsoid {
            center: DVec3::new(0.0, 0.0, 1e39),
            ..good
        };
        let err = pack_instances(&Scene::new(vec![good, good, far, good])).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("invalid scene") && text.contains("ellipsoid 2"),
            "{err}"
        );
        pack_instances(&Scene::new(vec![far])).unwrap();
        let scaled = pack(Ellipsoid {
            rotation: good.rotation * 3.0,
            ..good
        })
        .unwrap();
        let unit = pack(good).unwrap();
        assert_eq!(scaled.records, unit.records);
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
