// Per-instance set-up records written by the culling pre-pass (cull.comp, CULL_SETUP) and
// read by the SETUP_ONCE builds of the impostor stages, at the instance's index. Needs
// instance_setup.glsl first.
//
// FootprintRecord (binding 7) holds what the vertex stage needs, ShadingRecord (binding 6)
// what the fragment stage needs (both in gpu_layout.glsl).

#ifdef CULL_PASS
#define RECORD_ACCESS writeonly
#else
#define RECORD_ACCESS readonly
#endif

// Footprint flags.
const uint FOOTPRINT_CULLED = 1u;
const uint FOOTPRINT_SCREEN = 2u;
// Shading flag: the ray is relative to ray_origin (offset mode), so ray_c and eye_dist are
// not read.
const uint FLAG_OFFSET_ORIGIN = 4u;

#if defined(CULL_PASS) || defined(SETUP_ONCE_VERTEX)
layout(std430, set = 0, binding = 7) RECORD_ACCESS buffer FootprintRecords {
    FootprintRecord footprints[];
};
#endif
#if defined(CULL_PASS) || defined(SETUP_ONCE_FRAGMENT)
layout(std430, set = 0, binding = 6) RECORD_ACCESS buffer ShadingRecords {
    ShadingRecord shading[];
};
#endif

#ifdef CULL_PASS
void store_setup(uint id, Setup s) {
    uint flags = (s.culled ? FOOTPRINT_CULLED : 0u) | (s.screen_polygon ? FOOTPRINT_SCREEN : 0u);
    footprints[id] = FootprintRecord(s.centre, s.axis1, s.axis2, s.quad_z, flags);
    // Offset mode (o, ray_c = 0) is the common case: its hit test needs the first three vec4
    // only; the fourth holds ray_c (and |e~|) for rays that are pixel directions, the fifth g
    // for orthographic depth. The fragment stage derives k = (1, r cz, cz u, r) in perspective
    // offset mode, (0, r, u, r) otherwise, (1, 1, 0, 1) orthographic; r^2 = r r; and the depth
    // scale (cz in perspective offset mode, else 1) -- the same operations on the same values
    // as instance_setup.glsl, so the same bits.
    bool origin = s.ray_c == vec3(0.0);
    uint shading_flags = s.flags | (origin ? FLAG_OFFSET_ORIGIN : 0u);
    vec3 color = srgb_to_linear(unpackUnorm4x8(s.color).rgb);
    shading[id] = ShadingRecord(
        s.ray_x, s.k.w,
        s.ray_y, s.misc.x,
        s.ray_origin, s.depth.w, shading_flags,
        s.ray_c, s.misc.y,
        s.depth.xyz, 0.0,
        s.to_normal[0], color.r,
        s.to_normal[1], color.g,
        s.to_normal[2], color.b);
}
#endif

#ifdef SETUP_ONCE_VERTEX
Setup load_footprint(uint id) {
    Setup s;
    FootprintRecord f = footprints[id];
    s.culled = (f.flags & FOOTPRINT_CULLED) != 0u;
    s.screen_polygon = (f.flags & FOOTPRINT_SCREEN) != 0u;
    s.centre = f.centre;
    s.axis1 = f.axis1;
    s.axis2 = f.axis2;
    s.quad_z = f.quad_z;
    s.offset_mode = true; // only Gumhold's world quad reads it, and that is never set up once
    return s;
}
#endif
