#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// The benchmark's tiled splat (`impostor-tiled`, docs/deep-scenes.md), its binning steps
// (CULL_STEP, the pre-pass's step constant, numbers them here; research/tiled_splat.comp is
// the tile pass that follows):
//   RANGE   per glyph: set-up, pixel box and nearest depth into its record; the frame's
//           nearest and farthest glyph depth; glyphs too large for a tile list are left to the
//           draw as the splat leaves them (keep bits, compacted by the culling's SCAN/SCATTER);
//   COUNT   per glyph: its depth bucket; one count per (tile, bucket) its box touches;
//   SCAN    one workgroup: the counts to first slots, so each tile's list runs nearest bucket
//           first;
//   SCATTER per glyph: its index into each touched tile's list.
#define SPLAT_PASS
#define SETUP_HERE
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "splat_box.glsl"
#include "visibility.glsl"
#include "cull_groups.glsl"
#include "nearest_depth.glsl"
#define TILE_LISTS4_ACCESS
#include "tile_lists.glsl"

layout(local_size_x = 64) in;
const uint GROUP = 64u;

const int STEP_RANGE = 0;
const int STEP_COUNT = 1;
const int STEP_SCAN = 2;
const int STEP_SCATTER = 3;

// RANGE: glyph `k`'s record, and the frame's range of glyph depths.
void range(uint k) {
    uint near_bits = 0x7f800000u, far_bits = 0u;
    if (k < total) {
        uint at = record_at(k);
        lists[at + 3u] = NOT_BINNED;
        Instance inst = load_instance(k);
        Setup f = setup_instance(inst);
        ivec2 lo, hi;
        bool known = splat_pixel_box(f, lo, hi);
        ivec2 box = hi - lo + 1;
        ivec2 tiles = hi / int(TILE) - lo / int(TILE) + 1;
        bool empty = f.culled || (known && any(greaterThan(lo, hi)));
        bool large = box.x * box.y > SPLAT_MAX_BOX_PIXELS || tiles.x * tiles.y > MAX_GLYPH_TILES;
        if (!empty && (!known || large)) {
            // As the splat: left to the draw through the culling's compaction.
            atomicOr(groups[k / CULL_GROUP * 8u + k % CULL_GROUP / 32u], 1u << (k % 32u));
            atomicAdd(groups[group_count() * 8u + k / CULL_GROUP], 1u);
        } else if (!empty) {
            float nearest = nearest_with_gap(inst);
            lists[at] = pack_px(lo);
            lists[at + 1u] = pack_px(hi);
            lists[at + 2u] = floatBitsToUint(nearest);
            lists[at + 3u] = 0u;
            // The hit part of the set-up, computed once for every tile the glyph touches.
            uint q = at / 4u + 1u;
            lists4[q] = floatBitsToUint(vec4(f.ray_x, f.ray_origin.x));
            lists4[q + 1u] = floatBitsToUint(vec4(f.ray_y, f.ray_origin.y));
            lists4[q + 2u] = uvec4(floatBitsToUint(f.ray_c), f.flags);
            lists4[q + 3u] = floatBitsToUint(f.k);
            lists4[q + 4u] = floatBitsToUint(f.depth);
            lists4[q + 5u] = floatBitsToUint(f.misc);
            // Buckets order positive depths (their bits order like them).
            near_bits = floatBitsToUint(max(nearest, max(cam.near_plane, 0.0)));
            far_bits = near_bits;
        }
    }
    near_bits = subgroupMin(near_bits);
    far_bits = subgroupMax(far_bits);
    if (subgroupElect()) {
        atomicMin(lists[0], near_bits);
        atomicMax(lists[1], far_bits);
    }
}

// The tiles [t_lo, t_hi] glyph `k`'s box touches, and its bucket; false if it is not binned.
bool binned(uint k, out uvec2 t_lo, out uvec2 t_hi, out uint bucket) {
    uint at = record_at(k);
    t_lo = uvec2(1u);
    t_hi = uvec2(0u);
    bucket = lists[at + 3u];
    if (bucket == NOT_BINNED) {
        return false;
    }
    t_lo = uvec2(unpack_px(lists[at])) / TILE;
    t_hi = uvec2(unpack_px(lists[at + 1u])) / TILE;
    return true;
}

// COUNT: glyph `k`'s bucket, and one count in each (tile, bucket) it touches.
void count(uint k) {
    uint at = record_at(k);
    if (lists[at + 3u] == NOT_BINNED) {
        return;
    }
    float near = uintBitsToFloat(lists[0]), far = uintBitsToFloat(lists[1]);
    float nearest = max(uintBitsToFloat(lists[at + 2u]), max(cam.near_plane, 0.0));
    float span = far - near;
    uint bucket = span > 0.0
        ? min(uint((nearest - near) / span * float(BUCKETS)), BUCKETS - 1u) : 0u;
    lists[at + 3u] = bucket;
    uvec2 t_lo = uvec2(unpack_px(lists[at])) / TILE;
    uvec2 t_hi = uvec2(unpack_px(lists[at + 1u])) / TILE;
    uint tiles_x = tile_grid().x;
    for (uint ty = t_lo.y; ty <= t_hi.y; ty++) {
        for (uint tx = t_lo.x; tx <= t_hi.x; tx++) {
            atomicAdd(lists[HEADER + (ty * tiles_x + tx) * BUCKETS + bucket], 1u);
        }
    }
}

shared uint block_sums[GROUP];

// SCAN: the counts to first slots (the SCATTER's cursors) and the lists' starts.
void scan() {
    uint lane = gl_LocalInvocationIndex;
    uint n = cells();
    uint per = (n + GROUP - 1u) / GROUP;
    uint first = min(lane * per, n), last = min(first + per, n);
    uint sum = 0u;
    for (uint c = first; c < last; c++) {
        sum += lists[HEADER + c];
    }
    block_sums[lane] = sum;
    barrier();
    if (lane == 0u) {
        uint running = 0u;
        for (uint l = 0u; l < GROUP; l++) {
            uint s = block_sums[l];
            block_sums[l] = running;
            running += s;
        }
        lists[2] = running;
        lists[starts_at() + n] = running;
    }
    barrier();
    uint slot = block_sums[lane];
    for (uint c = first; c < last; c++) {
        uint count = lists[HEADER + c];
        lists[HEADER + c] = slot;
        lists[starts_at() + c] = slot;
        slot += count;
    }
}

// SCATTER: glyph `k` into each touched tile's list.
void scatter(uint k) {
    uvec2 t_lo, t_hi;
    uint bucket;
    binned(k, t_lo, t_hi, bucket);
    uint tiles_x = tile_grid().x;
    uint room = entry_room();
    for (uint ty = t_lo.y; ty <= t_hi.y; ty++) {
        for (uint tx = t_lo.x; tx <= t_hi.x; tx++) {
            uint slot = atomicAdd(lists[HEADER + (ty * tiles_x + tx) * BUCKETS + bucket], 1u);
            if (slot < room) {
                lists[entries_at() + slot] = k;
            } else {
                atomicAdd(lists[3], 1u);
            }
        }
    }
}

void main() {
    uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
    uint k = g * GROUP + gl_LocalInvocationIndex;
    if (CULL_STEP == STEP_RANGE) {
        range(k);
    } else if (CULL_STEP == STEP_COUNT) {
        if (k < total) {
            count(k);
        }
    } else if (CULL_STEP == STEP_SCAN) {
        scan();
    } else if (k < total) {
        scatter(k);
    }
}
