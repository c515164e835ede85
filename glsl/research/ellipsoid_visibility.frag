#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
// `impostor-visbuffer`: the draw ray casts each fragment as the shipped impostor does, but
// instead of shading and exporting depth it keeps the pixel's nearest hit in the visibility
// buffer (the compute splat's keys) and marks the resolve tile; the resolve then shades each
// visible pixel once. Drawn in a pass of its own, with no attachments, before the host's.
#define VISIBILITY_WRITER
#include "ellipsoid_common.glsl"
#include "shading.glsl"
#include "fragment_counter.glsl"

layout(location = 7) flat in uint v_id;
#include "impostor_state.glsl"
#include "impostor_hit.glsl"
#include "visibility.glsl"

void main() {
    count_fragment();
    load_setup();
    float z;
    vec3 normal;
    bool cap;
    vec2 pixel = camera_pixel(gl_FragCoord.xy);
    if (!impostor_depth(pixel, z, normal, cap)) {
        return;
    }
    uvec2 p = uvec2(pixel);
    uint64_t key = visibility_key(z, v_id + cam.first_instance);
    if (REVERSED_Z) {
        atomicMax(visibility[p.y * image_size().x + p.x], key);
    } else {
        atomicMin(visibility[p.y * image_size().x + p.x], key);
    }
    // Most fragments find their tile marked: a read spares them the atomic (a read racing
    // with an exchange only ever costs one more atomic, as in splat.comp).
    uint tile = resolve_tile_word((p.y / RESOLVE_TILE) * resolve_tiles_x() + p.x / RESOLVE_TILE);
    if (visibility[tile] != ~visibility_empty()) {
        atomicExchange(visibility[tile], ~visibility_empty());
    }
}
