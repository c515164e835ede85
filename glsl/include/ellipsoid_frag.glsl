// The impostor fragment stage, shared by ellipsoid.frag, ellipsoid_setup_once.frag and the
// benchmark's research/ellipsoid_flat_depth.frag.
// The hit itself is impostor_hit.glsl. Writes the depth in the camera's convention
// (depth_value) unless FLAT_DEPTH is defined (then the quad's constant depth stands: a
// measured approximation).
#include "ellipsoid_common.glsl"
#include "shading.glsl"
#include "fragment_counter.glsl"

// The instance drawn (chunk-relative), and its set-up: flat varyings, or with SETUP_ONCE the
// record the pre-pass wrote, read at the start of main.
layout(location = 7) flat in uint v_id;
#include "impostor_state.glsl"

layout(location = 0) out vec4 out_color;
#ifdef AUX_OUTPUTS
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
#endif
#ifndef FLAT_DEPTH
// Written depth never exceeds the quad's (reversed-Z: nearer is larger).
layout(depth_less) out float gl_FragDepth;
#endif

#include "impostor_hit.glsl"

#include "pixel_coverage.glsl"

void main() {
    count_fragment();
    load_setup();
    float z;
    vec3 n;
    if (COVERAGE_SAMPLES > 1) {
        // An empty mask writes no sample.
        gl_SampleMask[0] = pixel_coverage(z, n);
    } else {
        // The stage declares the output, so every invocation writes it: the coverage as is.
        gl_SampleMask[0] = gl_SampleMaskIn[0];
        if (!impostor_pixel(camera_pixel(gl_FragCoord.xy), z, n)) {
            discard;
        }
    }
#ifndef FLAT_DEPTH
    gl_FragDepth = z;
#endif

    out_color = vec4(shade(n, v_color), 1.0);
#ifdef AUX_OUTPUTS
    out_normal = vec4(n, 0.0);
    out_id = v_id + cam.first_instance;
#endif
}
