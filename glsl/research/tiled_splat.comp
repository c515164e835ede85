#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_shuffle : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The benchmark's tiled splat (`impostor-tiled`, docs/deep-scenes.md), its tile pass after the
// binning steps of research/tiled_bins.comp: the compute splat's picture, with each TILE x
// TILE screen tile's keys kept in the registers of the one workgroup that owns the tile while
// it walks the tile's list, and written to the visibility buffer once. The plain splat instead
// keeps every covered pixel's nearest hit with a 64-bit atomic, and on lavapipe each buffer
// access costs about what a ray cast does.
//
// The workgroup is TILE lanes, one subgroup on lavapipe (8 lanes on a 256-bit CPU; it needs a
// subgroup of at least TILE lanes): lane l owns column l of the tile, TILE rows. No barrier
// and no workgroup memory -- a first version with 64 lanes, set-ups shared through workgroup
// memory and barriers took 3 to 4 times the splat on lavapipe (likely its coroutines for a
// shader with barriers) -- so the glyphs' set-ups pass between lanes by subgroup shuffles.
// The list is walked TILE glyphs at a time: each lane loads one glyph's set-up (computed once
// by RANGE), then every lane ray casts its own pixels of each glyph in turn (the same glyph in
// every lane: uniform control flow). Between batches the tile's farthest hit drops, with one
// comparison each, the glyphs of later batches whose nearest point lies beyond it (the
// culling's test, docs/design.md §5.7 step 4); the lists run nearest depth bucket first.
// Ties: keys hold the scene index, so min/max keeps the lower instance as the atomics do.
#define SPLAT_PASS
#define SETUP_HERE
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "shading.glsl"
#include "impostor_state.glsl"
#include "impostor_hit.glsl"
#include "visibility.glsl"
#include "nearest_depth.glsl"
#include "fragment_counter.glsl"
#include "tile_lists.glsl"

layout(local_size_x = 8) in;

// The farther of `far` and the depth bits of `key` where the pixel is `on` the image.
uint farther(uint far, uint64_t key, bool on) {
    uint d = uint(key >> 32);
    return on ? (REVERSED_Z ? min(far, d) : max(far, d)) : far;
}

void main() {
    uvec2 size = image_size();
    uvec2 grid = tile_grid();
    uint t = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
    uint lane = gl_LocalInvocationIndex;
    ivec2 origin = ivec2(t % grid.x, t / grid.x) * int(TILE);
    int x = origin.x + int(lane);
    bool column = uint(x) < size.x;
    uint64_t keys[TILE];
    for (uint r = 0u; r < TILE; r++) {
        keys[r] = visibility_empty();
    }
    // A later chunk keeps what the earlier ones left (a loop of no trips for the first).
    for (uint once = 0u; once < (cam.first_instance != 0u ? 1u : 0u); once++) {
        for (uint r = 0u; r < TILE; r++) {
            uint y = uint(origin.y) + r;
            keys[r] = column && y < size.y ? visibility[y * size.x + uint(x)] : keys[r];
        }
    }
    const uint neutral = REVERSED_Z ? 0xffffffffu : 0u;
    uint far = empty_key_word();
    uint room = entry_room();
    uint first = min(lists[starts_at() + t * BUCKETS], room);
    uint last = min(lists[starts_at() + (t + 1u) * BUCKETS], room);
    uint ray_casts = 0u;
    for (uint base = first; base < last; base += TILE) {
        // Lane l takes entry base + l, unless the tile's hits hide every hit of it.
        uint id = lists[entries_at() + min(base + lane, last - 1u)];
        uint at = record_at(id);
        bool take = base + lane < last && !hides_every_hit(far, uintBitsToFloat(lists[at + 2u]));
        uvec4 taken = subgroupBallot(take);
        uint box_lo = lists[at], box_hi = lists[at + 1u];
        // The hit part of the glyph's set-up, as RANGE computed it.
        uint q = at / 4u + 1u;
        vec4 ray_x = uintBitsToFloat(lists4[q]), ray_y = uintBitsToFloat(lists4[q + 1u]);
        uvec4 ray_c = lists4[q + 2u];
        vec4 k4 = uintBitsToFloat(lists4[q + 3u]), depth = uintBitsToFloat(lists4[q + 4u]);
        vec4 misc = uintBitsToFloat(lists4[q + 5u]);
        for (uint left = taken.x; left != 0u; left &= left - 1u) {
            uint s = uint(findLSB(left));
            ivec2 lo = unpack_px(subgroupShuffle(box_lo, s));
            ivec2 hi = unpack_px(subgroupShuffle(box_hi, s));
            vec4 rx = subgroupShuffle(ray_x, s), ry = subgroupShuffle(ray_y, s);
            uvec4 rc = subgroupShuffle(ray_c, s);
            v_ray_x = rx.xyz;
            v_ray_y = ry.xyz;
            v_ray_origin = vec2(rx.w, ry.w);
            v_ray_c = uintBitsToFloat(rc.xyz);
            v_flags = rc.w;
            v_k = subgroupShuffle(k4, s);
            v_depth = subgroupShuffle(depth, s);
            v_misc = subgroupShuffle(misc, s);
            uint scene_id = subgroupShuffle(id, s) + cam.first_instance;
            // Pixels outside the glyph's box take nothing of it (the splat casts none there).
            bool in_x = x >= lo.x && x <= hi.x;
            // One ray cast in the code for all rows (an unrolled one per row took longer):
            // each row's key is picked out and put back with selects.
            int r_lo = max(lo.y - origin.y, 0), r_hi = min(hi.y - origin.y, int(TILE) - 1);
            for (int r = r_lo; r <= r_hi; r++) {
                float z;
                vec3 normal;
                bool cap;
                ray_casts++;
                bool hit = impostor_depth(vec2(float(x) + 0.5, float(origin.y + r) + 0.5), z,
                                          normal, cap);
                uint64_t k = hit && in_x ? visibility_key(z, scene_id) : visibility_empty();
                for (int i = 0; i < int(TILE); i++) {
                    uint64_t kept = REVERSED_Z ? max(keys[i], k) : min(keys[i], k);
                    keys[i] = i == r ? kept : keys[i];
                }
            }
        }
        // The tile's farthest hit, for the next batch's test.
        uint mine = neutral;
        for (uint r = 0u; r < TILE; r++) {
            mine = farther(mine, keys[r], column && uint(origin.y) + r < size.y);
        }
        far = REVERSED_Z ? subgroupMin(mine) : subgroupMax(mine);
    }
    bool any_hit = false;
    for (uint r = 0u; r < TILE; r++) {
        uint y = uint(origin.y) + r;
        if (column && y < size.y) {
            visibility[y * size.x + uint(x)] = keys[r];
            any_hit = any_hit || keys[r] != visibility_empty();
        }
    }
    if (COUNT_RAY_CASTS) {
        uint casts = subgroupAdd(ray_casts);
        if (subgroupElect()) {
            atomicAdd(compute_ray_casts, casts);
        }
    }
    if (subgroupAny(any_hit) && subgroupElect()) {
        uvec2 rt = uvec2(origin) / RESOLVE_TILE;
        atomicExchange(visibility[resolve_tile_word(rt.y * resolve_tiles_x() + rt.x)],
                       ~visibility_empty());
    }
}
