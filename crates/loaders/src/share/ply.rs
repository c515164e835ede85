//! Binary 3D Gaussian Splatting PLY read in shares: every process reads the header, then its
//! range of the vertex records (records of one size: each process's bytes are found without
//! reading those before). A splat's index is its place among the kept splats of the whole
//! file (invalid ones skipped and faint ones left out count nowhere), so each process numbers
//! its own from the counts of the processes before it. Files of any other kind (ASCII, list
//! properties, a header not as expected) are read whole.

use std::path::Path;

use super::collective::{offset, sum, Collective};
use super::line_ranges::{share_of, TextFile};
use super::loaded_share::{indices, LoadedShare, Split};
use crate::options::LoadOptions;
use crate::ply::{vertex_records, Tally, VertexRecords};
use crate::Result;
use ellipsoid_splat::Scene;

/// Whether `head` holds a whole `end_header` line (as the PLY loader finds it).
fn holds_end_header(head: &[u8]) -> bool {
    let mut lines = head.split(|&b| b == b'\n');
    // The last piece has no `\n` after it: not a whole line.
    lines.next_back();
    lines.any(|line| {
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        let end = line
            .iter()
            .rposition(|&b| b != b' ' && b != b'\t')
            .map_or(0, |p| p + 1);
        &line[..end] == b"end_header"
    })
}

/// The vertex records of the PLY file `file`, when they can be read in ranges.
pub(crate) fn read_records(file: &TextFile, path: &Path) -> Result<Option<VertexRecords>> {
    let head = file.head(holds_end_header)?;
    Ok(vertex_records(&head, file.len(), path))
}

/// This process's share of the splats of `path`, whose vertex records are `records`.
pub(crate) fn load(
    file: &TextFile,
    records: &VertexRecords,
    path: &Path,
    options: &LoadOptions,
    c: Collective,
) -> Result<LoadedShare> {
    let (lo, hi) = share_of(0, records.count as u64, c.rank(), c.size());
    let stride = records.stride as u64;
    let read = file
        .read(records.offset + lo * stride, records.offset + hi * stride)
        .and_then(|bytes| records.read(&bytes, lo as usize, path, options));
    let ((ellipsoids, tally), all) = c.agree(read, |(_, t)| {
        vec![t.kept as u64, t.skipped as u64, t.transparent as u64]
    })?;
    let skipped = sum(&all, 1);
    let whole = Tally {
        kept: sum(&all, 0) as usize,
        skipped: skipped as usize,
        transparent: sum(&all, 2) as usize,
        first_skipped: if skipped > 0 {
            c.first_text(tally.first_skipped.as_deref())?
        } else {
            None
        },
    };
    let notes = records.summary(&whole, path, options)?;
    let total = whole.kept as u64;
    Ok(LoadedShare {
        indices: indices(offset(&all, 0, c.rank()), ellipsoids.len() as u64, total)?,
        scene: Scene::new(ellipsoids),
        total,
        skipped,
        notes,
        split: Split::Records,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_end_header_line_must_be_whole() {
        assert!(holds_end_header(b"ply\nend_header \r\n\x00\x01"));
        assert!(!holds_end_header(b"ply\nend_header"));
        assert!(!holds_end_header(b"ply\nend_headers\n"));
    }
}
