//! The scene `--scene` names: a file or a generated scene, checked against the renderer's
//! addressing before anything is loaded (loading is `scene_io`'s).

use std::num::IntErrorKind;
use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::host_memory::gib;
use ellipsoid_splat::{InstanceFormat, NO_INSTANCE};

/// The most ellipsoids a scene can have. Instance indices are u32, and 0xFFFFFFFF
/// ([`NO_INSTANCE`]) marks background pixels in ID images, so indices run up to 0xFFFFFFFE.
pub const MAX_ELLIPSOIDS: u64 = NO_INSTANCE as u64;

/// The particles of `--scene md-liquid` without a count (the benchmark's `md-liquid`).
pub const MD_LIQUID_COUNT: usize = 8000;

/// The side of the largest `tensor-field:N` or `lattice:N`: the largest N with N^3 <=
/// [`MAX_ELLIPSOIDS`].
pub const MAX_TENSOR_FIELD_SIDE: u64 = 1625;

/// A scene as `--scene` names it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSpec {
    /// `tensor-field[:N]`: the N x N x N glyph lattice.
    TensorField(usize),
    /// `lattice[:N]`: N x N x N randomly rotated ellipsoids, semi-axes 0.1 to 0.45 (the
    /// benchmark's `lattice`, seed 1).
    Lattice(usize),
    /// `md-liquid[:N]`: a liquid of N rods and spheres (half each), seed
    /// `scene_io::MD_LIQUID_SEED`.
    MdLiquid(usize),
    /// `random:COUNT`: a random cloud.
    Random(usize),
    /// A scene file.
    File(PathBuf),
}

impl SceneSpec {
    /// Reads `--scene`; generated scenes must stay within [`MAX_ELLIPSOIDS`]. Errors name
    /// `--scene` and say why.
    pub fn parse(spec: &str) -> Result<Self> {
        let invalid = |reason: String| Error::invalid("--scene", reason);
        let side = format!(
            " (tensor-field:N and lattice:N have N^3 glyphs, so N can be at most \
             {MAX_TENSOR_FIELD_SIDE})"
        );
        let too_many = |count: String, note: &str| {
            invalid(format!(
                "{spec} asks for {count} ellipsoids, more than the {MAX_ELLIPSOIDS} the renderer \
                 can address{note}: instance indices are u32 (0xFFFFFFFF marks the background \
                 in ID images), and instances are {} bytes each on the GPU, so \
                 even that many take {}",
                InstanceFormat::Full.bytes(),
                gib(MAX_ELLIPSOIDS * InstanceFormat::Full.bytes() as u64)
            ))
        };
        // `cube`: the count is the number cubed (`tensor-field:N`).
        let count = |text: &str, what: &str, cube: bool| {
            text.trim().parse::<u64>().map_err(|e| match e.kind() {
                IntErrorKind::PosOverflow if cube => too_many(format!("{}^3", text.trim()), &side),
                IntErrorKind::PosOverflow => too_many(text.trim().to_string(), ""),
                _ => invalid(format!("{what} needs a whole number, got '{text}'")),
            })
        };
        // The cubes: `name` alone is 40^3, `name:N` is N^3.
        type Cube = fn(usize) -> SceneSpec;
        let cubes: [(&str, Cube); 2] = [
            ("tensor-field", SceneSpec::TensorField),
            ("lattice", SceneSpec::Lattice),
        ];
        for (name, make) in cubes {
            if spec == name {
                return Ok(make(40));
            }
            if let Some(text) = spec.strip_prefix(name).and_then(|t| t.strip_prefix(':')) {
                let n = count(text, &format!("{name}:N"), true)?;
                if n == 0 {
                    return Err(invalid(format!("{name}:N needs N >= 1")));
                }
                if n > MAX_TENSOR_FIELD_SIDE {
                    let glyphs = u128::from(n)
                        .checked_pow(3)
                        .map_or(format!("{n}^3"), |c| format!("{n}^3 = {c}"));
                    return Err(too_many(glyphs, &side));
                }
                return Ok(make(n as usize));
            }
        }
        if spec == "md-liquid" {
            return Ok(SceneSpec::MdLiquid(MD_LIQUID_COUNT));
        }
        if let Some(text) = spec.strip_prefix("md-liquid:") {
            let n = count(text, "md-liquid:N", false)?;
            if n == 0 {
                return Err(invalid("md-liquid:N needs N >= 1".to_string()));
            }
            if n > MAX_ELLIPSOIDS {
                return Err(too_many(n.to_string(), ""));
            }
            return Ok(SceneSpec::MdLiquid(n as usize));
        }
        if let Some(text) = spec.strip_prefix("random:") {
            let n = count(text, "random:COUNT", false)?;
            if n == 0 {
                return Err(invalid("random:COUNT needs COUNT >= 1".to_string()));
            }
            if n > MAX_ELLIPSOIDS {
                return Err(too_many(n.to_string(), ""));
            }
            return Ok(SceneSpec::Random(n as usize));
        }
        Ok(SceneSpec::File(PathBuf::from(spec)))
    }

    /// How many ellipsoids a generated scene has (`None` for a file).
    pub fn generated_count(&self) -> Option<u64> {
        match *self {
            SceneSpec::TensorField(n) | SceneSpec::Lattice(n) => Some((n as u64).pow(3)),
            SceneSpec::MdLiquid(n) | SceneSpec::Random(n) => Some(n as u64),
            SceneSpec::File(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scene_counts_are_bounded_by_addressing() {
        assert_eq!(
            SceneSpec::parse("random:4294967295").unwrap(),
            SceneSpec::Random(4294967295)
        );
        for spec in [
            "random:4294967296",
            "random:999999999999",
            "random:99999999999999999999999999",
            "tensor-field:1626",
            "tensor-field:99999999999999999999999999",
            "lattice:1626",
        ] {
            let e = SceneSpec::parse(spec).unwrap_err().to_string();
            assert!(
                e.contains("--scene") && e.contains("4294967295") && e.contains("u32"),
                "{spec}: {e}"
            );
        }
        assert_eq!(
            SceneSpec::parse("tensor-field:1625")
                .unwrap()
                .generated_count(),
            Some(1625u64.pow(3))
        );
        assert!(1625u64.pow(3) <= MAX_ELLIPSOIDS && 1626u64.pow(3) > MAX_ELLIPSOIDS);
        assert_eq!(SceneSpec::parse("lattice").unwrap(), SceneSpec::Lattice(40));
        assert_eq!(
            SceneSpec::parse("lattice:3").unwrap(),
            SceneSpec::Lattice(3)
        );
        let e = SceneSpec::parse("lattice:0").unwrap_err().to_string();
        assert!(e.contains("lattice:N needs N >= 1"), "{e}");
        let e = SceneSpec::parse("random:12x").unwrap_err().to_string();
        assert!(e.contains("needs a whole number, got '12x'"), "{e}");
    }

    #[test]
    fn md_liquid_takes_a_particle_count() {
        assert_eq!(
            SceneSpec::parse("md-liquid").unwrap(),
            SceneSpec::MdLiquid(MD_LIQUID_COUNT)
        );
        let spec = SceneSpec::parse("md-liquid:300").unwrap();
        assert_eq!(spec, SceneSpec::MdLiquid(300));
        assert_eq!(spec.generated_count(), Some(300));
        for (text, reason) in [
            ("md-liquid:0", "md-liquid:N needs N >= 1"),
            ("md-liquid:many", "needs a whole number, got 'many'"),
            ("md-liquid:4294967296", "4294967295"),
        ] {
            let e = SceneSpec::parse(text).unwrap_err().to_string();
            assert!(e.contains("--scene") && e.contains(reason), "{text}: {e}");
        }
    }
}
