#version 460
#extension GL_GOOGLE_include_directive : require
// The impostor vertex stage reading the set-up the culling pre-pass computed once per instance.
#define SETUP_ONCE
#include "impostor_vert.glsl"
