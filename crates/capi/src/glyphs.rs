//! Glyphs from arrays of plain structs.

use ellipsoid_splat::Ellipsoid;
use glam::{DQuat, DVec3};

use crate::status::Failure;

/// One ellipsoid.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct EsGlyph {
    /// Centre in world coordinates.
    pub center: [f64; 3],
    /// Semi-axes along the local x, y, z axes (finite, > 0).
    pub radii: [f64; 3],
    /// The rotation of the local axes into world axes, a quaternion `(w, x, y, z)` (normalised
    /// by the library; not zero).
    pub rotation: [f64; 4],
    /// Display (sRGB) colour, each channel in [0, 1].
    pub color: [f32; 3],
}

/// The library's ellipsoids of `glyphs` (errors name the glyph's index, from `first`). One
/// allocation of the exact size: collecting into a `Result` would grow the vector by doubling.
pub(crate) fn ellipsoids(glyphs: &[EsGlyph], first: usize) -> Result<Vec<Ellipsoid>, Failure> {
    let mut out = Vec::new();
    out.try_reserve_exact(glyphs.len()).map_err(|_| Failure {
        status: crate::status::EsStatus::ErrorOutOfMemory,
        message: format!("no host memory for {} glyphs", glyphs.len()),
    })?;
    for (k, g) in glyphs.iter().enumerate() {
        let [w, x, y, z] = g.rotation;
        let ellipsoid = Ellipsoid::new(
            DVec3::from_array(g.center),
            DVec3::from_array(g.radii),
            DQuat::from_xyzw(x, y, z, w),
            Some(g.color),
        )
        .map_err(|e| Failure::invalid(&format!("glyph {}", first + k), e))?;
        out.push(ellipsoid);
    }
    Ok(out)
}

/// The glyphs behind `glyphs`, checked.
///
/// # Safety
/// A non-null `glyphs` points at `count` readable `EsGlyph`s.
pub(crate) unsafe fn glyph_slice<'a>(
    glyphs: *const EsGlyph,
    count: usize,
) -> Result<&'a [EsGlyph], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    // Instance indices are 32-bit; the bound also keeps the slice's size far below isize::MAX.
    if count > u32::MAX as usize {
        return Err(Failure::invalid(
            "count",
            format!("{count} glyphs is more than 2^32 - 1"),
        ));
    }
    if glyphs.is_null() {
        return Err(Failure::invalid(
            "glyphs",
            format!("is null with count {count}"),
        ));
    }
    // SAFETY: caller contract.
    Ok(unsafe { std::slice::from_raw_parts(glyphs, count) })
}
