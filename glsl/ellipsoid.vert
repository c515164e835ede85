#version 460
#extension GL_GOOGLE_include_directive : require
// The impostor vertex stage computing each instance's set-up in every vertex.
#include "impostor_vert.glsl"
