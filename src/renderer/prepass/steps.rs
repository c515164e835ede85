//! The pre-pass's steps (`CULL_STEP` and `CULL_SELECT` of `glsl/cull.comp`), their
//! workgroup counts and the sizes of the buffers they fill.

use crate::culling::Culling;
use crate::gpu_layout::RESOLVE_TILE;

/// One dispatch of the pre-pass (`CULL_STEP` in the shader).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum CullStep {
    /// Lower the occlusion tiles each ellipsoid's inscribed sphere covers.
    Occluders = 0,
    /// Keep bits and a count per group of instances.
    Classify = 1,
    /// Counts to first output slots, and the draw's instance count.
    Scan = 2,
    /// Kept instance indices to their slots.
    Scatter = 3,
    /// The visible-first splat: each occlusion tile takes the farthest depth the first
    /// pass left over its pixels.
    KeyTiles = 4,
    /// The visible-first splat: the glyphs the finished frame shows are stamped.
    MarkShown = 5,
}

/// Which glyphs the CLASSIFY step lists (`CULL_SELECT`), and so which list a visible-first
/// splat pass walks (`SplatKey::list`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub(crate) enum CullSelect {
    /// Every glyph the culling keeps.
    #[default]
    All = 0,
    /// The glyphs the last stamping frame showed: the visible-first splat's first pass.
    Shown = 1,
    /// The others the culling keeps, where the first pass's hits do not hide them: its
    /// second pass.
    Rest = 2,
    /// Those a splat pass of this frame left to the draw.
    Drawn = 3,
}

impl CullSelect {
    /// Whether CLASSIFY picks by a stamp alone (`CLASSIFY_STAMPS` in `cull.comp`): then one
    /// invocation per keep word, as SCATTER.
    pub(crate) fn by_stamp(self) -> bool {
        matches!(self, CullSelect::Shown | CullSelect::Drawn)
    }
}

/// The benchmark's tiled splat's steps (`CULL_STEP` of `glsl/research/tiled_bins.comp`, then
/// `glsl/research/tiled_splat.comp`), in the order they run in place of the compute splat.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum TiledStep {
    /// Per glyph: set-up, pixel box and nearest depth; the frame's range of depths.
    Range = 0,
    /// Per glyph: its depth bucket, and a count per (tile, bucket) its box touches.
    Count = 1,
    /// One workgroup: the counts to first slots.
    Scan = 2,
    /// Per glyph: its index into each touched tile's list.
    Scatter = 3,
    /// One workgroup per tile: its glyphs ray cast, its keys written once.
    Tiles = 4,
}

impl TiledStep {
    /// Every step, in order.
    pub const ALL: [TiledStep; 5] = [
        TiledStep::Range,
        TiledStep::Count,
        TiledStep::Scan,
        TiledStep::Scatter,
        TiledStep::Tiles,
    ];
}

/// The tiled splat's tile edge in pixels (`TILE` in `glsl/research/tile_lists.glsl`).
pub(crate) const TILED_TILE: u32 = 8;
/// The tiled splat's depth buckets per tile (`BUCKETS`).
const TILED_BUCKETS: u64 = 8;
/// Words of the tiled splat's header (`HEADER`).
pub(crate) const TILED_HEADER_WORDS: u64 = 4;
/// Words of a glyph's record in the tiled splat's lists (`RECORD`).
const TILED_RECORD_WORDS: u64 = 28;
/// Room in the tiled splat's lists, in entries per glyph: the most tiles a glyph's box may
/// touch for the lists to take it (`MAX_GLYPH_TILES`; larger glyphs are drawn), so no entry is
/// ever dropped.
const TILED_ENTRIES_PER_GLYPH: u64 = 64;

/// The tiled splat's tiles across and down a `width` x `height` image.
pub(crate) fn tiled_grid(width: u32, height: u32) -> (u32, u32) {
    (width.div_ceil(TILED_TILE), height.div_ceil(TILED_TILE))
}

/// The tiled splat's (tile, bucket) cells of a `width` x `height` image.
pub(crate) fn tiled_cells(width: u32, height: u32) -> u64 {
    let (x, y) = tiled_grid(width, height);
    x as u64 * y as u64 * TILED_BUCKETS
}

/// Bytes of the tiled splat's lists for `count` glyphs on a `width` x `height` image: the
/// header, a count and a first slot per cell (and one past the last), 4 words per glyph and
/// the entries.
pub(crate) fn tiled_lists_bytes(width: u32, height: u32, count: u32) -> u64 {
    let count = count.max(1) as u64;
    let words = TILED_HEADER_WORDS
        + 2 * tiled_cells(width, height)
        + 4
        + TILED_RECORD_WORDS * count
        + TILED_ENTRIES_PER_GLYPH * count;
    4 * words
}

/// Instances per workgroup (`local_size_x` of `cull.comp`).
pub(crate) const GROUP_SIZE: u64 = 256;
/// Instances per workgroup of the compute splat (`local_size_x` of `splat.comp`).
pub(crate) const SPLAT_GROUP_SIZE: u32 = 64;
/// Occlusion tile edge in pixels (`TILE`).
const TILE: u64 = 4;
/// Most workgroups in one dimension of a dispatch that every device supports.
const MAX_GROUPS_X: u32 = 65_535;

/// Workgroups over `count` instances.
pub(crate) fn group_count(count: u32) -> u32 {
    (count as u64).div_ceil(GROUP_SIZE) as u32
}

/// Workgroups over the keep words of `count` instances (8 per group of 256): SCATTER, and
/// CLASSIFY by a stamp, take one invocation per word, since on lavapipe an invocation costs
/// about as much as a few reads.
pub(crate) fn word_groups(count: u32) -> u32 {
    (group_count(count) as u64 * 8).div_ceil(GROUP_SIZE) as u32
}

/// Bytes of the groups buffer: 8 words of keep bits and one count per group.
pub(crate) fn groups_bytes(count: u32) -> u64 {
    4 * 9 * group_count(count).max(1) as u64
}

/// Occlusion tiles of a `width` x `height` image.
fn tiles_count(width: u32, height: u32) -> u32 {
    (width as u64).div_ceil(TILE) as u32 * (height as u64).div_ceil(TILE) as u32
}

/// Bytes of the occlusion tiles of a `width` x `height` image.
pub(crate) fn tiles_bytes(width: u32, height: u32) -> u64 {
    4 * tiles_count(width, height) as u64
}

/// Strips of a resolve tile (`STRIPS` in `cull.comp`): rows of occlusion tiles across it.
const STRIPS: u64 = RESOLVE_TILE as u64 / TILE;

/// Workgroups of KEY_TILES and MARK_SHOWN over `resolve_tiles` resolve tiles: an invocation
/// per strip (a lavapipe invocation costs about as much as a few reads, so not one per
/// occlusion tile or pixel).
pub(crate) fn strip_groups(resolve_tiles: u32) -> u32 {
    (resolve_tiles as u64 * STRIPS).div_ceil(GROUP_SIZE) as u32
}

/// The dispatch grid for `groups` workgroups: x up to the guaranteed limit, then rows.
pub(crate) fn dispatch_grid(groups: u32) -> (u32, u32) {
    let x = groups.clamp(1, MAX_GROUPS_X);
    (x, groups.div_ceil(x).max(1))
}

/// The steps after the compute splat: it writes the keep bits and counts of the glyphs it
/// leaves to the draw, and these compact them in instance order.
pub(crate) const SPLAT_STEPS: [CullStep; 2] = [CullStep::Scan, CullStep::Scatter];

/// The steps a culling frame runs, in order.
pub(crate) fn steps(culling: Culling) -> Vec<CullStep> {
    let mut steps = Vec::with_capacity(4);
    if culling.occlusion {
        steps.push(CullStep::Occluders);
    }
    steps.extend([CullStep::Classify, CullStep::Scan, CullStep::Scatter]);
    steps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_cover_every_instance_and_pixel() {
        assert_eq!(group_count(0), 0);
        assert_eq!(group_count(256), 1);
        assert_eq!(group_count(257), 2);
        assert_eq!(groups_bytes(0), 36);
        assert_eq!(groups_bytes(1_000_000), 4 * 9 * 3907);
        assert_eq!(word_groups(0), 0);
        assert_eq!(word_groups(64_000), 8); // 250 groups, 2,000 words
        assert_eq!(word_groups(1_000_000), 123); // 3,907 groups, 31,256 words
        assert_eq!(tiles_bytes(1920, 1080), 4 * 480 * 270);
        assert_eq!(tiles_bytes(161, 121), 4 * 41 * 31);
        // 60 x 34 resolve tiles at 1920 x 1080, 8 strips each: 16,320 invocations.
        assert_eq!(strip_groups(2040), 64);
        assert_eq!(strip_groups(32), 1);
        assert_eq!(strip_groups(33), 2);
        assert_eq!(strip_groups(1), 1);
    }

    #[test]
    fn dispatch_grid_covers_all_groups() {
        assert_eq!(dispatch_grid(0), (1, 1));
        assert_eq!(dispatch_grid(3907), (3907, 1));
        let (x, y) = dispatch_grid(200_000);
        assert!(x <= MAX_GROUPS_X && x as u64 * y as u64 >= 200_000);
    }
}
