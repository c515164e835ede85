#version 460
#extension GL_GOOGLE_include_directive : require
// The shipped impostor fragment shader reading the set-up the culling pre-pass computed.
#define SETUP_ONCE
#include "ellipsoid_frag.glsl"
