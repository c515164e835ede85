//! What a click reports: the glyph under the cursor (read from the renderer's ID output), its
//! centre, semi-axes and colour, and what it came from: the lattice cell or cloud index of a
//! generated scene (the particle index of the liquid), and for a file the record the loader kept for it (`Origins`: CSV line,
//! PLY vertex, NIfTI voxel, PDB/mmCIF atom with its name and residue).

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat_loaders::Origins;

use crate::cli::SceneSpec;

/// The colour a picked glyph is drawn in until the next pick (sRGB), a magenta no built-in
/// colouring uses.
pub const HIGHLIGHT: [f32; 3] = [1.0, 0.1, 0.9];

/// Where glyph `index` of the scene named by `spec` came from; `origins` is what its loader
/// recorded.
pub fn source(spec: &SceneSpec, index: u32, origins: &Origins) -> String {
    match spec {
        SceneSpec::TensorField(n) | SceneSpec::Lattice(n) => {
            let n = *n as u32;
            let (i, j, k) = (index % n, index / n % n, index / (n * n));
            let name = match spec {
                SceneSpec::TensorField(_) => "tensor-field lattice",
                _ => "lattice",
            };
            format!("{name} cell (i, j, k) = ({i}, {j}, {k})")
        }
        SceneSpec::Random(_) => format!("random cloud glyph {index}"),
        SceneSpec::MdLiquid(_) => format!("md-liquid particle {index}"),
        SceneSpec::File(path) => match origins.describe(index as usize) {
            Some(record) => format!("{record} of {}", path.display()),
            None => format!("glyph {index} of {}", path.display()),
        },
    }
}

/// The lines a pick prints.
pub fn report(index: u32, count: usize, glyph: &Ellipsoid, source: &str) -> String {
    let c = glyph.center;
    let r = glyph.radii;
    let [red, green, blue] = glyph.color;
    format!(
        "glyph {index} of {count}: centre ({:.6}, {:.6}, {:.6}), semi-axes ({:.6}, {:.6}, \
         {:.6}), colour (sRGB) ({red:.3}, {green:.3}, {blue:.3}); from {source}",
        c.x, c.y, c.z, r.x, r.y, r.z
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sources_name_what_is_known() {
        let none = Origins::None;
        let field = source(&SceneSpec::TensorField(4), 4 * 4 + 4 + 1, &none);
        assert!(field.ends_with("(1, 1, 1)"), "{field}");
        let lattice = source(&SceneSpec::Lattice(4), 4 * 4 * 2 + 3, &none);
        assert_eq!(lattice, "lattice cell (i, j, k) = (3, 0, 2)");
        let csv = source(
            &SceneSpec::File("a.csv".into()),
            1,
            &Origins::Lines(vec![3, 7]),
        );
        assert_eq!(csv, "line 7 of a.csv");
        let ply = source(
            &SceneSpec::File("a.ply".into()),
            0,
            &Origins::Vertices(vec![12]),
        );
        // Numbered from 1, as the PLY loader's errors number vertices.
        assert_eq!(ply, "splat (vertex) 13 of a.ply");
        let atoms = Origins::Atoms(vec![(40, "atom 5 CA (ALA A 1)".into())]);
        let pdb = source(&SceneSpec::File("a.pdb".into()), 0, &atoms);
        assert_eq!(pdb, "atom 5 CA (ALA A 1), line 40 of a.pdb");
        let voxel = source(
            &SceneSpec::File("a.nii".into()),
            0,
            &Origins::Voxels(vec![[1, 2, 3]]),
        );
        assert_eq!(voxel, "voxel (i, j, k) = (1, 2, 3) of a.nii");
    }
}
