// Occlusion tiles of the culling pre-pass (cull.comp), which the visible-first splat's second
// pass also reads (splat.comp). Needs ellipsoid_common.glsl first.
//
// Tiles of TILE x TILE pixels, row-major from the top left. For the culled draw each holds the
// float bits of a view depth such that every pixel centre (multisampled: every sample) of the
// tile shows a surface at or before it (+inf: none known); positive floats order like their
// bits, so atomicMin works on them. Under the visible-first splat each holds instead the
// farthest depth-buffer value's bits at its pixels (KEY_TILES), or the empty key's word: none
// known.

layout(std430, set = 0, binding = 5) buffer OcclusionTiles {
    uint tiles[];
};

// The same words as the visible-first splat's second CLASSIFY and second splat pass read
// them (binding 13, `OCCLUSION_TILE_WORDS` in src/renderer/descriptors.rs, which says why
// only there): a texel each (why texel reads: design §7). Only after a barrier: no pass both
// writes and reads them here.
layout(set = 0, binding = 13) uniform utextureBuffer occlusion_tile_words;

// The word of tile `t` (row-major), through the texel view.
uint tile_word(int t) {
    return texelFetch(occlusion_tile_words, t).x;
}

const int TILE = 4;

ivec2 tile_grid() {
    return (ivec2(image_size()) + TILE - 1) / TILE;
}
