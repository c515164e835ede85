// The shading records the compute splat stored (SPLAT_SETUP_ONCE, binding 6), as its resolve
// reads them: binding 14 views the chunk's records as R32G32B32A32_UINT texels, eight a record
// (`ShadingRecord`'s 128 bytes, its vec4 rows in order), read through texel fetches because
// lavapipe gathers a texel fetch's lanes and reads a storage buffer lane by lane (design §7).
// Needs impostor_state.glsl first (the globals the records fill).
#define SHADING_RECORD_READER
#include "setup_records.glsl"

layout(set = 0, binding = 14) uniform utextureBuffer shading_record_texels;

// The record of instance `id` (chunk-relative); rows the set-up does not read are not fetched
// once the compiler sees them unused (the depth gradient outside orthographic cameras).
ShadingRecord shading_record(uint id) {
    int at = int(id * 8u);
    uvec4 r0 = texelFetch(shading_record_texels, at);
    uvec4 r1 = texelFetch(shading_record_texels, at + 1);
    uvec4 r2 = texelFetch(shading_record_texels, at + 2);
    uvec4 r3 = texelFetch(shading_record_texels, at + 3);
    uvec4 r4 = texelFetch(shading_record_texels, at + 4);
    vec4 r5 = uintBitsToFloat(texelFetch(shading_record_texels, at + 5));
    vec4 r6 = uintBitsToFloat(texelFetch(shading_record_texels, at + 6));
    vec4 r7 = uintBitsToFloat(texelFetch(shading_record_texels, at + 7));
    return ShadingRecord(
        uintBitsToFloat(r0.xyz), uintBitsToFloat(r0.w),
        uintBitsToFloat(r1.xyz), uintBitsToFloat(r1.w),
        uintBitsToFloat(r2.xy), uintBitsToFloat(r2.z), r2.w,
        uintBitsToFloat(r3.xyz), uintBitsToFloat(r3.w),
        uintBitsToFloat(r4.xyz), uintBitsToFloat(r4.w),
        r5.xyz, r5.w,
        r6.xyz, r6.w,
        r7.xyz, r7.w);
}
