// The benchmark's tiled splat's lists (binding 11, `TileLists`; `tiled_lists_bytes` in
// src/renderer/prepass/steps.rs), shared by its binning steps (research/tiled_bins.comp) and
// its tile pass (research/tiled_splat.comp): a header (the glyphs' nearest and farthest
// nearest-depth bits, the entries, the entries dropped for want of room), per (tile, bucket)
// a count (the SCAN's cursor after), per (tile, bucket) and one past the last the first slot,
// per glyph a record of RECORD words from a multiple of 4 (box lo and hi as x | y << 16,
// nearest depth bits, bucket or NOT_BINNED; then the hit part of its set-up, computed once,
// as 6 vec4: ray_x and ray_origin.x, ray_y and ray_origin.y, ray_c and flags, k, depth, misc),
// then the entries: each tile's glyphs, nearest depth bucket first. Needs
// ellipsoid_common.glsl and the IndirectDraw block (`total`) first.

// A tile is TILE x TILE pixels; `TILED_TILE` in src/renderer/prepass/steps.rs mirrors it.
const uint TILE = 8u;
// Depth buckets per tile (`TILED_BUCKETS`).
const uint BUCKETS = 8u;
// The most tiles a glyph's box may touch for the lists to take it (larger glyphs are drawn):
// the lists have room for this many entries per glyph (`TILED_ENTRIES_PER_GLYPH`), so none is
// ever dropped.
const uint MAX_GLYPH_TILES = 64u;

layout(std430, set = 0, binding = 11) buffer TileLists {
    uint lists[];
};
#ifndef TILE_LISTS4_ACCESS
#define TILE_LISTS4_ACCESS readonly
#endif
// The same binding read 16 bytes at a time (the records' set-ups).
layout(std430, set = 0, binding = 11) TILE_LISTS4_ACCESS buffer TileLists4 {
    uvec4 lists4[];
};
const uint RECORD = 28u;
const uint HEADER = 4u;
const uint NOT_BINNED = 0xffffffffu;

uvec2 tile_grid() {
    return (image_size() + TILE - 1u) / TILE;
}
uint cells() {
    uvec2 g = tile_grid();
    return g.x * g.y * BUCKETS;
}
uint starts_at() {
    return HEADER + cells();
}
uint record_at(uint k) {
    return (starts_at() + cells() + 4u) / 4u * 4u + RECORD * k;
}
uint entries_at() {
    return record_at(total);
}
// Entries the lists have room for.
uint entry_room() {
    return uint(lists.length()) - entries_at();
}

uint pack_px(ivec2 p) {
    return uint(p.x) | uint(p.y) << 16;
}
ivec2 unpack_px(uint w) {
    return ivec2(w & 0xffffu, w >> 16);
}
