#version 460
#extension GL_GOOGLE_include_directive : require
// Sample 0 of the multisampled instance-ID attachment (R32_UINT).
#define SAMPLE_TEXTURE utexture2DMS
#include "sample_zero.glsl"

uint sample_zero_word(ivec2 pixel) {
    return texelFetch(multisampled, pixel, 0).r;
}
