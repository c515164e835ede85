#version 460
#extension GL_GOOGLE_include_directive : require
// `box-proxy`: the ellipsoid's oriented bounding box as 12 triangles, ray-cast inside by the
// impostor fragment stage in its textbook mode (what SIBR, MegaMol and OVITO draw).
// Front faces only: the ray's hit lies behind them, so `depth_less` holds. Perspective only.
#include "ellipsoid_common.glsl"

layout(location = 0) flat out vec3 v_ray_x;
layout(location = 10) flat out vec3 v_ray_y;
layout(location = 11) flat out vec3 v_ray_c;
layout(location = 12) flat out vec2 v_ray_origin;
layout(location = 1) flat out vec4 v_k;
layout(location = 2) flat out vec4 v_depth;
layout(location = 3) flat out vec4 v_misc;
layout(location = 4) flat out mat3 v_to_normal;
layout(location = 7) flat out uint v_id;
layout(location = 8) flat out uint v_flags;
layout(location = 9) flat out vec3 v_color;

// Corner of the unit cube for vertex `index` of 36: face = index / 6 (axis, sign), two
// triangles wound counter-clockwise seen from outside.
vec3 cube_corner(int index) {
    int face = index / 6;
    int axis = face >> 1;
    float s = (face & 1) == 0 ? 1.0 : -1.0;
    const int ccw[6] = int[6](0, 1, 2, 0, 2, 3);
    const int cw[6] = int[6](0, 2, 1, 0, 3, 2);
    int k = s > 0.0 ? ccw[index % 6] : cw[index % 6];
    vec2 square[4] = vec2[4](vec2(-1.0, -1.0), vec2(1.0, -1.0), vec2(1.0, 1.0), vec2(-1.0, 1.0));
    vec3 p;
    p[axis] = s;
    p[(axis + 1) % 3] = square[k].x;
    p[(axis + 2) % 3] = square[k].y;
    return p;
}

void main() {
    Instance inst = load_instance(uint(gl_InstanceIndex));
    mat3 R = quat_to_mat3(inst.rotation);
    vec3 radii = inst.radii.xyz;
    vec3 r = cam.right, u = cam.up, f = cam.forward;
    vec3 world = inst.center + R * (radii * cube_corner(gl_VertexIndex));
    vec3 v = vec3(dot(world, r), dot(world, u), dot(world, f)) - cam.eye_view;
    vec3 c = vec3(dot(inst.center, r), dot(inst.center, u), dot(inst.center, f)) - cam.eye_view;

    // The textbook fragment path reads the centre relative to the eye (world axes) and M.
    v_depth = vec4(c.x * r + c.y * u + c.z * f, c.z);
    v_to_normal = transpose(mat3(R[0] / radii.x, R[1] / radii.y, R[2] / radii.z));
    v_ray_x = vec3(0.0);
    v_ray_y = vec3(0.0);
    v_ray_c = vec3(0.0);
    v_ray_origin = vec2(0.0);
    v_k = vec4(0.0);
    v_misc = vec4(0.0);
    v_flags = FLAG_MAY_CAP;
    v_id = uint(gl_InstanceIndex);
    v_color = srgb_to_linear(unpackUnorm4x8(inst.color).rgb);
    // Clip x, y = w times Vulkan's NDC (y down) of the shaders' NDC v.xy / (v.z ndc_scale).
    vec2 xy = v.xy / vec2(cam.ndc_scale_x, cam.ndc_scale_y) - cam.ndc_shift * v.z;
    gl_Position = vec4(xy.x, -xy.y, depth_clip_z(v.z), v.z);
}
