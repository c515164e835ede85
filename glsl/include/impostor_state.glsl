// The impostor's set-up as the hit test reads it, three ways:
// - SETUP_ONCE: globals loaded from the record the pre-pass wrote for instance v_id (the
//   includer declares v_id);
// - SETUP_HERE: globals the includer fills from a Setup it computes itself with use_setup
//   (the compute splat and its resolve, which need instance_setup.glsl first);
// - otherwise: the flat varyings of the vertex stage (include/instance_setup.glsl).
#if defined(SETUP_HERE) || defined(SETUP_ONCE)
vec3 v_ray_x, v_ray_y, v_ray_c;
vec2 v_ray_origin;
vec4 v_k, v_depth, v_misc;
mat3 v_to_normal;
uint v_flags;
vec3 v_color;
#endif

#if defined(SETUP_HERE)
// Takes the set-up `s` as the vertex stage hands it down.
void use_setup(Setup s) {
    HAND_DOWN_SETUP(s);
}

void load_setup() {}
void load_shading() {}
#elif defined(SETUP_ONCE)
#define SETUP_ONCE_FRAGMENT
#include "setup_records.glsl"

// What the hit test needs (see store_setup for the layout and the derived values).
void load_setup() {
    float r = shading[v_id].radius, u = shading[v_id].inv_eye_dist;
    float cz = shading[v_id].centre_depth, eye_dist = 0.0;
    v_ray_x = shading[v_id].ray_x;
    v_ray_y = shading[v_id].ray_y;
    v_flags = shading[v_id].flags;
    bool origin = (v_flags & FLAG_OFFSET_ORIGIN) != 0u;
    v_ray_origin = shading[v_id].ray_origin;
    v_ray_c = vec3(0.0);
    if (!origin) {
        v_ray_c = shading[v_id].ray_c;
        eye_dist = shading[v_id].eye_dist;
    }
    v_k = ORTHOGRAPHIC ? vec4(1.0, 1.0, 0.0, 1.0)
        : (origin ? vec4(1.0, r * cz, cz * u, r) : vec4(0.0, r, u, r));
    // Only orthographic depth reads g.
    v_depth = vec4(ORTHOGRAPHIC ? shading[v_id].depth_gradient : vec3(0.0), cz);
    float depth_scale = origin && !ORTHOGRAPHIC ? cz : 1.0;
    v_misc = vec4(u, eye_dist, r * r, depth_scale);
}

// What shading a hit needs: loaded only for fragments that hit.
void load_shading() {
    v_to_normal = mat3(shading[v_id].to_normal_x, shading[v_id].to_normal_y,
                       shading[v_id].to_normal_z);
    v_color = vec3(shading[v_id].color_r, shading[v_id].color_g, shading[v_id].color_b);
}
#else
layout(location = 0) flat in vec3 v_ray_x;
layout(location = 10) flat in vec3 v_ray_y;
layout(location = 11) flat in vec3 v_ray_c;
layout(location = 12) flat in vec2 v_ray_origin;
layout(location = 1) flat in vec4 v_k;
layout(location = 2) flat in vec4 v_depth;
layout(location = 3) flat in vec4 v_misc;
layout(location = 4) flat in mat3 v_to_normal;
layout(location = 8) flat in uint v_flags;
layout(location = 9) flat in vec3 v_color;

void load_setup() {}
void load_shading() {}
#endif

