//! How view depth becomes a depth-buffer value: the host's convention (reversed or standard Z,
//! finite or infinite far plane), so ellipsoids depth-test exactly against the host's meshes.
//! The map of every convention: [`DepthConvention`].

use ash::vk;

use crate::error::{Error, Result};

/// Where the near and far planes land in the depth buffer.
///
/// Every convention is one map `depth(d) = a + b d + c / d` of view depth `d` (a `DepthMap`,
/// from [`DepthConvention::map`] or [`Camera::depth_map`](crate::Camera::depth_map)):
///
/// | convention | perspective (and orthographic without far) | orthographic with far |
/// |---|---|---|
/// | reversed, infinite | `n / d` | -- |
/// | reversed, far `f` | `n (f - d) / (d (f - n))` | `(f - d) / (f - n)` |
/// | standard, infinite | `1 - n / d` | -- |
/// | standard, far `f` | `f (d - n) / (d (f - n))` | `(d - n) / (f - n)` |
///
/// Perspective projection matrices give the hyperbolic column, orthographic ones the linear
/// column; an orthographic camera with no far plane keeps the hyperbolic map (a linear one
/// needs a far plane).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthConvention {
    /// Reversed Z: 1 at the near plane, falling towards 0 far away (compare `GREATER`, clear
    /// to 0). Standard Z: 0 at the near plane, rising towards 1 (compare `LESS`, clear to 1).
    pub reversed: bool,
    /// The far plane's view depth; `None` for an infinite far plane.
    pub far: Option<f64>,
}

impl Default for DepthConvention {
    /// Reversed Z with an infinite far plane: the most precise choice for a float depth buffer.
    fn default() -> Self {
        Self::REVERSED_INFINITE
    }
}

/// The map `depth(d) = a + b d + c / d` of one camera's convention: its terms per convention
/// are the table on [`DepthConvention`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthMap {
    /// Constant term.
    pub a: f64,
    /// Linear term (orthographic cameras with a far plane).
    pub b: f64,
    /// Reciprocal term (everything else).
    pub c: f64,
}

impl DepthConvention {
    /// Reversed Z, infinite far plane (the crate's default).
    pub const REVERSED_INFINITE: Self = Self {
        reversed: true,
        far: None,
    };
    /// Standard Z, infinite far plane.
    pub const STANDARD_INFINITE: Self = Self {
        reversed: false,
        far: None,
    };

    /// Checks the far plane against the camera's `near`.
    pub fn validate(&self, near: f64) -> Result<()> {
        match self.far {
            Some(far) if !(far.is_finite() && far > near) => Err(Error::invalid(
                "camera far",
                format!("must be finite and beyond near ({near}), got {far}"),
            )),
            _ => Ok(()),
        }
    }

    /// The map for a camera with `near` (`linear`: an orthographic camera with a far plane).
    pub fn map(&self, near: f64, orthographic: bool) -> DepthMap {
        let n = near;
        match (self.far, self.reversed) {
            (None, true) => DepthMap {
                a: 0.0,
                b: 0.0,
                c: n,
            },
            (None, false) => DepthMap {
                a: 1.0,
                b: 0.0,
                c: -n,
            },
            (Some(f), reversed) if orthographic => {
                let s = if reversed { -1.0 } else { 1.0 };
                let base = if reversed { f } else { -n };
                DepthMap {
                    a: base / (f - n),
                    b: s / (f - n),
                    c: 0.0,
                }
            }
            (Some(f), true) => DepthMap {
                a: -n / (f - n),
                b: 0.0,
                c: n * f / (f - n),
            },
            (Some(f), false) => DepthMap {
                a: f / (f - n),
                b: 0.0,
                c: -n * f / (f - n),
            },
        }
    }

    /// The depth compare operation that keeps the nearer fragment.
    pub fn compare_op(&self) -> vk::CompareOp {
        if self.reversed {
            vk::CompareOp::GREATER
        } else {
            vk::CompareOp::LESS
        }
    }

    /// The depth-buffer value that means "nothing drawn" (the far end): clear to this.
    pub fn clear_value(&self) -> f32 {
        if self.reversed {
            0.0
        } else {
            1.0
        }
    }
}

impl DepthMap {
    /// The depth-buffer value of view depth `d`.
    pub fn depth(&self, d: f64) -> f64 {
        self.a + self.b * d + self.c / d
    }

    /// The view depth whose depth-buffer value is `z` (the inverse of `depth`).
    pub fn view_depth(&self, z: f64) -> f64 {
        if self.b != 0.0 {
            (z - self.a) / self.b
        } else {
            self.c / (z - self.a)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each map sends near and far to the ends the table says, and is monotonic between.
    #[test]
    fn maps_send_near_and_far_to_their_ends() {
        let (n, f) = (0.5, 80.0);
        for reversed in [true, false] {
            for orthographic in [false, true] {
                let convention = DepthConvention {
                    reversed,
                    far: Some(f),
                };
                let m = convention.map(n, orthographic);
                let (at_near, at_far) = if reversed { (1.0, 0.0) } else { (0.0, 1.0) };
                assert!((m.depth(n) - at_near).abs() < 1e-12, "{convention:?} {m:?}");
                assert!((m.depth(f) - at_far).abs() < 1e-12, "{convention:?} {m:?}");
                let mid = m.depth(10.0);
                assert!(mid > 0.0 && mid < 1.0);
                assert!((m.view_depth(mid) - 10.0).abs() < 1e-9);
            }
            let infinite = DepthConvention {
                reversed,
                far: None,
            }
            .map(n, false);
            let at_near = if reversed { 1.0 } else { 0.0 };
            assert_eq!(infinite.depth(n), at_near);
            assert!((infinite.depth(1e30) - (1.0 - at_near)).abs() < 1e-12);
        }
    }

    #[test]
    fn names_a_bad_far_plane() {
        let c = DepthConvention {
            reversed: false,
            far: Some(0.1),
        };
        assert!(c.validate(1.0).unwrap_err().to_string().contains("far"));
        assert!(c.validate(0.01).is_ok());
    }
}
