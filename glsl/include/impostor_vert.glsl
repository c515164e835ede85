// Expands instance gl_InstanceIndex into a polygon on screen that contains the projected
// silhouette, and hands the fragment stage the instance's set-up (include/instance_setup.glsl).
//
// Two builds: this one computes the set-up in every vertex and passes it down as flat
// varyings; ellipsoid_setup_once.vert (SETUP_ONCE) reads the set-up the culling pre-pass
// computed once per instance and passes down only the instance index, for the fragment stage
// to read the rest (lavapipe's per-vertex cost grows with every varying).
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#ifdef SETUP_ONCE
#define SETUP_ONCE_VERTEX
#endif
#include "setup_records.glsl"

layout(location = 7) flat out uint v_id;
#ifndef SETUP_ONCE
layout(location = 0) flat out vec3 v_ray_x;
layout(location = 10) flat out vec3 v_ray_y;
layout(location = 11) flat out vec3 v_ray_c;
layout(location = 12) flat out vec2 v_ray_origin;
layout(location = 1) flat out vec4 v_k;
layout(location = 2) flat out vec4 v_depth;
layout(location = 3) flat out vec4 v_misc;
layout(location = 4) flat out mat3 v_to_normal;
layout(location = 8) flat out uint v_flags;
layout(location = 9) flat out vec3 v_color;
#endif

void main() {
    uint id = CULLED ? visible_instances[gl_InstanceIndex] : uint(gl_InstanceIndex);
    v_id = id;
#ifdef SETUP_ONCE
    gl_Position = corner_position(load_footprint(id), gl_VertexIndex);
#else
    Setup s = setup_instance(load_instance(id));
    gl_Position = corner_position(s, gl_VertexIndex);
    HAND_DOWN_SETUP(s);
#endif
}
