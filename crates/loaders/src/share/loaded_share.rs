//! What reading a share returns ([`LoadedShare`]): this process's glyphs with their places in
//! the whole scene, and the whole load's report; and the share of a scene every process holds
//! whole (formats not split, generated scenes).

use ellipsoid_splat::Scene;

use super::line_ranges::share_of;
use crate::loaded::Loaded;
use crate::{Error, Result};

/// How the processes divided a file between them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// Text: each read the lines that start in its byte range of the data.
    Lines,
    /// Binary records: each read its range of them.
    Records,
    /// Each read the whole file (or made the whole scene) and kept its range of the glyphs:
    /// formats whose records cannot be found without reading what comes before them
    /// (gzip, NIfTI, PDB and mmCIF, ASCII PLY).
    Whole,
}

/// One process's share of a scene read by several ([`load_share`](crate::load_share)).
#[derive(Clone, Debug)]
pub struct LoadedShare {
    /// This process's glyphs, in increasing global index.
    pub scene: Scene,
    /// The global index of each glyph: its index in the scene one process loading the whole
    /// file gets ([`load()`](crate::load())), colours included.
    pub indices: Vec<u32>,
    /// The glyphs of every share together.
    pub total: u64,
    /// Records dropped as invalid, every share together (only with `skip_invalid`).
    pub skipped: u64,
    /// Lines for the user about the whole load, the same on every process.
    pub notes: Vec<String>,
    /// How the file was divided.
    pub split: Split,
}

impl LoadedShare {
    /// Share `rank` of `size` of a scene every process holds whole: its range of the glyphs
    /// (near-equal ranges, in order).
    pub fn of_whole(loaded: Loaded, rank: usize, size: usize) -> Result<Self> {
        let total = loaded.scene.len() as u64;
        let (lo, hi) = share_of(0, total, rank, size);
        let mut glyphs = loaded.scene.ellipsoids;
        glyphs.truncate(hi as usize);
        glyphs.drain(..lo as usize);
        Ok(Self {
            scene: Scene::new(glyphs),
            indices: indices(lo, hi - lo, total)?,
            total,
            skipped: loaded.skipped as u64,
            notes: loaded.notes,
            split: Split::Whole,
        })
    }
}

/// The global indices `first`, `first + 1`, ... of `count` glyphs of a scene of `total`; an
/// error when `total` is more than instance indices reach (the same on every process:
/// [`check_total`]).
pub(crate) fn indices(first: u64, count: u64, total: u64) -> Result<Vec<u32>> {
    check_total(total)?;
    Ok((first..first + count).map(|i| i as u32).collect())
}

/// The index marking no glyph (the renderer's `NO_INSTANCE`, the ID images' background): glyph
/// indices stay below it.
const NO_INSTANCE: u32 = u32::MAX;

/// An error when a scene of `total` glyphs has more than instance indices reach.
pub(crate) fn check_total(total: u64) -> Result<()> {
    if total > u64::from(NO_INSTANCE) {
        return Err(Error::invalid(
            "scene",
            format!(
                "{total} glyphs: more than the {NO_INSTANCE} a scene can index (u32 instance \
                 indices, 0xFFFFFFFF marking the background)"
            ),
        ));
    }
    Ok(())
}
