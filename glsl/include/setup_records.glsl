// Per-instance set-up records written by the culling pre-pass (cull.comp, CULL_SETUP) and
// read by the SETUP_ONCE builds of the impostor stages, at the instance's index; the shading
// records also by the compute splat (SPLAT_SETUP_ONCE) for its resolve, which reads them
// through binding 14 (shading_record_texels.glsl). Needs instance_setup.glsl first (the
// writers) or impostor_state.glsl's globals (the readers).
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
#ifdef SETUP_ONCE_FRAGMENT
layout(std430, set = 0, binding = 6) readonly buffer ShadingRecords {
    ShadingRecord shading[];
};
#endif

#if defined(CULL_PASS) || defined(SPLAT_PASS)
// The writers store the shading records through binding 15, a storage texel view of binding
// 6 (R32G32B32A32_UINT, eight texels a record, ShadingRecord's vec4 rows in order): lavapipe
// stores a storage buffer's words lane by lane, a texel's four at once here.
layout(set = 0, binding = 15, rgba32ui) uniform writeonly uimageBuffer shading_record_stores;

// Offset mode (o, ray_c = 0) is the common case: its hit test needs the first three rows
// only; the fourth holds ray_c (and |e~|) for rays that are pixel directions, the fifth g
// for orthographic depth, each stored only where it is read. The fragment stage derives
// k = (1, r cz, cz u, r) in perspective offset mode, (0, r, u, r) otherwise, (1, 1, 0, 1)
// orthographic; r^2 = r r; and the depth scale (cz in perspective offset mode, else 1) -- the
// same operations on the same values as instance_setup.glsl, so the same bits
// (use_record_setup below).
void store_shading(uint id, Setup s) {
    bool origin = s.ray_c == vec3(0.0);
    uint flags = s.flags | (origin ? FLAG_OFFSET_ORIGIN : 0u);
    vec3 color = srgb_to_linear(unpackUnorm4x8(s.color).rgb);
    int at = int(id * 8u);
    imageStore(shading_record_stores, at, floatBitsToUint(vec4(s.ray_x, s.k.w)));
    imageStore(shading_record_stores, at + 1, floatBitsToUint(vec4(s.ray_y, s.misc.x)));
    imageStore(shading_record_stores, at + 2,
               uvec4(floatBitsToUint(vec3(s.ray_origin, s.depth.w)), flags));
    if (!origin) {
        imageStore(shading_record_stores, at + 3, floatBitsToUint(vec4(s.ray_c, s.misc.y)));
    }
    if (ORTHOGRAPHIC) {
        imageStore(shading_record_stores, at + 4, floatBitsToUint(vec4(s.depth.xyz, 0.0)));
    }
    imageStore(shading_record_stores, at + 5, floatBitsToUint(vec4(s.to_normal[0], color.r)));
    imageStore(shading_record_stores, at + 6, floatBitsToUint(vec4(s.to_normal[1], color.g)));
    imageStore(shading_record_stores, at + 7, floatBitsToUint(vec4(s.to_normal[2], color.b)));
}
#endif

#ifdef CULL_PASS
void store_setup(uint id, Setup s) {
    uint flags = (s.culled ? FOOTPRINT_CULLED : 0u) | (s.screen_polygon ? FOOTPRINT_SCREEN : 0u);
    footprints[id] = FootprintRecord(s.centre, s.axis1, s.axis2, s.quad_z, flags);
    store_shading(id, s);
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

#if defined(SETUP_ONCE_FRAGMENT) || defined(SHADING_RECORD_READER)
// The globals the hit test reads (impostor_state.glsl) from a shading record: what
// instance_setup.glsl hands down, derived as store_shading says, so the same bits.
void use_record_setup(ShadingRecord rec) {
    float r = rec.radius, u = rec.inv_eye_dist, cz = rec.centre_depth;
    v_ray_x = rec.ray_x;
    v_ray_y = rec.ray_y;
    v_flags = rec.flags;
    bool origin = (v_flags & FLAG_OFFSET_ORIGIN) != 0u;
    v_ray_origin = rec.ray_origin;
    // ray_c and |e~| are read only for rays that are pixel directions.
    v_ray_c = origin ? vec3(0.0) : rec.ray_c;
    float eye_dist = origin ? 0.0 : rec.eye_dist;
    v_k = ORTHOGRAPHIC ? vec4(1.0, 1.0, 0.0, 1.0)
        : (origin ? vec4(1.0, r * cz, cz * u, r) : vec4(0.0, r, u, r));
    // Only orthographic depth reads g.
    v_depth = vec4(ORTHOGRAPHIC ? rec.depth_gradient : vec3(0.0), cz);
    float depth_scale = origin && !ORTHOGRAPHIC ? cz : 1.0;
    v_misc = vec4(u, eye_dist, r * r, depth_scale);
}

// What shading a hit needs, from the same record.
void use_record_shading(ShadingRecord rec) {
    v_to_normal = mat3(rec.to_normal_x, rec.to_normal_y, rec.to_normal_z);
    v_color = vec3(rec.color_r, rec.color_g, rec.color_b);
}
#endif
