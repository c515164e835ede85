//! Which images a frame produces: the offscreen renderer allocates, draws and reads back only
//! those.

/// The outputs of an offscreen frame.
/// The default is none: a frame that only draws.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub struct Outputs {
    /// sRGB colour.
    pub color: bool,
    /// View depth (the depth target itself always exists: the draw depth-tests against it).
    pub depth: bool,
    /// World-space unit normal.
    pub normal: bool,
    /// Instance index.
    pub id: bool,
}

impl Outputs {
    /// Every output.
    pub const ALL: Outputs = Outputs {
        color: true,
        depth: true,
        normal: true,
        id: true,
    };
    /// Colour and depth: what a host's frame draws.
    pub const COLOR_DEPTH: Outputs = Outputs {
        color: true,
        depth: true,
        normal: false,
        id: false,
    };

    /// Whether every output of `other` is one of these.
    pub fn covers(self, other: Outputs) -> bool {
        (self.color || !other.color)
            && (self.depth || !other.depth)
            && (self.normal || !other.normal)
            && (self.id || !other.id)
    }

    /// Whether the pass has the normal and ID attachments (the fragment stage writes both).
    pub fn aux(self) -> bool {
        self.normal || self.id
    }
}
