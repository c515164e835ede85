// The impostor's set-up as the hit test reads it, three ways:
// - SETUP_ONCE: globals loaded from the record the pre-pass wrote for instance v_id (the
//   includer declares v_id);
// - SETUP_HERE: globals the includer fills from a Setup it computes itself with use_setup
//   (the compute splat and its resolve, which need instance_setup.glsl first), or with
//   use_record_setup and use_record_shading from a record the splat stored (the resolve);
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

void load_setup() {
    use_record_setup(shading[v_id]);
}

// What shading a hit needs: loaded only for fragments that hit.
void load_shading() {
    use_record_shading(shading[v_id]);
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

