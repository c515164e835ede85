#version 460
#extension GL_GOOGLE_include_directive : require
// The shipped impostor fragment shader: exact hit, normal and depth.
#include "ellipsoid_frag.glsl"
