#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The compute splat's resolve: one square per resolve tile (instance = tile, row-major), a
// strip of 4 vertices (the impostor pipelines' topology); a tile no splatted glyph marked
// collapses to a point and costs no fragment. The depth is replaced by the fragment stage's.
#include "ellipsoid_common.glsl"
#include "visibility.glsl"

void main() {
    uint tile = uint(gl_InstanceIndex);
    if (key_words(resolve_tile_word(tile)).x == empty_key_word()) {
        gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    // Corner of the square, in strip order.
    const uvec2 corners[4] = uvec2[](uvec2(0, 0), uvec2(1, 0), uvec2(0, 1), uvec2(1, 1));
    uvec2 size = image_size();
    uvec2 corner = uvec2(tile % resolve_tiles_x(), tile / resolve_tiles_x()) + corners[gl_VertexIndex];
    vec2 px = vec2(min(corner * RESOLVE_TILE, size));
    gl_Position = vec4(px * cam.ndc_per_pixel - 1.0, 0.0, 1.0);
}
