#version 460
#extension GL_GOOGLE_include_directive : require
// The traced path's boxes: one axis-aligned box per glyph of the chunk (scene-origin
// coordinates, as the instances), the bounding-volume hierarchy's procedural primitives. The
// box of R diag(radii) applied to the unit sphere reaches, along world axis i, the length of
// that map's row i; it is padded by 1e-4 of the coordinates' size, far more than float32
// rounding of the box, the traversal ray and the hit moves anything.
#define SPLAT_PASS
#include "ellipsoid_common.glsl"

// The glyph count, then per glyph its box (min x, y, z, max x, y, z), from byte 8: the
// layout VkAabbPositionsKHR reads.
layout(std430, set = 1, binding = 1) buffer Boxes {
    uint box_count;
    uint box_unused;
    float boxes[];
};

layout(local_size_x = 64) in;

void main() {
    uint k = (gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x) * 64u + gl_LocalInvocationID.x;
    if (k >= box_count) {
        return;
    }
    Instance inst = load_instance(k);
    mat3 m = instance_rotation(inst);
    vec3 radii = instance_radii(inst);
    vec3 a = m[0] * radii.x, b = m[1] * radii.y, c = m[2] * radii.z;
    vec3 reach = sqrt(a * a + b * b + c * c);
    vec3 size = abs(inst.center) + reach;
    float pad = 1e-4 * max(size.x, max(size.y, size.z)) + 1e-30;
    vec3 lo = inst.center - reach - pad, hi = inst.center + reach + pad;
    boxes[6u * k + 0u] = lo.x;
    boxes[6u * k + 1u] = lo.y;
    boxes[6u * k + 2u] = lo.z;
    boxes[6u * k + 3u] = hi.x;
    boxes[6u * k + 4u] = hi.y;
    boxes[6u * k + 5u] = hi.z;
}
