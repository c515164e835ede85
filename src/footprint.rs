//! The screen polygon each impostor is drawn as, chosen per frame from the glyphs' mean
//! projected area (docs/design.md §5.1).

/// The screen-space polygon around an impostor's projected ellipse. Any affine image of a
/// polygon circumscribing the unit circle circumscribes the ellipse with the same area ratio.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Footprint {
    /// A triangle (area ratio 1.65; 3 vertices, one primitive).
    Triangle,
    /// The oriented rectangle: 4/pi of the ellipse's area for any shape and orientation.
    OrientedRect,
    /// A hexagon (area ratio 1.10; 6 vertices).
    Hexagon,
    /// An octagon (area ratio 1.05; 8 vertices).
    Octagon,
}

impl Footprint {
    /// Mean projected glyph area (square pixels) above which the hexagon's 13 % fewer
    /// fragments pay for its 2 extra vertices, and above which the octagon's pay for 2 more.
    /// From lavapipe's costs on this project's machine: about 0.18 us per vertex (its
    /// front end is single-threaded) and 6 ns per impostor fragment.
    pub const HEXAGON_AREA: f64 = 360.0;
    /// See [`Footprint::HEXAGON_AREA`].
    pub const OCTAGON_AREA: f64 = 1200.0;
    /// Mean projected area below which the triangle's one primitive and three vertices cost
    /// less than the rectangle's two and four, its larger area notwithstanding.
    pub const TRIANGLE_AREA: f64 = 250.0;

    /// The footprint for glyphs of this mean projected area on single-sample targets: the
    /// rectangle for small glyphs (the triangle below [`Footprint::TRIANGLE_AREA`] when
    /// `triangles`, [`crate::Settings::small_glyph_triangles`]), where vertex work
    /// dominates; the hexagon and then the octagon as glyphs grow and fragments dominate.
    pub fn for_area(mean_area_px: f64, triangles: bool) -> Footprint {
        if mean_area_px >= Self::OCTAGON_AREA {
            Footprint::Octagon
        } else if mean_area_px >= Self::HEXAGON_AREA {
            Footprint::Hexagon
        } else if mean_area_px >= Self::TRIANGLE_AREA || !triangles {
            Footprint::OrientedRect
        } else {
            Footprint::Triangle
        }
    }

    /// The footprint on multisampled targets. There lavapipe finds each primitive's coverage
    /// at every sample of every 4 x 4 block it touches, which costs more than the fragments a
    /// tighter polygon saves: the triangle below [`Footprint::TRIANGLE_AREA`], the oriented
    /// rectangle above. Measured with 4x MSAA in `examples/embed --bench` with the footprint
    /// forced in a patched build (2026-11-25, lavapipe on 2 CPU cores, variants
    /// interleaved): glyphs of 559 px^2, rectangle 196.7 ms against hexagon 234.0; of 29
    /// px^2, triangle 173.4 ms against rectangle 209.1.
    pub fn for_area_multisampled(mean_area_px: f64) -> Footprint {
        if mean_area_px >= Self::TRIANGLE_AREA {
            Footprint::OrientedRect
        } else {
            Footprint::Triangle
        }
    }

    /// Vertices per instance (a triangle strip over the polygon).
    pub fn vertices(self) -> u32 {
        match self {
            Footprint::Triangle => 3,
            Footprint::OrientedRect => 4,
            Footprint::Hexagon => 6,
            Footprint::Octagon => 8,
        }
    }
}
