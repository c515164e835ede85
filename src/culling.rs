//! Which exact culling the pre-pass does (docs/design.md §5.3; its steps are
//! `src/renderer/prepass/`, the shader `glsl/cull.comp`).

/// Which exact culling the pre-pass does before the draw (none: the pre-pass runs only to set
/// up glyphs once, if it does that). Nothing culled
/// can change a pixel: see `glsl/cull.comp`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct Culling {
    /// Drop instances whose silhouette lies off screen or before the near plane.
    pub frustum: bool,
    /// Drop instances whose silhouette's bounding rectangle holds no pixel centre (on
    /// multisampled targets: no sample).
    pub pixel_centres: bool,
    /// Drop instances whose every pixel centre (multisampled: every sample) is covered by an
    /// ellipsoid lying wholly nearer (each ellipsoid vouches for the pixels of its inscribed
    /// sphere).
    pub occlusion: bool,
}

impl Culling {
    /// No culling.
    pub const OFF: Culling = Culling {
        frustum: false,
        pixel_centres: false,
        occlusion: false,
    };
    /// Every kind.
    pub const ON: Culling = Culling {
        frustum: true,
        pixel_centres: true,
        occlusion: true,
    };

    /// Whether anything is culled.
    pub fn any(self) -> bool {
        self.frustum || self.pixel_centres || self.occlusion
    }
}

impl Default for Culling {
    /// Every kind: each is exact, and each costs little where it finds nothing to drop
    /// (`docs/culling.md`).
    fn default() -> Self {
        Self::ON
    }
}
