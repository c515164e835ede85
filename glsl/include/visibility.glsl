// The compute splat's visibility buffer (binding 8, `visibility_bytes` in src/gpu_layout.rs;
// also written by the benchmark's research/ellipsoid_visibility.frag, VISIBILITY_WRITER):
// per pixel, row-major, the nearest hit as one 64-bit key, the depth-buffer value's bits above
// the instance's; then per RESOLVE_TILE-pixel square tile, row-major, a word that is empty
// until a glyph with a hit in the tile marks it (the resolve draws marked tiles only). Depth values in [0, 1]
// order like their bits, so the nearest hit has the largest key under reversed Z (atomicMax
// from 0) and the smallest under standard Z (atomicMin from all ones). The instance bits are
// inverted under reversed Z, so of two equal depths the lower instance wins, as in the draw
// (its depth test passes only strictly nearer fragments, and instances are drawn in order).
// Needs GL_EXT_shader_explicit_arithmetic_types_int64 (and, where written,
// GL_EXT_shader_atomic_int64) enabled by the includer.

#include "visibility_words.glsl"

#if defined(SPLAT_PASS) || defined(VISIBILITY_WRITER)
#define VISIBILITY_ACCESS
#else
#define VISIBILITY_ACCESS readonly
#endif
layout(std430, set = 0, binding = 8) VISIBILITY_ACCESS buffer Visibility {
    uint64_t visibility[];
};

// The key of a pixel no instance shows (the clear value).
uint64_t visibility_empty() {
    return REVERSED_Z ? 0ul : ~0ul;
}

// The key of a hit of instance `id` (scene index) at depth-buffer value `z`.
uint64_t visibility_key(float z, uint id) {
    return (uint64_t(floatBitsToUint(z)) << 32) | uint64_t(REVERSED_Z ? ~id : id);
}

// The instance (scene index) of a key that is not empty.
uint visibility_id(uint64_t key) {
    return key_instance(uint(key));
}
