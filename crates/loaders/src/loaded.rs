//! What a loader returns: the scene, and what it has to say about it ([`Loaded`],
//! [`Origins`]).

use ellipsoid_splat::Scene;

/// A loaded scene and what the loader has to say about it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Loaded {
    /// The ellipsoids.
    pub scene: Scene,
    /// Records dropped as invalid (only with `skip_invalid`).
    pub skipped: usize,
    /// Lines for the user: parameters in effect, records filtered out and why.
    pub notes: Vec<String>,
    /// Where each glyph came from in the file (a viewer's pick reports it).
    pub origins: Origins,
}

/// Where each glyph of a loaded file came from, one entry per glyph in scene order (a few
/// bytes each: kept for every glyph so that a pick can name its record).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Origins {
    /// Not recorded (generated scenes: the index says it all).
    #[default]
    None,
    /// The 1-based line of each glyph's row (Ellipsoid CSV).
    Lines(Vec<u32>),
    /// The 0-based vertex index of each splat (3D Gaussian Splatting PLY); described 1-based,
    /// as the PLY loader's errors number vertices.
    Vertices(Vec<u32>),
    /// The voxel `(i, j, k)` of each glyph (NIfTI tensor volumes).
    Voxels(Vec<[u16; 3]>),
    /// The line and label (`atom 5 CA (ALA A 1)`) of each atom (PDB, mmCIF).
    Atoms(Vec<(u32, String)>),
    /// The 1-based line and the atom id of each particle (LAMMPS dumps, extended XYZ); where
    /// the file has no `id` column, the id is the particle's 1-based place in its frame.
    Particles(Vec<(u32, i64)>),
}

impl Origins {
    /// What glyph `index` came from, in words, if recorded.
    pub fn describe(&self, index: usize) -> Option<String> {
        match self {
            Origins::None => None,
            Origins::Lines(lines) => lines.get(index).map(|l| format!("line {l}")),
            // 1-based like the loader's "vertex N" errors; u64 so u32::MAX cannot overflow.
            Origins::Vertices(v) => v
                .get(index)
                .map(|&v| format!("splat (vertex) {}", u64::from(v) + 1)),
            Origins::Voxels(v) => v
                .get(index)
                .map(|[i, j, k]| format!("voxel (i, j, k) = ({i}, {j}, {k})")),
            Origins::Atoms(a) => a
                .get(index)
                .map(|(line, label)| format!("{label}, line {line}")),
            Origins::Particles(p) => p
                .get(index)
                .map(|(line, id)| format!("atom id {id}, line {line}")),
        }
    }
}
