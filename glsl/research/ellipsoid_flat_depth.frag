#version 460
#extension GL_GOOGLE_include_directive : require
// The `impostor-flat-depth` measurement: no per-fragment depth, the quad's nearest-point depth
// stands (cheaper, and keeps early depth testing), at the cost of wrong depth inside glyphs.
#define FLAT_DEPTH
#include "ellipsoid_frag.glsl"
