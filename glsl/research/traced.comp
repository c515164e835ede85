#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_ray_query : require
// The traced path (research): one invocation per pixel walks a bounding-volume hierarchy of
// the glyphs' boxes (traced_boxes.comp) along the pixel centre's ray. Each box the ray meets
// is set up and hit with the splat's own functions (instance_setup.glsl, impostor_hit.glsl),
// and the nearest key (visibility.glsl: depth bits above the scene index) is kept in a local:
// the same decision as the splat's atomics, without them. Once a hit is kept, the traversal
// is told to stop beyond it (rayQueryGenerateIntersectionEXT), at a ray parameter
// conservatively beyond the hit, so rounding never culls a box whose glyph could win or tie;
// the kept key, not the query's committed hit, decides. The pixel's key goes to the
// visibility buffer and its resolve tile is marked: the resolve shades it as the splat's.
#define SPLAT_PASS
#define SETUP_HERE
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "shading.glsl"
#include "impostor_state.glsl"
#include "impostor_hit.glsl"
#include "visibility.glsl"
#include "fragment_counter.glsl"

layout(set = 1, binding = 0) uniform accelerationStructureEXT glyph_boxes;

layout(local_size_x = 8, local_size_y = 8) in;

// Whether a pixel of the workgroup (8 x 8, inside one resolve tile) shows a glyph.
shared uint group_hit;

void main() {
    if (gl_LocalInvocationIndex == 0u) {
        group_hit = 0u;
    }
    barrier();
    ivec2 size = ivec2(image_size());
    ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(xy, size));
    uint64_t best = visibility_empty();
    uint ray_casts = 0u;
    if (inside) {
        vec2 pixel = vec2(xy) + 0.5;
        // The pixel's ray in scene-origin coordinates (the boxes'): the eye from its view
        // coordinates, the direction with unit forward step, so the ray parameter is the view
        // depth (perspective), or the view depth less the start's (orthographic, the start
        // moved to just before the near plane: ray queries start at a parameter >= 0).
        vec3 eye = cam.eye_view.x * cam.right + cam.eye_view.y * cam.up + cam.eye_view.z * cam.forward;
        vec3 origin, dir;
        pixel_ray(pixel, origin, dir);
        float slack = 1e-4 * (length(cam.eye_view) + abs(cam.near_plane));
        float start = ORTHOGRAPHIC ? cam.near_plane - slack : 0.0;
        origin = eye + origin + start * dir;
        rayQueryEXT query;
        rayQueryInitializeEXT(query, glyph_boxes, gl_RayFlagsNoneEXT, 0xffu, origin, 0.0,
                              dir, 3.0e38);
        float cut = 3.0e38;
        while (rayQueryProceedEXT(query)) {
            uint id = rayQueryGetIntersectionPrimitiveIndexEXT(query, false);
            ray_casts++;
            Setup f = setup_instance(load_instance(id));
            if (f.culled) {
                continue;
            }
            use_setup(f);
            float z;
            vec3 normal;
            bool cap;
            if (!impostor_depth(pixel, z, normal, cap)) {
                continue;
            }
            uint64_t key = visibility_key(z, id + cam.first_instance);
            if (REVERSED_Z ? key <= best : key >= best) {
                continue;
            }
            best = key;
            // The hit's view depth from its depth-buffer value a + b d + c / d (b = 0 in
            // perspective, c = 0 orthographic); the margin below covers the rounding.
            float view_depth = ORTHOGRAPHIC ? (z - cam.depth_a) / cam.depth_b
                                            : cam.depth_c / (z - cam.depth_a);
            // A thousandth of the depth and the slack beyond the hit: far more than float32
            // moves the hit, the ray or the padded boxes, so every box the traversal skips
            // starts behind every hit that could win or tie.
            float beyond = (view_depth - start) * 1.001 + slack + 1e-30;
            if (beyond >= 0.0 && beyond < cut) {
                cut = beyond;
                rayQueryGenerateIntersectionEXT(query, cut);
            }
        }
        visibility[uint(xy.y * size.x + xy.x)] = best;
        if (best != visibility_empty()) {
            atomicOr(group_hit, 1u);
        }
    }
    if (COUNT_RAY_CASTS && ray_casts > 0u) {
        atomicAdd(compute_ray_casts, ray_casts);
    }
    barrier();
    if (gl_LocalInvocationIndex == 0u && group_hit != 0u) {
        uvec2 tile = gl_WorkGroupID.xy * 8u / RESOLVE_TILE;
        atomicExchange(visibility[resolve_tile_word(tile.y * resolve_tiles_x() + tile.x)],
                       ~visibility_empty());
    }
}
