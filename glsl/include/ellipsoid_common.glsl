// Shared by every shader: the CPU-GPU layouts (gpu_layout.glsl), the instance buffer and
// the helpers the stages have in common.
//
// Coordinates: instance centres are relative to a scene origin chosen on the CPU near the data;
// the eye arrives already rotated into view axes (computed in float64), so float32 never
// subtracts two large nearly-equal positions and a centre's view coordinates are exact to
// float32 rounding of small numbers.

// texelFetch and textureSize on the uniform texel buffers (utextureBuffer: a SPIR-V image of
// dimension Buffer with no sampler, as Vulkan's texel buffers are).
#extension GL_EXT_samplerless_texture_functions : require

#include "gpu_layout.glsl"

// How far a footprint reaches beyond the exact silhouette bounds, in pixels: a sliver, so
// float rounding never drops a covered pixel centre.
const float QUAD_MARGIN_PX = 0.01;

// The camera's image size in pixels: 2 / (2 / W) in float32 rounds back to W exactly for
// every W <= 16384.
uvec2 image_size() {
    return uvec2(round(2.0 / cam.ndc_per_pixel));
}

// A fragment's position in the camera's image: gl_FragCoord less the viewport's origin (whole
// pixels, so exact).
vec2 camera_pixel(vec2 frag_coord) {
    return frag_coord - vec2(cam.viewport_origin & 0xffffu, cam.viewport_origin >> 16);
}

// The shaders' NDC (y up; screen plane over ndc_scale, §3.2) that camera pixel position p
// samples: Vulkan's NDC of the image plus the principal point's and the jitter's shift.
vec2 pixel_ndc(vec2 p) {
    return vec2(p.x * cam.ndc_per_pixel.x - 1.0, 1.0 - p.y * cam.ndc_per_pixel.y) + cam.ndc_shift;
}

// Vulkan's NDC of the image (y up, as the pixel contract's) of the shaders' NDC point v.
vec2 image_ndc(vec2 v) {
    return v - cam.ndc_shift;
}

// The depth-buffer value of view depth d in the host's convention: a + b d + c / d
// (src/depth.rs). Reversed Z with an infinite far plane is (0, 0, near): exactly near / d.
float depth_value(float d) {
    return cam.depth_a + cam.depth_b * d + cam.depth_c / d;
}

// Clip z for a perspective vertex with clip w = d: depth_value(d) * d (b is 0 in perspective).
float depth_clip_z(float d) {
    return cam.depth_a * d + cam.depth_c;
}

// The draw's chunk of the instance buffer, read as 16-byte texels (R32G32B32A32_UINT) through
// a uniform texel buffer (why: design §7).
layout(set = 0, binding = 0) uniform utextureBuffer instance_texels;

// Texels per instance: `Instance` is 48 bytes, `CompactInstance` 32.
uint instance_texel_count() {
    return COMPACT ? 2u : 3u;
}

// Instances in the draw's chunk.
uint chunk_instances() {
    return uint(textureSize(instance_texels)) / instance_texel_count();
}

// Instance `i` of the draw's chunk, in either layout.
Instance load_instance(uint i) {
    uint at = i * instance_texel_count();
    uvec4 head = texelFetch(instance_texels, int(at));
    uvec4 second = texelFetch(instance_texels, int(at + 1u));
    Instance inst;
    inst.center = uintBitsToFloat(head.xyz);
    inst.color = head.w;
    if (!COMPACT) {
        inst.rotation = uintBitsToFloat(second);
        uvec4 third = texelFetch(instance_texels, int(at + 2u));
        inst.radii = uintBitsToFloat(third.xyz);
        inst.unused = uintBitsToFloat(third.w);
        return inst;
    }
    // CompactInstance: the quaternion as 4 snorm16, the radii as 3 halves.
    // Quantised: renormalise, so the rotation stays orthonormal.
    inst.rotation = normalize(vec4(unpackSnorm2x16(second.x), unpackSnorm2x16(second.y)));
    vec3 radii = vec3(unpackHalf2x16(second.z), unpackHalf2x16(second.w).x);
    inst.radii = radii * cam.radius_unit;
    inst.unused = 0.0;
    return inst;
}

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
    return quat_to_mat3(inst.rotation);
}
vec3 instance_radii(Instance inst) {
    return inst.radii.xyz;
}

// sRGB transfer function, decoded: instance colours are display (sRGB) values, shading is linear.
vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}
