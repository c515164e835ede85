#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
// The compute splat: each glyph of the chunk computes its set-up (instance_setup.glsl, as the
// vertex stage does; it says when the glyph is off screen), ray casts the pixel centres of its
// silhouette ellipse, row by row, with the fragment stage's hit (impostor_hit.glsl), keeps the
// nearest hit per pixel in the visibility buffer with a 64-bit atomic and marks the resolve
// tiles it touched (and, with SPLAT_SETUP_ONCE, stores its shading set-up for the resolve).
// The visible-first splat's second pass skips the occlusion tiles its first pass hides.
// resolve.vert/.frag then shade each pixel of the marked tiles once. No rasterizer front end
// (on lavapipe about 0.5 us per instance on one thread). A glyph too large to walk is left to
// the draw: its keep bit and its group's count go where the culling's CLASSIFY step would put
// them, and the SCAN and SCATTER steps that follow compact them in instance order for the
// culled draw.
#define SPLAT_PASS
#define SETUP_HERE
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "setup_records.glsl"
#include "splat_box.glsl"
#include "shading.glsl"
#include "impostor_state.glsl"
#include "impostor_hit.glsl"
#include "visibility.glsl"
#include "occlusion_tiles.glsl"
#include "nearest_depth.glsl"
#include "cull_groups.glsl"
#include "glyph_stamps.glsl"
#include "fragment_counter.glsl"

// The visible-pixel floor's lists (SPLAT_FLOOR_VISIBLE; `set_floor_pixels`): the scene's glyph
// count N, N + 1 offsets (glyph g's entries run from offset g to offset g + 1), then the
// entries, each a pixel `x | y << 16`.
layout(std430, set = 0, binding = 9) readonly buffer FloorPixels {
    uint floor_pixels[];
};

layout(local_size_x = 64) in;
const uint GROUP = 64u;

// The visible-first splat's second pass (its list is CULL_SELECT_REST's) reads the occlusion
// tiles KEY_TILES left, after a barrier.
const bool SKIP_HIDDEN_TILES = SPLAT_LIST && CULL_SELECT == CULL_SELECT_REST;

// The visible-pixel floor: glyph `k` is set up and ray casts the pixels it shows, each once,
// keeping nothing (the depths feed a sum the compiler cannot drop).
void visible_floor(uint k) {
    Setup f = setup_instance(load_instance(k));
    use_setup(f);
    uint glyph = k + cam.first_instance;
    uint glyphs = floor_pixels[0];
    uint entries = glyphs + 2u;
    // The host checks the lists are the uploaded scene's; a glyph beyond them casts nothing.
    uint first = glyph < glyphs ? floor_pixels[1u + glyph] : 0u;
    uint last = glyph < glyphs ? floor_pixels[2u + glyph] : 0u;
    uint depth_sum = 0u, ray_casts = 0u;
    for (uint e = first; e < last; e++) {
        uint xy = floor_pixels[entries + e];
        float z;
        vec3 normal;
        bool cap;
        impostor_depth(vec2(float(xy & 0xffffu) + 0.5, float(xy >> 16) + 0.5), z, normal, cap);
        depth_sum ^= floatBitsToUint(z) + xy;
        ray_casts++;
    }
    if (COUNT_RAY_CASTS) {
        atomicAdd(compute_ray_casts, ray_casts);
    }
    if (depth_sum == 0x5eed5eedu) {
        visibility[0] = 1ul;
    }
}

// The block of GROUP glyphs workgroup `g` of `n` takes. A CPU driver splits the workgroups
// between its threads in index order, in equal runs (lavapipe), and glyphs in scene order are
// rarely alike from the first half to the second (a lattice seen from one side has its near,
// larger glyphs in one half): so runs of RUN workgroups (long enough to keep reading the
// instances in order) take places a prime stride apart, and every thread's share spreads over
// the whole scene. The atomics make the order irrelevant to the picture.
uint spread_block(uint g, uint n) {
    const uint RUN = 16u, STRIDE = 7919u;
    uint runs = n / RUN;
    if (g >= runs * RUN || runs % STRIDE == 0u) {
        return g;
    }
    return uint((uint64_t(g / RUN) * STRIDE) % uint64_t(runs)) * RUN + g % RUN;
}

void main() {
    uint workgroups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    uint g = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
    uint block = spread_block(g, workgroups);
    uint k = block * GROUP + gl_LocalInvocationID.x;
    // The whole chunk (no culling steps run before: the splat's own set-up and pixel walk skip
    // what the culling would have dropped, at a fraction of a dispatch's cost), or one pass of
    // the visible-first splat over the pre-pass's list.
    if (k >= (SPLAT_LIST ? instance_count : total)) {
        return;
    }
    uint id = SPLAT_LIST ? visible_instances[k] : k;
    if (SPLAT_FLOOR == SPLAT_FLOOR_VISIBLE) {
        visible_floor(k);
        return;
    }
    if (SPLAT_FLOOR == SPLAT_FLOOR_MEMORY) {
        // Every instance read once, nothing computed (the store never happens: radii > 0).
        Instance inst = load_instance(id);
        if (inst.radii.x + inst.center.x + float(inst.color) < -1e30) {
            visibility[0] = 1ul;
        }
        return;
    }
    Instance inst = load_instance(id);
    Setup f = setup_instance(inst);
    if (f.culled) {
        return;
    }
    use_setup(f);
    ivec2 size = ivec2(image_size());
    ivec2 lo, hi;
    bool bounds_known = splat_pixel_box(f, lo, hi);
    if (any(greaterThan(lo, hi)) && bounds_known) {
        return; // no pixel centre in the box
    }
    ivec2 box = hi - lo + 1;
    if (!bounds_known || box.x * box.y > SPLAT_MAX_BOX_PIXELS) {
        // Too large for one invocation to walk (it would hold up its workgroup), or reaching
        // the eye plane: left to the draw, through the culling's own compaction, in instance
        // order (from its keep bit, or in a pass over a list from its stamp).
        if (SPLAT_LIST) {
            glyph_stamps[2u * id + 1u] = frame;
        } else {
            atomicOr(groups[k / CULL_GROUP * 8u + k % CULL_GROUP / 32u], 1u << (k % 32u));
            atomicAdd(groups[group_count() * 8u + k / CULL_GROUP], 1u);
        }
        return;
    }
    uint scene_id = id + cam.first_instance;
    bool any_hit = false;
    uint depth_sum = 0u;
    uint ray_casts = 0u;
    // Each row walks only the pixel centres of the silhouette ellipse's chord through the
    // row's centre (the ellipse holds the exact silhouette with a margin, as the draw's
    // footprint does): |A^-1 d| <= 1 for d the offset from the centre, A = (axis1 axis2) in
    // pixels, gives the chord mid + s01 dy / s11 +- |det A| sqrt(s11 - dy^2) / s11.
    vec2 to_px = vec2(0.5, -0.5) * vec2(size) / vec2(cam.ndc_scale_x, cam.ndc_scale_y);
    vec2 c_ndc = image_ndc(f.centre / vec2(cam.ndc_scale_x, cam.ndc_scale_y));
    vec2 c_px = (vec2(c_ndc.x, -c_ndc.y) + 1.0) * vec2(size) * 0.5;
    vec2 a1 = f.axis1 * to_px, a2 = f.axis2 * to_px;
    float s01 = a1.x * a1.y + a2.x * a2.y, s11 = a1.y * a1.y + a2.y * a2.y;
    float det_a = abs(a1.x * a2.y - a2.x * a1.y);
    // The visible-first splat's second pass skips the occlusion tiles whose every pixel the
    // first pass already holds nearer than any hit of the glyph (the list's own test, tile by
    // tile: the glyph passed it because some tile under it failed). Per band of TILE rows, a
    // bit per tile column of the box (the first 32; beyond them nothing is skipped), so a
    // hidden tile costs one read instead of its ray casts.
    float nearest = SKIP_HIDDEN_TILES ? nearest_with_gap(inst) : 0.0;
    bool skipping = SKIP_HIDDEN_TILES && nearest > cam.near_plane;
    int tile_x0 = lo.x / TILE;
    int band = -1;
    uint hidden = 0u;
    for (int y = lo.y; y <= hi.y; y++) {
        if (skipping && y / TILE != band) {
            band = y / TILE;
            hidden = 0u;
            int row = band * tile_grid().x;
            int tile_x1 = min(hi.x / TILE, tile_x0 + 31);
            for (int tx = tile_x0; tx <= tile_x1; tx++) {
                if (hides_every_hit(tile_word(row + tx), nearest)) {
                    hidden |= 1u << uint(tx - tile_x0);
                }
            }
        }
        float dy = float(y) + 0.5 - c_px.y;
        // A thousandth of s11 and a twentieth of a pixel more than the chord: more than
        // float32 rounding moves it.
        float chord = det_a * sqrt(max(s11 * 1.001 - dy * dy, 0.0)) / s11;
        float mid = c_px.x + s01 * dy / s11;
        int x_lo = max(lo.x, int(ceil(mid - chord - 0.55)));
        int x_hi = min(hi.x, int(floor(mid + chord - 0.45)));
        for (int x = x_lo; x <= x_hi; x++) {
            uint column = uint(x / TILE - tile_x0);
            if (column < 32u && (hidden >> column & 1u) != 0u) {
                x = (x / TILE + 1) * TILE - 1; // on to the next tile
                continue;
            }
            float z;
            vec3 normal;
            bool cap;
            ray_casts++;
            if (!impostor_depth(vec2(float(x) + 0.5, float(y) + 0.5), z, normal, cap)) {
                continue;
            }
            any_hit = true;
            uint at = uint(y * size.x + x);
            uint64_t key = visibility_key(z, scene_id);
            if (SPLAT_FLOOR == SPLAT_FLOOR_ARITHMETIC) {
                // The ray cast without the atomic: every depth feeds a sum stored (almost
                // never) after the loop, so the compiler cannot drop any ray cast.
                depth_sum ^= floatBitsToUint(z) + at;
            } else if (REVERSED_Z) {
                atomicMax(visibility[at], key);
            } else {
                atomicMin(visibility[at], key);
            }
        }
    }
    if (COUNT_RAY_CASTS) {
        atomicAdd(compute_ray_casts, ray_casts);
    }
    if (SPLAT_FLOOR == SPLAT_FLOOR_ARITHMETIC && depth_sum == 0x5eed5eedu) {
        visibility[0] = 1ul;
    }
    if (any_hit && SPLAT_FLOOR == SPLAT_FLOOR_NONE) {
        if (SPLAT_SETUP_ONCE) {
            // Only a glyph with a hit can be a pixel's nearest: the resolve reads no other
            // record.
            store_shading(id, f);
        }
        // The tiles the glyph's box touches get resolved (every glyph marking one writes the
        // same word; atomically, so the writes do not race). A plain read first: most glyphs
        // find their tiles marked, and a million glyphs exchanging a few thousand words keep
        // their cache lines moving between the cores (on lavapipe at 1M 2-px glyphs the read
        // saved about a tenth of the splat). The read races with other invocations' exchanges,
        // harmlessly: whatever it returns, a word that does not read as marked is exchanged,
        // so a stale or torn read costs one atomic and never leaves a tile unmarked.
        uvec2 t_lo = uvec2(lo) / RESOLVE_TILE, t_hi = uvec2(hi) / RESOLVE_TILE;
        for (uint ty = t_lo.y; ty <= t_hi.y; ty++) {
            for (uint tx = t_lo.x; tx <= t_hi.x; tx++) {
                uint word = resolve_tile_word(ty * resolve_tiles_x() + tx);
                if (visibility[word] != ~visibility_empty()) {
                    atomicExchange(visibility[word], ~visibility_empty());
                }
            }
        }
    }
}
