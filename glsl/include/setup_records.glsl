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
    // Offset mode (o, ray_c = 0) is the common case: its hit test needs the first three vec4
    // only; the fourth holds ray_c (and |e~|) for rays that are pixel directions, the fifth g
    // for orthographic depth. The fragment stage derives k = (1, r cz, cz u, r) in perspective
    // offset mode, (0, r, u, r) otherwise, (1, 1, 0, 1) orthographic; r^2 = r r; and the depth
    // scale (cz in perspective offset mode, else 1) -- the same operations on the same values
    // as instance_setup.glsl, so the same bits.
    bool origin = s.ray_c == vec3(0.0);
    uint shading_flags = s.flags | (origin ? FLAG_OFFSET_ORIGIN : 0u);
    vec3 color = srgb_to_linear(unpackUnorm4x8(s.color).rgb);
    uint base = 8u * id;
    shading[base] = vec4(s.ray_x, s.k.w);
    shading[base + 1u] = vec4(s.ray_y, s.misc.x);
    shading[base + 2u] = vec4(s.ray_origin, s.depth.w, uintBitsToFloat(shading_flags));
    shading[base + 3u] = vec4(s.ray_c, s.misc.y);
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
