#version 460
#extension GL_GOOGLE_include_directive : require
// `flat-fill`: the same quads with no ray cast, no discard and no depth: the rasterizer's
// limit for that coverage.
#include "ellipsoid_common.glsl"
#include "fragment_counter.glsl"

// The impostor vertex stage's whole interface, declared so every output is consumed.
layout(location = 0) flat in vec3 v_ray_x;
layout(location = 10) flat in vec3 v_ray_y;
layout(location = 11) flat in vec3 v_ray_c;
layout(location = 12) flat in vec2 v_ray_origin;
layout(location = 1) flat in vec4 v_k;
layout(location = 2) flat in vec4 v_depth;
layout(location = 3) flat in vec4 v_misc;
layout(location = 4) flat in mat3 v_to_normal;
layout(location = 7) flat in uint v_id;
layout(location = 8) flat in uint v_flags;
layout(location = 9) flat in vec3 v_color;

layout(location = 0) out vec4 out_color;
#ifdef AUX_OUTPUTS
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
#endif

void main() {
    count_fragment();
    out_color = vec4(v_color, 1.0);
#ifdef AUX_OUTPUTS
    out_normal = vec4(0.0);
    out_id = v_id + cam.first_instance;
#endif
}
