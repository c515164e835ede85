// Shared between ellipsoid.vert and ellipsoid.frag: camera push constants, the instance
// record, and the interface between the stages.
//
// Coordinates: instance centres are relative to a scene origin chosen on the CPU near the data;
// the eye arrives already rotated into view axes (computed in float64), so float32 never
// subtracts two large nearly-equal positions and a centre's view coordinates are exact to
// float32 rounding of small numbers.

// Must match `push_constants` in src/renderer.rs (8 x vec4 = 128 bytes).
layout(push_constant, std430) uniform CameraPush {
    vec4 eye_near;       // xyz: V (eye - scene origin), the eye in view axes, rounded once from
                         // float64 so view-space centres never lose the eye's precision; w: near
    vec4 right_sx;       // xyz: camera right r, w: NDC x -> screen-plane scale (tan(fovy/2) W/H or h/2 W/H)
    vec4 up_sy;          // xyz: camera up u,    w: NDC y -> screen-plane scale (tan(fovy/2) or h/2)
    vec4 forward;        // xyz: view direction f, w: depth map a
    vec4 viewport;       // x: 2/W, y: 2/H (NDC per pixel), z: quad margin in pixels, w: depth map b
    vec4 material;       // ambient, diffuse, specular, shininess
    vec4 specular_color; // rgb, w: depth map c
    uvec4 chunk;         // x: index of the draw's first instance (scenes beyond one binding
                         // are drawn in chunks; instance indices in shaders are chunk-relative);
                         // y: float bits of the compact format's semi-axis unit
} cam;

// The depth-buffer value of view depth d in the host's convention: a + b d + c / d
// (src/depth.rs). Reversed Z with an infinite far plane is (0, 0, near): exactly near / d.
float depth_value(float d) {
    return cam.forward.w + cam.viewport.w * d + cam.specular_color.w / d;
}

// Clip z for a perspective vertex with clip w = d: depth_value(d) * d (b is 0 in perspective).
float depth_clip_z(float d) {
    return cam.forward.w * d + cam.specular_color.w;
}

// Must match `GpuInstance` in src/renderer.rs (48 bytes, std430).
struct Instance {
    vec3 center;   // relative to the scene origin
    uint color;    // sRGB-encoded RGBA8, packUnorm4x8 order
    vec4 rotation; // unit quaternion (x, y, z, w): local axes -> world
    vec4 radii;    // xyz semi-axes, w unused
};

layout(std430, set = 0, binding = 0) readonly buffer Instances {
    Instance instances[];
};

// The same binding read as 32-byte compact records (src/instances.rs): centre, colour,
// snorm16 quaternion, float16 semi-axes in units of cam.chunk.y.
layout(constant_id = 15) const bool COMPACT = false;
layout(std430, set = 0, binding = 0) readonly buffer CompactInstances {
    uvec4 compact_instances[]; // two per instance
};

// Instance `i` of the draw's chunk, in either layout.
Instance load_instance(uint i) {
    if (!COMPACT) {
        return instances[i];
    }
    uvec4 a = compact_instances[2u * i];
    uvec4 b = compact_instances[2u * i + 1u];
    Instance inst;
    inst.center = uintBitsToFloat(a.xyz);
    inst.color = a.w;
    // Quantised: renormalise, so the rotation stays orthonormal.
    inst.rotation = normalize(vec4(unpackSnorm2x16(b.x), unpackSnorm2x16(b.y)));
    vec3 radii = vec3(unpackHalf2x16(b.z), unpackHalf2x16(b.w).x);
    inst.radii = vec4(radii * uintBitsToFloat(cam.chunk.y), 0.0);
    return inst;
}

// Chosen when the pipeline is built (src/renderer.rs `Variant`).
layout(constant_id = 0) const bool ORTHOGRAPHIC = false;
layout(constant_id = 2) const bool TEXTBOOK = false;
// Footprint of an instance on screen (the `impostor*` methods of `bench`).
const int BOUNDS_TIGHT = 0;      // n-gon around the projected ellipse (4 corners: its oriented box)
const int BOUNDS_AXIS_RECT = 1;  // the projected ellipse's axis-aligned bounding rectangle
const int BOUNDS_WORLD_QUAD = 2; // Gumhold's square in the silhouette plane
layout(constant_id = 3) const int BOUNDS = BOUNDS_TIGHT;
layout(constant_id = 4) const int CORNERS = 4;
// The draw reads instance indices compacted by the culling pre-pass (cull.comp).
layout(constant_id = 8) const bool CULLED = false;
// Every instance is a sphere, stored with the identity rotation: rotation and per-axis radii
// drop out of the set-up (same bits as the general path, less work).
layout(constant_id = 13) const bool SPHERES = false;
#ifndef CULL_PASS
layout(std430, set = 0, binding = 2) readonly buffer VisibleInstances {
    uint visible_instances[];
};
#endif

// Per-instance flags passed to the fragment stage.
const uint FLAG_EYE_INSIDE = 1u;  // the eye is inside the ellipsoid: show the exit-side cap
const uint FLAG_MAY_CAP = 2u;     // the ellipsoid reaches in front of the near plane

// Rotation matrix (columns = local axes in world) of a unit quaternion.
mat3 quat_to_mat3(vec4 q) {
    float x2 = q.x + q.x, y2 = q.y + q.y, z2 = q.z + q.z;
    float xx = q.x * x2, yy = q.y * y2, zz = q.z * z2;
    float xy = q.x * y2, xz = q.x * z2, yz = q.y * z2;
    float wx = q.w * x2, wy = q.w * y2, wz = q.w * z2;
    return mat3(
        vec3(1.0 - (yy + zz), xy + wz, xz - wy),
        vec3(xy - wz, 1.0 - (xx + zz), yz + wx),
        vec3(xz + wy, yz - wx, 1.0 - (xx + yy)));
}

// The instance's rotation and semi-axes, as the set-up uses them.
mat3 instance_rotation(Instance inst) {
    return SPHERES ? mat3(1.0) : quat_to_mat3(inst.rotation);
}
vec3 instance_radii(Instance inst) {
    return SPHERES ? vec3(inst.radii.x) : inst.radii.xyz;
}

// sRGB transfer function, decoded: instance colours are display (sRGB) values, shading is linear.
vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}
