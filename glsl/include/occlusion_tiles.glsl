// Occlusion tiles of the culling pre-pass (cull.comp). Needs ellipsoid_common.glsl first.
//
// Tiles of TILE x TILE pixels, row-major from the top left, each holding the float bits of a
// view depth such that every pixel centre (multisampled: every sample) of the tile shows a
// surface at or before it (+inf: none known). Positive floats order like their bits, so
// atomicMin works on them.

layout(std430, set = 0, binding = 5) buffer OcclusionTiles {
    uint tiles[];
};

const int TILE = 4;

ivec2 tile_grid() {
    return (ivec2(image_size()) + TILE - 1) / TILE;
}
