#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The culling pre-pass: writes, in instance order, the indices of the instances that can
// change a pixel, and their count into the indirect draw. Exact: an instance is dropped only
// if its silhouette lies off screen or before the near plane (frustum), or its silhouette's
// bounding rectangle holds no pixel centre (pixel centres). One workgroup walks the instances
// in chunks, so the compacted order is the instance order: draw order, and with it which of
// two exactly tied depths wins, is unchanged.
#define CULL_PASS
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"

layout(local_size_x = 256) in;

layout(constant_id = 6) const bool CULL_FRUSTUM = true;
layout(constant_id = 7) const bool CULL_PIXEL_CENTRES = true;

layout(std430, set = 0, binding = 2) writeonly buffer Visible {
    uint visible[];
};
// A VkDrawIndirectCommand followed by the number of instances uploaded.
layout(std430, set = 0, binding = 3) buffer Indirect {
    uint vertex_count;
    uint instance_count;
    uint first_vertex;
    uint first_instance;
    uint total;
};

shared uint subgroup_counts[gl_WorkGroupSize.x];

// Does the instance reach a pixel centre on screen?
bool needed(uint index) {
    vec4 rect;
    if (!silhouette_rect(instances[index], rect)) {
        return !CULL_FRUSTUM;
    }
    // A sliver of a pixel of slack, as the vertex stage grows its polygon.
    vec2 margin = cam.viewport.z * cam.viewport.xy;
    rect += vec4(-margin, margin);
    if (CULL_FRUSTUM && (rect.z < -1.0 || rect.x > 1.0 || rect.w < -1.0 || rect.y > 1.0)) {
        return false;
    }
    if (CULL_PIXEL_CENTRES) {
        // Pixel centres in NDC sit at (2i + 1) / W - 1: is there one in [x0, x1]?
        vec2 size = 2.0 / cam.viewport.xy;
        vec2 lo = ceil(((rect.xy + 1.0) * size - 1.0) * 0.5);
        vec2 hi = floor(((rect.zw + 1.0) * size - 1.0) * 0.5);
        // Rows count from the top, but a range test needs no flip.
        if (any(greaterThan(lo, hi))) {
            return false;
        }
    }
    return true;
}

void main() {
    uint lane = gl_LocalInvocationIndex;
    uint written = 0u;
    for (uint start = 0u; start < total; start += gl_WorkGroupSize.x) {
        uint index = start + lane;
        uint keep = (index < total && needed(index)) ? 1u : 0u;
        // Exclusive prefix over the workgroup: within the subgroup, then over subgroups.
        uint in_subgroup = subgroupExclusiveAdd(keep);
        uint subgroup_total = subgroupAdd(keep);
        if (subgroupElect()) {
            subgroup_counts[gl_SubgroupID] = subgroup_total;
        }
        barrier();
        uint before = 0u, chunk = 0u;
        for (uint s = 0u; s < gl_NumSubgroups; s++) {
            uint n = subgroup_counts[s];
            before += s < gl_SubgroupID ? n : 0u;
            chunk += n;
        }
        if (keep != 0u) {
            visible[written + before + in_subgroup] = index;
        }
        written += chunk;
        barrier();
    }
    if (lane == 0u) {
        instance_count = written;
    }
}
