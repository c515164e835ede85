#version 460
#extension GL_GOOGLE_include_directive : require
// `mesh-L*`: an icosphere per instance, the tessellation users pick instead of impostors.
// Perspective only: clip = (x/sx, -y/sy, depth_clip_z(z), z) gives depth_value(z) directly.
#include "ellipsoid_common.glsl"

layout(location = 0) in vec3 in_position; // on the unit sphere: parameter-space point and normal

layout(location = 0) out vec3 v_normal; // world, unnormalised
layout(location = 7) flat out uint v_id;
layout(location = 9) flat out vec3 v_color;

void main() {
    Instance inst = load_instance(uint(gl_InstanceIndex));
    mat3 R = quat_to_mat3(inst.rotation);
    vec3 radii = inst.radii.xyz;
    vec3 world = inst.center + R * (radii * in_position);
    vec3 v = vec3(dot(world, cam.right), dot(world, cam.up), dot(world, cam.forward))
        - cam.eye_view;
    v_normal = R * (in_position / radii);
    v_id = uint(gl_InstanceIndex);
    v_color = srgb_to_linear(unpackUnorm4x8(inst.color).rgb);
    // Clip x, y = w times Vulkan's NDC (y down) of the shaders' NDC v.xy / (v.z ndc_scale).
    vec2 xy = v.xy / vec2(cam.ndc_scale_x, cam.ndc_scale_y) - cam.ndc_shift * v.z;
    gl_Position = vec4(xy.x, -xy.y, depth_clip_z(v.z), v.z);
}
