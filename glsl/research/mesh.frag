#version 460
#extension GL_GOOGLE_include_directive : require
// `mesh-L*`: Blinn-Phong with the interpolated vertex normal; depth from the rasterizer.
#include "ellipsoid_common.glsl"
#include "shading.glsl"
#include "fragment_counter.glsl"


layout(location = 0) in vec3 v_normal;
layout(location = 7) flat in uint v_id;
layout(location = 9) flat in vec3 v_color;

layout(location = 0) out vec4 out_color;
#ifdef AUX_OUTPUTS
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
#endif

void main() {
    count_fragment();
    vec3 n = normalize(v_normal);
    out_color = vec4(shade(n, v_color), 1.0);
#ifdef AUX_OUTPUTS
    out_normal = vec4(n, 0.0);
    out_id = v_id + cam.first_instance;
#endif
}
