#version 460
#extension GL_GOOGLE_include_directive : require
// Sample 0 of the multisampled depth attachment (D32_SFLOAT), as its float bits.
#define SAMPLE_TEXTURE texture2DMS
#include "sample_zero.glsl"

uint sample_zero_word(ivec2 pixel) {
    return floatBitsToUint(texelFetch(multisampled, pixel, 0).r);
}
