//! How glyphs are coloured once loaded: the scene's own colours, or one computed from each
//! glyph's shape or orientation. `render --color MODE` applies one mode; a viewer can cycle
//! through [`ColorMode::ALL`].
//!
//! Every colour is a display (sRGB) value in [0, 1], as [`Ellipsoid::color`] is everywhere.

use glam::DVec3;

use ellipsoid_splat::{internals::shape_color, Ellipsoid};

use crate::anisotropy::fractional_anisotropy;

/// The colour of every glyph in [`ColorMode::Uniform`]: a neutral mid-light grey (sRGB 0.7,
/// about 45 % linear), light enough that shading shows and dark enough that highlights do.
pub const UNIFORM_GREY: [f32; 3] = [0.7, 0.7, 0.7];

/// A way of colouring glyphs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorMode {
    /// The colours the scene gives: the file's (CSV `r,g,b`, splat `f_dc`, element colours of
    /// atoms) or, where it gives none, the loader's or generator's choice (shape colours for
    /// tensor volumes, the tensor field and CSV rows without colour; random colours for random
    /// clouds). The default, and what [`ColorMode::apply`] leaves unchanged.
    #[default]
    File,
    /// Shape after Westin's measures: linear red, planar green, spherical blue
    /// ([`shape_color`]).
    Shape,
    /// The direction of the longest semi-axis in world axes, as diffusion-MRI viewers show it:
    /// RGB = its absolute x, y, z components (see [`principal_color`]).
    Principal,
    /// [`ColorMode::Principal`] times the fractional anisotropy of the semi-axes
    /// ([`fractional_anisotropy`]): near-spheres go dark, clear directions stay bright.
    PrincipalFa,
    /// [`UNIFORM_GREY`] for every glyph.
    Uniform,
}

impl ColorMode {
    /// Every mode, in the order a viewer cycles through them.
    pub const ALL: [ColorMode; 5] = [
        ColorMode::File,
        ColorMode::Shape,
        ColorMode::Principal,
        ColorMode::PrincipalFa,
        ColorMode::Uniform,
    ];

    /// The mode's name, as `--color` takes it.
    pub fn name(self) -> &'static str {
        match self {
            ColorMode::File => "file",
            ColorMode::Shape => "shape",
            ColorMode::Principal => "principal",
            ColorMode::PrincipalFa => "principal-fa",
            ColorMode::Uniform => "uniform",
        }
    }

    /// The mode after this one in [`ColorMode::ALL`], wrapping around: what a viewer's colour
    /// key steps to.
    pub fn next(self) -> Self {
        let at = Self::ALL.iter().position(|&m| m == self).unwrap_or(0);
        Self::ALL[(at + 1) % Self::ALL.len()]
    }

    /// The colour of `ellipsoid` in this mode; [`ColorMode::File`] gives its own colour, so a
    /// viewer that keeps the loaded glyphs can recolour a copy in any mode and back again.
    pub fn color(self, ellipsoid: &Ellipsoid) -> [f32; 3] {
        match self {
            ColorMode::File => ellipsoid.color,
            ColorMode::Shape => shape_color(ellipsoid.radii),
            ColorMode::Principal => principal_color(ellipsoid),
            ColorMode::PrincipalFa => {
                let fa = fractional_anisotropy(ellipsoid.radii).clamp(0.0, 1.0) as f32;
                principal_color(ellipsoid).map(|c| c * fa)
            }
            ColorMode::Uniform => UNIFORM_GREY,
        }
    }

    /// Recolours `ellipsoids` in this mode. [`ColorMode::File`] changes nothing: the file's
    /// colours are whatever the glyphs hold, so cycling back to them needs the loaded glyphs
    /// (see [`ColorMode::color`]).
    pub fn apply(self, ellipsoids: &mut [Ellipsoid]) {
        if self == ColorMode::File {
            return;
        }
        for ellipsoid in ellipsoids {
            ellipsoid.color = self.color(ellipsoid);
        }
    }
}

/// The unit direction, in world axes, of `ellipsoid`'s longest semi-axis (its sign is that of
/// the local axis, which colours ignore).
///
/// Ties: when two or three semi-axes are equally longest (a disc, a sphere), there is no unique
/// direction, and the first of them in local order x, y, z is taken -- a sphere gives its local
/// x axis. Equal means equal as stored, so the same glyph always gets the same colour.
pub fn principal_direction(ellipsoid: &Ellipsoid) -> DVec3 {
    let r = ellipsoid.radii;
    // Strict comparisons keep the earlier axis on a tie.
    let local = if r.y > r.x && r.y >= r.z {
        DVec3::Y
    } else if r.z > r.x && r.z > r.y {
        DVec3::Z
    } else {
        DVec3::X
    };
    ellipsoid.axes() * local
}

/// The principal-direction colour: RGB = `|x|, |y|, |z|` of [`principal_direction`] (red along
/// world x, green along y, blue along z), used directly as display values as diffusion-MRI
/// viewers do.
pub fn principal_color(ellipsoid: &Ellipsoid) -> [f32; 3] {
    let d = principal_direction(ellipsoid).abs();
    // A unit vector's components are in [0, 1]; the clamp holds the range for a rotation that
    // is a rounding away from unit length.
    [d.x, d.y, d.z].map(|c| c.clamp(0.0, 1.0) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    fn glyph(radii: DVec3, rotation: DQuat, color: [f32; 3]) -> Ellipsoid {
        Ellipsoid::new(DVec3::ZERO, radii, rotation, Some(color)).unwrap()
    }

    fn close(a: [f32; 3], b: [f64; 3], tolerance: f64) -> bool {
        a.iter()
            .zip(b)
            .all(|(&x, y)| (x as f64 - y).abs() <= tolerance)
    }

    #[test]
    fn principal_colour_is_the_long_axis_in_world_axes() {
        // A needle along local x, turned so that x goes to each of these unit directions.
        let third = 1.0 / 3.0;
        let directions = [
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            DVec3::new(third, 2.0 * third, 2.0 * third),
            DVec3::new(-third, 2.0 * third, -2.0 * third),
            DVec3::new(0.6, -0.8, 0.0),
            DVec3::new(1.0, 1.0, 1.0).normalize(),
        ];
        for to in directions {
            let rotation = DQuat::from_rotation_arc(DVec3::X, to);
            for radii in [DVec3::new(3.0, 1.0, 0.5), DVec3::new(3.0, 0.5, 1.0)] {
                let needle = glyph(radii, rotation, [0.2; 3]);
                let expected = to.abs().to_array();
                let color = principal_color(&needle);
                assert!(close(color, expected, 1e-6), "{to}: {color:?}");
                assert_eq!(ColorMode::Principal.color(&needle), color);
            }
            // The longest axis as local y or z, brought to the same direction.
            let y_long = glyph(
                DVec3::new(1.0, 3.0, 0.5),
                DQuat::from_rotation_arc(DVec3::Y, to),
                [0.2; 3],
            );
            let z_long = glyph(
                DVec3::new(1.0, 0.5, 3.0),
                DQuat::from_rotation_arc(DVec3::Z, to),
                [0.2; 3],
            );
            for g in [y_long, z_long] {
                assert!(
                    close(principal_color(&g), to.abs().to_array(), 1e-6),
                    "{to}"
                );
            }
        }
        // Rotated 90 degrees about z, the long local x lies along world y: pure green.
        let turned = glyph(
            DVec3::new(2.0, 1.0, 1.0),
            DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
            [1.0; 3],
        );
        assert!(close(principal_color(&turned), [0.0, 1.0, 0.0], 1e-7));
    }

    #[test]
    fn ties_take_the_first_local_axis() {
        let rotation = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.7, 1.1);
        let axes = glam::DMat3::from_quat(rotation);
        let cases = [
            (DVec3::splat(1.0), axes.x_axis),
            (DVec3::new(2.0, 2.0, 1.0), axes.x_axis),
            (DVec3::new(2.0, 1.0, 2.0), axes.x_axis),
            (DVec3::new(1.0, 2.0, 2.0), axes.y_axis),
            (DVec3::new(1.0, 2.0, 1.0), axes.y_axis),
            (DVec3::new(1.0, 1.0, 2.0), axes.z_axis),
        ];
        for (radii, expected) in cases {
            let g = glyph(radii, rotation, [0.0; 3]);
            let d = principal_direction(&g);
            assert!(
                (d - expected).length() < 1e-12,
                "{radii}: {d} vs {expected}"
            );
            // The same glyph always gets the same colour.
            assert_eq!(principal_color(&g), principal_color(&g.clone()));
        }
    }

    #[test]
    fn fa_weighting_darkens_spheres_and_keeps_needles() {
        let rotation = DQuat::from_rotation_arc(DVec3::X, DVec3::new(0.0, 0.6, 0.8));
        let sphere = glyph(DVec3::splat(0.7), rotation, [1.0; 3]);
        assert_eq!(ColorMode::PrincipalFa.color(&sphere), [0.0; 3]);
        // Semi-axes (10, 1, 1): FA = 9 / sqrt(102).
        let needle = glyph(DVec3::new(10.0, 1.0, 1.0), rotation, [1.0; 3]);
        let fa = 9.0 / 102f64.sqrt();
        let color = ColorMode::PrincipalFa.color(&needle);
        assert!(close(color, [0.0, 0.6 * fa, 0.8 * fa], 1e-6), "{color:?}");
    }

    #[test]
    fn apply_recolours_every_glyph_and_file_keeps_them() {
        let rotation = DQuat::from_rotation_y(0.4);
        let original = vec![
            glyph(DVec3::new(4.0, 1.0, 1.0), rotation, [0.1, 0.2, 0.3]),
            glyph(DVec3::new(3.0, 3.0, 0.5), rotation, [0.9, 0.8, 0.7]),
            glyph(DVec3::splat(1.0), rotation, [0.5, 0.5, 0.5]),
        ];
        let mut glyphs = original.clone();
        ColorMode::File.apply(&mut glyphs);
        assert_eq!(glyphs, original);
        ColorMode::Uniform.apply(&mut glyphs);
        assert!(glyphs.iter().all(|g| g.color == UNIFORM_GREY));
        ColorMode::Shape.apply(&mut glyphs);
        assert_eq!(glyphs[0].color, shape_color(glyphs[0].radii));
        assert_eq!(glyphs[1].color, shape_color(glyphs[1].radii));
        assert_eq!(glyphs[2].color, [0.0, 0.0, 1.0]);
        ColorMode::Principal.apply(&mut glyphs);
        for (g, o) in glyphs.iter().zip(&original) {
            assert_eq!(g.color, principal_color(o));
            // Only the colour changes.
            assert_eq!(
                (g.center, g.radii, g.rotation),
                (o.center, o.radii, o.rotation)
            );
        }
    }

    #[test]
    fn modes_cycle_through_all_from_the_default() {
        let names = ColorMode::ALL.map(ColorMode::name);
        assert_eq!(
            names,
            ["file", "shape", "principal", "principal-fa", "uniform"]
        );
        let mut mode = ColorMode::default();
        assert_eq!(mode, ColorMode::File);
        let mut seen = Vec::new();
        for _ in 0..ColorMode::ALL.len() {
            seen.push(mode);
            mode = mode.next();
        }
        assert_eq!(seen, ColorMode::ALL);
        assert_eq!(mode, ColorMode::File);
    }
}
