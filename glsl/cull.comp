#version 460
#extension GL_GOOGLE_include_directive : require
// The culling pre-pass: writes, in instance order, the indices of the instances that can
// change a pixel, and their count into the indirect draw. Exact: an instance is dropped only
// if its silhouette lies off screen or before the near plane (frustum), its silhouette's
// bounding rectangle holds no pixel centre (pixel centres), or every pixel centre of that
// rectangle is already covered by some ellipsoid lying wholly nearer (occlusion). On
// multisampled targets both proofs are about the samples (SAMPLE_GRID): the pixels with a
// sample in the rectangle, and tiles whose every sample the occluder covers.
//
// The steps, one dispatch each (CULL_STEP): over groups of 256 instances, one invocation each
// (SCATTER, and CLASSIFY by a stamp: one per 32 of them, a keep word); SCAN one workgroup;
// KEY_TILES and MARK_SHOWN one invocation per strip of the image:
//   OCCLUDERS  each ellipsoid lowers, on the pixel tiles its inscribed sphere covers for
//              certain, the tile's "something lies at or before this view depth" bound;
//   CLASSIFY   keep bits and a count per group, and (CULL_SETUP) each kept instance's set-up
//              for the impostor stages, computed once instead of in each of its vertices;
//   SCAN       one workgroup turns the counts into each group's first output slot (and
//              writes the splat's indirect dispatch over the list);
//   SCATTER    kept indices to their slots: the compacted order is the instance order, so
//              draw order, and with it which of two exactly tied depths wins, is unchanged;
//   KEY_TILES  (the visible-first splat, after its first pass) each tile of a marked resolve
//              tile takes the farthest depth-buffer value the visibility buffer holds over
//              its pixels;
//   MARK_SHOWN (the visible-first splat, after its passes) each glyph the finished visibility
//              buffer shows is stamped with the frame, to be splatted first next frame.
// CULL_SELECT picks what CLASSIFY lists: the visible-first splat lists the glyphs the last
// frame showed, then the rest that the first pass's hits do not hide, then those its passes
// left to the draw (docs/design.md §5.7).
#define CULL_PASS
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "setup_records.glsl"
#include "occlusion_tiles.glsl"
#include "nearest_depth.glsl"
#include "glyph_stamps.glsl"
#include "visibility_words.glsl"

#include "cull_groups.glsl"

// The workgroup size, named here rather than read from gl_WorkGroupSize (a built-in SPIR-V
// 1.6 deprecates): one group of instances.
layout(local_size_x = 256) in;
const uint GROUP = CULL_GROUP;

// CLASSIFY also computes each kept instance's set-up for the SETUP_ONCE impostor stages.
const int STEP_OCCLUDERS = 0;
const int STEP_CLASSIFY = 1;
const int STEP_SCAN = 2;
const int STEP_SCATTER = 3;
const int STEP_KEY_TILES = 4;
const int STEP_MARK_SHOWN = 5;
// CLASSIFY picks by a stamp alone (`classify_stamps`; `CullSelect::by_stamp` in
// src/renderer/prepass/steps.rs).
const bool CLASSIFY_STAMPS = CULL_SELECT == CULL_SELECT_SHOWN || CULL_SELECT == CULL_SELECT_DRAWN;

layout(std430, set = 0, binding = 2) writeonly buffer Visible {
    uint visible[];
};
// Rectangles of more tiles than this are not tested (kept): few instances are that large.
const int MAX_TESTED_TILES = 256;
// An occluder writes at most this many tiles across (a subset of its tiles stays exact).
const int MAX_WRITTEN_TILES = 64;
// How far a pixel's samples may lie from its centre along each axis, in pixels: 0 for the
// centre alone; half a pixel less the half step of a finer grid; a half pixel anywhere.
float sample_spread() {
    return SAMPLE_GRID == 0 ? 0.5 : 0.5 - 0.5 / float(SAMPLE_GRID);
}

uint group_index() {
    return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
}

// The cell centres of a grid of `size` cells over the screen inside an NDC rectangle with y up:
// (first column, first row, last column, last row), rows from the top, unclamped (may lie off
// screen); empty when first > last.
vec4 cell_centres(vec4 rect, vec2 size) {
    // Cell centre i sits at NDC (2i + 1) / W - 1.
    vec2 lo = ceil(((rect.xy + 1.0) * size - 1.0) * 0.5);
    vec2 hi = floor(((rect.zw + 1.0) * size - 1.0) * 0.5);
    // Rows count from the top.
    return vec4(lo.x, size.y - 1.0 - hi.y, hi.x, size.y - 1.0 - lo.y);
}

// The pixels with a sample inside an NDC rectangle with y up, as `cell_centres`; empty when
// first > last. The sizes are exact integers (2 / (2 / H) in float32 can fall just short of
// H).
vec4 pixels_sampled(vec4 rect) {
    vec2 size = vec2(image_size());
    if (SAMPLE_GRID == 0) {
        // Samples anywhere: the pixels whose centre lies within half a pixel of the rectangle.
        vec2 half_pixel = 0.5 * cam.ndc_per_pixel;
        return cell_centres(rect + vec4(-half_pixel, half_pixel), size);
    }
    // The samples are centres of a grid SAMPLE_GRID times finer: its cell k lies in pixel
    // floor(k / SAMPLE_GRID).
    float grid = float(SAMPLE_GRID);
    vec4 cells = cell_centres(rect, size * grid);
    if (any(greaterThan(cells.xy, cells.zw))) {
        return vec4(0.0, 0.0, -1.0, -1.0);
    }
    return floor(cells / grid);
}

// The tiles (inclusive) holding the on-screen ones of the pixels `sampled` (first column,
// first row, last column, last row, as `pixels_sampled` gives them); empty when lo > hi.
void tiles_touched(vec4 sampled, out ivec2 lo, out ivec2 hi) {
    vec2 last = vec2(image_size() - 1u);
    lo = ivec2(clamp(sampled.xy, vec2(0.0), last + 1.0)) / TILE;
    hi = ivec2(clamp(sampled.zw, vec2(-1.0), last));
    hi = (hi + TILE) / TILE - 1; // floor division that keeps -1 below 0
}

// OCCLUDERS: the ellipsoid contains the sphere of its smallest radius r around its centre c,
// and every ray within angle asin(r / |c|) of c hits that sphere. Since
// sin(angle(p, m)) <= |p - m| for screen-plane points p, m (slopes x/z, y/z), every pixel
// centre within r / |c| of the projected centre m shows this ellipsoid or something nearer.
// The ray d enters the sphere at a point P with (P - c).d <= 0, so P's view depth is at most
// cz + r |f - d|: the surface there lies no deeper. Orthographic: within r of the centre's
// axis, no deeper than cz.
void write_occluder(uint index) {
    Instance inst = load_instance(index);
    vec3 r = cam.right, u_axis = cam.up, f = cam.forward;
    vec2 s = vec2(cam.ndc_scale_x, cam.ndc_scale_y);
    vec3 c = vec3(dot(inst.center, r), dot(inst.center, u_axis), dot(inst.center, f)) - cam.eye_view;
    float radius = min(inst.radii.x, min(inst.radii.y, inst.radii.z));
    float reach = ORTHOGRAPHIC ? radius : radius / length(c);
    // The disc's radius in pixels (of the longer pixel side, where pixels are not square),
    // shrunk so float rounding never claims a pixel the fragment stage might miss. Most
    // glyphs vouch for no whole tile: leave before the costlier tests.
    float per_pixel = max(cam.ndc_scale_x * cam.ndc_per_pixel.x, cam.ndc_scale_y * cam.ndc_per_pixel.y);
    float pixels = 0.99 * reach / per_pixel - 0.05;
    if (!(pixels >= 0.5 * float(TILE))) {
        return;
    }
    // Multisampled: a tile's samples reach e beyond its pixel centres on each axis.
    float e = sample_spread();
    // Only ellipsoids wholly beyond the near plane (no cap) and in front of the eye.
    vec2 z = depth_range(inst);
    if (!(z.x - z.y > cam.near_plane) || !(z.x - z.y > 0.0)) {
        return;
    }
    vec2 centre; // screen plane
    float bound;
    if (ORTHOGRAPHIC) {
        centre = c.xy;
        bound = c.z;
    } else {
        centre = c.xy / c.z;
        // |f - d| = 2 sin(theta / 2) for the ray's angle theta off the view axis, at most
        // atan(|m| + reach) inside the disc.
        float t = length(centre) + reach;
        bound = c.z + radius * sqrt(max(2.0 - 2.0 / sqrt(1.0 + t * t), 0.0));
    }
    // Pixel centre i at coordinate i, rows from the top.
    ivec2 size = ivec2(image_size());
    vec2 ndc = image_ndc(centre / s);
    vec2 p = vec2(ndc.x + 1.0, 1.0 - ndc.y) * 0.5 * vec2(size) - 0.5;
    if (any(isnan(p))) {
        return;
    }
    // Tile rows, then the tiles of each row whose samples all lie in the disc; a tile cut by
    // the screen's edge holds only its on-screen pixels. Large occluders write a
    // central subset of their tiles: still exact, far fewer atomics. Clamped in float before
    // any conversion to int, so far-off discs stay harmless.
    ivec2 grid = tile_grid();
    float y_lo = clamp(ceil(p.y - pixels + e), 0.0, float(size.y));
    float y_hi = clamp(floor(p.y + pixels - e), -1.0, float(size.y - 1));
    if (y_lo > y_hi) {
        return;
    }
    int ty0 = int(y_lo) / TILE;
    int ty1 = int(y_hi) / TILE;
    int excess = max(ty1 - ty0 + 1 - MAX_WRITTEN_TILES, 0);
    ty0 += excess / 2;
    ty1 -= excess - excess / 2;
    uint bits = floatBitsToUint(bound);
    for (int ty = ty0; ty <= ty1; ty++) {
        float top = float(ty * TILE), bottom = float(min(ty * TILE + TILE - 1, size.y - 1));
        float dy = max(abs(top - e - p.y), abs(bottom + e - p.y));
        if (dy > pixels) {
            continue;
        }
        float half_width = sqrt(pixels * pixels - dy * dy);
        float x_lo = clamp(ceil(p.x - half_width + e), 0.0, float(size.x));
        float x_hi = clamp(floor(p.x + half_width - e), -1.0, float(size.x - 1));
        if (x_lo > x_hi) {
            continue;
        }
        int x0 = int(x_lo);
        int x1 = int(x_hi);
        int tx0 = (x0 + TILE - 1) / TILE;
        int tx1 = x1 == size.x - 1 ? grid.x - 1 : (x1 + 1) / TILE - 1;
        int extra = max(tx1 - tx0 + 1 - MAX_WRITTEN_TILES, 0);
        tx0 += extra / 2;
        tx1 -= extra - extra / 2;
        for (int tx = tx0; tx <= tx1; tx++) {
            atomicMin(tiles[ty * grid.x + tx], bits);
        }
    }
}

// The tiles holding the pixels `sampled`, if there are some and few enough to test.
bool tested_tiles(vec4 sampled, out ivec2 t0, out ivec2 t1) {
    tiles_touched(sampled, t0, t1);
    ivec2 n = t1 - t0 + 1;
    return all(greaterThan(n, ivec2(0))) && n.x * n.y <= MAX_TESTED_TILES;
}

// Is every sample of the pixels `sampled` covered by something at least DEPTH_GAP nearer than
// the ellipsoid's nearest point?
bool occluded(uint index, vec4 sampled) {
    float limit = nearest_with_gap(load_instance(index));
    ivec2 grid = tile_grid();
    ivec2 t0, t1;
    if (!(limit > 0.0) || !tested_tiles(sampled, t0, t1)) {
        return false;
    }
    for (int ty = t0.y; ty <= t1.y; ty++) {
        for (int tx = t0.x; tx <= t1.x; tx++) {
            if (!(uintBitsToFloat(tiles[ty * grid.x + tx]) < limit)) {
                return false;
            }
        }
    }
    return true;
}

// KEY_TILES and MARK_SHOWN go by strips: a strip is a row of occlusion tiles across a resolve
// tile (32 x 4 pixels), invocation `i` takes strip `i % STRIPS` of resolve tile `i / STRIPS`,
// so each 8 consecutive invocations (a subgroup on lavapipe) share a resolve tile. On lavapipe
// an invocation costs about as much as a few reads, so what a resolve tile no glyph marked
// costs is its strips' invocations; such a tile shows nothing so far this frame (a glyph with
// a hit marks every resolve tile its box touches), and its strips read no pixel, in loops of
// no trips (lavapipe runs a branch's body whatever the condition, but not a loop's).
const uint STRIPS = RESOLVE_TILE / uint(TILE);

// The strip of invocation `i`: its first pixel, and whether its resolve tile was marked; none
// (false) below the image.
bool strip_of(uint i, out uvec2 origin, out bool marked) {
    uint tiles_x = resolve_tiles_x();
    uint r = i / STRIPS;
    origin = uvec2(r % tiles_x * RESOLVE_TILE, r / tiles_x * RESOLVE_TILE + i % STRIPS * TILE);
    marked = false;
    if (origin.y >= image_size().y) {
        return false; // below the image (and beyond the last resolve tile)
    }
    marked = key_words(resolve_tile_word(r)).x != empty_key_word();
    return true;
}

// KEY_TILES: each occlusion tile of a marked strip takes the farthest depth-buffer value (bits:
// positive floats order like their bits) the visibility buffer holds at its on-screen pixels,
// or the empty key's when a pixel shows nothing: every pixel of the tile holds a hit at or
// nearer than it. The other tiles keep the empty key's word the pre-pass cleared them to.
void key_tiles(uint i) {
    uvec2 origin;
    bool marked;
    if (!strip_of(i, origin, marked)) {
        return;
    }
    uvec2 size = image_size();
    uint row = origin.y / uint(TILE) * uint(tile_grid().x);
    uint end_x = marked ? min(origin.x + RESOLVE_TILE, size.x) : origin.x;
    for (uint x0 = origin.x; x0 < end_x; x0 += uint(TILE)) {
        uvec2 last = min(uvec2(x0, origin.y) + uint(TILE) - 1u, size - 1u);
        uint farthest = ~empty_key_word();
        for (uint y = origin.y; y <= last.y; y++) {
            for (uint x = x0; x <= last.x; x++) {
                uint z = key_words(y * size.x + x).y;
                farthest = REVERSED_Z ? min(farthest, z) : max(farthest, z);
            }
        }
        tiles[row + x0 / uint(TILE)] = farthest;
    }
}

// MARK_SHOWN: the glyph each on-screen pixel of the strip shows is stamped with the frame.
void mark_shown(uint i) {
    uvec2 origin;
    bool marked;
    if (!strip_of(i, origin, marked)) {
        return;
    }
    uvec2 size = image_size();
    uvec2 end = marked ? min(origin + uvec2(RESOLVE_TILE, TILE), size) : origin;
    for (uint y = origin.y; y < end.y; y++) {
        for (uint x = origin.x; x < end.x; x++) {
            uint low = key_words(y * size.x + x).x;
            uint glyph = key_instance(low) - cam.first_instance;
            if (low != empty_key_word() && glyph < total) {
                glyph_stamps[2u * glyph] = frame;
            }
        }
    }
}

// Does the first pass's picture hide the glyph at every pixel with a sample in `sampled`?
// Each such pixel already holds a hit at or nearer than its tile's word (KEY_TILES). The
// glyph's every hit lies beyond its nearest point moved nearer by DEPTH_GAP of the depths
// involved (`nearest_with_gap`); where that lies beyond the near plane, its depth-buffer value
// more than two float steps beyond the tile's word means the glyph can neither win nor tie a
// pixel of the tile. A glyph that may reach the near plane (a cap) is never hidden.
bool hidden_by_first_pass(uint index, vec4 sampled) {
    float nearest = nearest_with_gap(load_instance(index));
    ivec2 grid = tile_grid();
    ivec2 t0, t1;
    if (!(nearest > cam.near_plane) || !tested_tiles(sampled, t0, t1)) {
        return false;
    }
    for (int ty = t0.y; ty <= t1.y; ty++) {
        for (int tx = t0.x; tx <= t1.x; tx++) {
            if (!hides_every_hit(tile_word(ty * grid.x + tx), nearest)) {
                return false;
            }
        }
    }
    return true;
}

// Can the instance change a pixel? `reaches`: whether anything of it lies beyond the near
// plane; `rect`: an NDC rectangle (y up) holding its silhouette.
bool needed(uint index, bool reaches, vec4 rect) {
    if (!reaches) {
        return !CULL_FRUSTUM;
    }
    if (any(isnan(rect))) {
        return true; // degenerate: the vertex stage drops it
    }
    // A sliver of a pixel of slack, as the vertex stage grows its polygon.
    vec2 margin = QUAD_MARGIN_PX * cam.ndc_per_pixel;
    rect += vec4(-margin, margin);
    if (CULL_FRUSTUM && (rect.z < -1.0 || rect.x > 1.0 || rect.w < -1.0 || rect.y > 1.0)) {
        return false;
    }
    if (!CULL_PIXEL_CENTRES && !CULL_OCCLUSION && CULL_SELECT != CULL_SELECT_REST) {
        return true;
    }
    vec4 sampled = pixels_sampled(rect);
    if (CULL_PIXEL_CENTRES && any(greaterThan(sampled.xy, sampled.zw))) {
        return false;
    }
    if (CULL_SELECT == CULL_SELECT_REST) {
        return !hidden_by_first_pass(index, sampled);
    }
    return !(CULL_OCCLUSION && occluded(index, sampled));
}

// The rectangle of `needed` from a set-up instance: around the ellipse its footprint polygon
// circumscribes (which holds the silhouette), or the whole screen. No rectangle when the
// vertex stage culls the instance as off screen or before the near plane.
bool setup_rect(Setup s, out vec4 rect) {
    rect = vec4(-1.0, -1.0, 1.0, 1.0);
    if (s.culled) {
        return false;
    }
    if (s.bounded && !s.screen_polygon) {
        vec2 sxy = vec2(cam.ndc_scale_x, cam.ndc_scale_y);
        vec2 extent = sqrt(s.axis1 * s.axis1 + s.axis2 * s.axis2);
        rect = vec4((s.centre - extent) / sxy, (s.centre + extent) / sxy) - cam.ndc_shift.xyxy;
    }
    return true;
}

shared uint keep_bits[8];
// CLASSIFY of the stamps: the kept instances of each of the workgroup's groups.
shared uint kept_in_group[GROUP / 8u];

// CLASSIFY of the glyphs a stamp picks (those the last stamping frame showed, or those a
// splat pass of this frame left to the draw): invocation `w` reads the stamps of keep word
// `w`'s 32 instances, as SCATTER takes them, and the 8 lanes of a group add up its count.
void classify_stamps(uint w) {
    uint lane = gl_LocalInvocationIndex;
    uint group = w / 8u;
    if (lane < GROUP / 8u) {
        kept_in_group[lane] = 0u;
    }
    barrier();
    uint bits = 0u;
    uint end = group < group_count() ? min(w * 32u + 32u, total) : 0u;
    for (uint i = w * 32u; i < end; i++) {
        bool keep = CULL_SELECT == CULL_SELECT_SHOWN ? shown_last_frame(i) : left_to_draw(i);
        bits |= keep ? 1u << (i % 32u) : 0u;
    }
    if (end > 0u) {
        groups[w] = bits;
        atomicAdd(kept_in_group[lane / 8u], uint(bitCount(bits)));
    }
    barrier();
    if (end > 0u && lane % 8u == 0u) {
        groups[group_count() * 8u + group] = kept_in_group[lane / 8u];
    }
}

void classify(uint group, uint index) {
    uint lane = gl_LocalInvocationIndex;
    if (lane < 8u) {
        keep_bits[lane] = 0u;
    }
    barrier();
    if (index < total) {
        vec4 rect;
        bool keep;
        if (CULL_SETUP) {
            // The set-up holds the footprint: no second projection for the rectangle.
            Setup s = setup_instance(load_instance(index));
            keep = needed(index, setup_rect(s, rect), rect);
            if (keep) {
                store_setup(index, s);
            }
        } else {
            keep = (CULL_SELECT != CULL_SELECT_REST || !shown_last_frame(index))
                && needed(index, silhouette_rect(load_instance(index), rect), rect);
        }
        if (keep) {
            atomicOr(keep_bits[lane / 32u], 1u << (lane % 32u));
        }
    }
    barrier();
    if (lane < 8u) {
        groups[group * 8u + lane] = keep_bits[lane];
    }
    if (lane == 0u) {
        uint kept = 0u;
        for (int w = 0; w < 8; w++) {
            kept += uint(bitCount(keep_bits[w]));
        }
        groups[group_count() * 8u + group] = kept;
    }
}

shared uint block_sums[GROUP];

// One workgroup: each lane sums a run of consecutive groups, the runs are prefixed, then each
// lane rewrites its groups' counts as first slots.
void scan() {
    uint lane = gl_LocalInvocationIndex;
    uint n = group_count();
    uint base = n * 8u;
    uint per = (n + GROUP - 1u) / GROUP;
    uint first = min(lane * per, n), last = min(first + per, n);
    uint sum = 0u;
    for (uint g = first; g < last; g++) {
        sum += groups[base + g];
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
        instance_count = running;
        // The splat's workgroups of 64 over the list: x up to the guaranteed limit, then rows.
        uint splat_groups = (running + 63u) / 64u;
        uint x = min(splat_groups, 65535u);
        dispatch_x = x;
        dispatch_y = x == 0u ? 1u : (splat_groups + x - 1u) / x;
        dispatch_z = 1u;
    }
    barrier();
    uint slot = block_sums[lane];
    for (uint g = first; g < last; g++) {
        uint count = groups[base + g];
        groups[base + g] = slot;
        slot += count;
    }
}

// SCATTER: invocation `w` takes keep word `w` (word w % 8 of group w / 8) and writes its kept
// instances to their slots in instance order, from the group's first slot and the kept
// instances of the group's earlier words: one invocation per 32 instances, since on lavapipe
// an invocation costs about as much as a few reads.
void scatter_word(uint w) {
    uint group = w / 8u;
    if (group >= group_count()) {
        return; // the dispatch grid's padding
    }
    uint word = groups[w];
    uint slot = groups[group_count() * 8u + group];
    for (uint k = group * 8u; k < w; k++) {
        slot += uint(bitCount(groups[k]));
    }
    for (; word != 0u; word &= word - 1u) {
        visible[slot] = w * 32u + uint(findLSB(word));
        slot++;
    }
}

void main() {
    if (CULL_STEP == STEP_SCAN) {
        scan();
        return;
    }
    if (CULL_STEP == STEP_KEY_TILES) {
        key_tiles(group_index() * GROUP + gl_LocalInvocationIndex);
        return;
    }
    if (CULL_STEP == STEP_MARK_SHOWN) {
        mark_shown(group_index() * GROUP + gl_LocalInvocationIndex);
        return;
    }
    if (CULL_STEP == STEP_SCATTER) {
        scatter_word(group_index() * GROUP + gl_LocalInvocationIndex);
        return;
    }
    if (CULL_STEP == STEP_CLASSIFY && CLASSIFY_STAMPS) {
        classify_stamps(group_index() * GROUP + gl_LocalInvocationIndex);
        return;
    }
    uint group = group_index();
    if (group >= group_count()) {
        return; // the whole workgroup: the dispatch grid's padding
    }
    uint index = group * GROUP + gl_LocalInvocationIndex;
    if (CULL_STEP == STEP_OCCLUDERS) {
        if (index < total) {
            write_occluder(index);
        }
    } else if (CULL_STEP == STEP_CLASSIFY) {
        classify(group, index);
    }
}
