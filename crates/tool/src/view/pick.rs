//! What a click reports: the glyph under the cursor (read from the renderer's ID output), its
//! centre, semi-axes and colour, and what it came from as far as the loaders tell. The
//! loaders return ellipsoids only, so the source is exact for generated scenes and for files
//! whose every record became a glyph, and otherwise says what is missing.

use std::path::Path;

use ellipsoid_splat::Ellipsoid;
use ellipsoid_splat_loaders::load::{detect_format, Format};

use crate::cli::SceneSpec;

/// The colour a picked glyph is drawn in until the next pick (sRGB), a magenta no built-in
/// colouring uses.
pub const HIGHLIGHT: [f32; 3] = [1.0, 0.1, 0.9];

/// Where glyph `index` of `count` came from, for a scene named by `spec` loaded with
/// nothing filtered out (`filtered` says whether records were dropped or filtered).
pub fn source(spec: &SceneSpec, index: u32, filtered: bool) -> String {
    match spec {
        SceneSpec::TensorField(n) => {
            let n = *n as u32;
            let (i, j, k) = (index % n, index / n % n, index / (n * n));
            format!("tensor-field lattice cell (i, j, k) = ({i}, {j}, {k})")
        }
        SceneSpec::Random(_) => format!("random cloud glyph {index}"),
        SceneSpec::File(path) => file_source(path, index, filtered),
    }
}

fn file_source(path: &Path, index: u32, filtered: bool) -> String {
    let name = path.display();
    let caveat = if filtered {
        " -- but records were filtered or skipped on loading, and the loader keeps no \
         source index, so the record is unknown"
    } else {
        ""
    };
    match detect_format(path) {
        Ok(Format::Csv) => format!(
            "data row {} of {name} (the loader keeps no line numbers: comment and blank lines \
             are not counted){caveat}",
            index + 1
        ),
        Ok(Format::GaussianPly) => format!("splat (vertex) {index} of {name}{caveat}"),
        Ok(Format::Nifti) => format!(
            "a voxel of {name}: the loader keeps no voxel index (voxels outside the mask, \
             with FA below --min-fa or not positive definite are left out)"
        ),
        Ok(Format::Pdb | Format::MmCif) => format!(
            "atom record {index} with anisotropic displacements in {name}: the loader keeps no \
             atom name or residue{caveat}"
        ),
        Err(_) => format!("glyph {index} of {name}"),
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
        let field = source(&SceneSpec::TensorField(4), 4 * 4 + 4 + 1, false);
        assert!(field.ends_with("(1, 1, 1)"), "{field}");
        let csv = source(&SceneSpec::File("a.csv".into()), 2, false);
        assert!(csv.starts_with("data row 3 of a.csv"), "{csv}");
        let ply = source(&SceneSpec::File("a.ply".into()), 7, true);
        assert!(
            ply.contains("splat (vertex) 7") && ply.contains("unknown"),
            "{ply}"
        );
    }
}
