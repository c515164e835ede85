// Per-instance set-up records written by the culling pre-pass (cull.comp, CULL_SETUP) and
// read by the PRESET_SETUP builds of the impostor stages, at the instance's index. Needs
// instance_setup.glsl first.
//
// Footprint (binding 7, 32 bytes): what the vertex stage needs.
// Shading (binding 6, 128 bytes): what the fragment stage needs, packed into 8 vec4 so a
// million instances fit in the 128 MiB storage-buffer range every device supports.

#ifdef CULL_PASS
#define RECORD_ACCESS writeonly
#else
#define RECORD_ACCESS readonly
#endif

// Footprint flags.
const uint FOOTPRINT_CULLED = 1u;
const uint FOOTPRINT_SCREEN = 2u;
// Shading flag: ray_c holds the ray origin o (offset mode) rather than the constant term.
const uint FLAG_OFFSET_ORIGIN = 4u;

#if defined(CULL_PASS) || defined(PRESET_SETUP_VERTEX)
layout(std430, set = 0, binding = 7) RECORD_ACCESS buffer Footprints {
    vec4 footprints[];  // 2 per instance: (centre, axis1), (axis2, quad_z, flags)
};
#endif
#if defined(CULL_PASS) || defined(PRESET_SETUP_FRAGMENT)
layout(std430, set = 0, binding = 6) RECORD_ACCESS buffer ShadingRecords {
    vec4 shading[];     // 8 per instance, see store_setup
};
#endif

#ifdef CULL_PASS
void store_setup(uint id, Setup s) {
    uint flags = (s.culled ? FOOTPRINT_CULLED : 0u) | (s.screen_polygon ? FOOTPRINT_SCREEN : 0u);
    footprints[2u * id] = vec4(s.centre, s.axis1);
    footprints[2u * id + 1u] = vec4(s.axis2, s.quad_z, uintBitsToFloat(flags));
    // Offset mode has ray_c = 0; otherwise o = 0: one slot holds whichever is not zero. The
    // fragment stage derives k0 (1 in offset mode, else 0), r^2 = r r and the depth scale
    // (cz in perspective offset mode, else 1) exactly as instance_setup.glsl sets them, and
    // needs only the first four vec4 to test for a hit in perspective (five orthographic).
    bool origin = s.ray_c == vec3(0.0);
    vec3 ray_c = origin ? vec3(s.ray_origin, 0.0) : s.ray_c;
    uint shading_flags = s.flags | (origin ? FLAG_OFFSET_ORIGIN : 0u);
    vec3 color = srgb_to_linear(unpackUnorm4x8(s.color).rgb);
    uint base = 8u * id;
    shading[base] = vec4(s.ray_x, s.k.y);
    shading[base + 1u] = vec4(s.ray_y, s.k.z);
    shading[base + 2u] = vec4(ray_c, s.k.w);
    shading[base + 3u] = vec4(s.misc.x, s.depth.w, uintBitsToFloat(shading_flags), s.misc.y);
    shading[base + 4u] = vec4(s.depth.xyz, 0.0);
    shading[base + 5u] = vec4(s.to_normal[0], color.r);
    shading[base + 6u] = vec4(s.to_normal[1], color.g);
    shading[base + 7u] = vec4(s.to_normal[2], color.b);
}
#endif

#ifdef PRESET_SETUP_VERTEX
Setup load_footprint(uint id) {
    Setup s;
    vec4 a = footprints[2u * id], b = footprints[2u * id + 1u];
    uint flags = floatBitsToUint(b.w);
    s.culled = (flags & FOOTPRINT_CULLED) != 0u;
    s.screen_polygon = (flags & FOOTPRINT_SCREEN) != 0u;
    s.centre = a.xy;
    s.axis1 = a.zw;
    s.axis2 = b.xy;
    s.quad_z = b.z;
    s.offset_mode = true; // only Gumhold's world quad reads it, and that is never preset
    return s;
}
#endif
