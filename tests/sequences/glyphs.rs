//! The glyphs a sequence uploads: made from a seed, so a shrunk case names them in a few
//! numbers, and the defects a host can write into an `Ellipsoid`'s public fields, each of
//! which `upload` and `update` must refuse by naming the glyph.

use ellipsoid_splat::Ellipsoid;
use glam::{DQuat, DVec3};

/// SplitMix64: a few lines, the same numbers on every machine.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }
}

/// A glyph inside the cube `[-1.5, 1.5]^3` where every camera looks. Red stays at 0.9 or more,
/// so a covered pixel is never the offscreen renderer's dark background nor the host's black
/// one, even at one sample of four and ambient light alone (`oracle.rs`).
pub fn glyph(rng: &mut Rng) -> Ellipsoid {
    let center = DVec3::new(
        rng.range(-1.5, 1.5),
        rng.range(-1.5, 1.5),
        rng.range(-1.5, 1.5),
    );
    let radii = DVec3::new(
        rng.range(0.15, 0.8),
        rng.range(0.15, 0.8),
        rng.range(0.15, 0.8),
    );
    let axis = DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    let rotation = DQuat::from_axis_angle(
        axis.try_normalize().unwrap_or(DVec3::Z),
        rng.range(0.0, 6.3),
    );
    let color = [
        rng.range(0.9, 1.0) as f32,
        rng.range(0.0, 1.0) as f32,
        rng.range(0.0, 1.0) as f32,
    ];
    Ellipsoid::new(center, radii, rotation, Some(color)).expect("a generated glyph is valid")
}

/// `count` glyphs from `seed`.
pub fn glyphs(count: usize, seed: u64) -> Vec<Ellipsoid> {
    let mut rng = Rng::new(seed);
    (0..count).map(|_| glyph(&mut rng)).collect()
}

/// What a host may write into an `Ellipsoid` literal that no renderer can draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlyphDefect {
    NanCentre,
    InfiniteCentre,
    /// Finite in float64, beyond float32.
    HugeCentre,
    ZeroRadius,
    NegativeRadius,
    NanRadius,
    /// A semi-axis float32 rounds to zero.
    TinyRadius,
    NanRotation,
    ZeroRotation,
    NanColour,
    ColourAboveOne,
}

impl GlyphDefect {
    pub const ALL: [GlyphDefect; 11] = [
        GlyphDefect::NanCentre,
        GlyphDefect::InfiniteCentre,
        GlyphDefect::HugeCentre,
        GlyphDefect::ZeroRadius,
        GlyphDefect::NegativeRadius,
        GlyphDefect::NanRadius,
        GlyphDefect::TinyRadius,
        GlyphDefect::NanRotation,
        GlyphDefect::ZeroRotation,
        GlyphDefect::NanColour,
        GlyphDefect::ColourAboveOne,
    ];

    /// `glyph` with this defect written into its fields.
    pub fn apply(self, glyph: Ellipsoid) -> Ellipsoid {
        let mut e = glyph;
        match self {
            GlyphDefect::NanCentre => e.center.y = f64::NAN,
            GlyphDefect::InfiniteCentre => e.center.x = f64::INFINITY,
            GlyphDefect::HugeCentre => e.center.z = 1e39,
            GlyphDefect::ZeroRadius => e.radii.x = 0.0,
            GlyphDefect::NegativeRadius => e.radii.z = -0.3,
            GlyphDefect::NanRadius => e.radii.y = f64::NAN,
            GlyphDefect::TinyRadius => e.radii.x = 1e-50,
            GlyphDefect::NanRotation => e.rotation.x = f64::NAN,
            GlyphDefect::ZeroRotation => e.rotation = DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0),
            GlyphDefect::NanColour => e.color[1] = f32::NAN,
            GlyphDefect::ColourAboveOne => e.color[2] = 1.5,
        }
        e
    }
}
