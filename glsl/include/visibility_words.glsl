// The layout of the compute splat's visibility buffer (binding 8; visibility.glsl says what it
// holds) as far as 32-bit words tell it, for shaders without 64-bit integers (the pre-pass's
// visible-first steps) and for the 64-bit accessors in visibility.glsl: a key's low word holds
// the instance (inverted under reversed Z), its high word the depth-buffer value's bits.

// The same buffer as its readers that never write it see it (binding 12, `VISIBILITY_KEYS` in
// src/renderer/descriptors.rs): a key per texel (R32G32_UINT), low word then high, through a
// uniform texel buffer (why: design §7). Only after a barrier: no pass both writes and reads
// it here.
layout(set = 0, binding = 12) uniform utextureBuffer visibility_keys;

// The words (low, high) of the key at `index` (64-bit keys from the buffer's start).
uvec2 key_words(uint index) {
    return texelFetch(visibility_keys, int(index)).xy;
}

// Side of a resolve tile in pixels (`RESOLVE_TILE` in src/gpu_layout.rs).
const uint RESOLVE_TILE = 32u;

// Either word of the key of a pixel no instance shows (the clear value).
uint empty_key_word() {
    return REVERSED_Z ? 0u : 0xffffffffu;
}

// The instance (scene index) of a key whose low word is `low` (the key not empty).
uint key_instance(uint low) {
    return REVERSED_Z ? ~low : low;
}

// Resolve tiles per row of the image.
uint resolve_tiles_x() {
    return (image_size().x + RESOLVE_TILE - 1u) / RESOLVE_TILE;
}

// Where tile `t` (row-major) keeps its word, in 64-bit keys from the buffer's start.
uint resolve_tile_word(uint t) {
    return image_size().x * image_size().y + t;
}
