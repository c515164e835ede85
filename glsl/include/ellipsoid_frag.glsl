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

// Sample `s` of COVERAGE_SAMPLES in the Vulkan standard locations, from the pixel's top-left
// corner (2 and 4 samples; the plan shades per sample for other counts).
vec2 standard_sample_position(int s) {
    if (COVERAGE_SAMPLES == 2) {
        return s == 0 ? vec2(0.75, 0.75) : vec2(0.25, 0.25);
    }
    const vec2 four[4] = vec2[](vec2(0.375, 0.125), vec2(0.875, 0.375), vec2(0.125, 0.625),
                                vec2(0.625, 0.875));
    return four[s];
}

// Shaded once per pixel on a multisampled target: which samples the glyph covers, each by the
// exact hit at its position (caps and planes included); the pixel's one depth, the nearest of
// the covered samples' (so wherever the glyph lies in front of host geometry at every sample
// it covers, it shows at all of them: silhouettes stay exact against meshes behind); and its
// unit world normal at the first covered sample, where it is shaded (the standard positions
// all lie 0.4 px from the centre). Returns the coverage mask (0: nothing).
int pixel_coverage(out float nearest, out vec3 n) {
    vec2 corner = floor(gl_FragCoord.xy);
    nearest = REVERSED_Z ? 0.0 : 1.0;
    n = vec3(0.0);
    vec3 first_normal = vec3(0.0);
    bool first_cap = false;
    int mask = 0;
    for (int s = 0; s < COVERAGE_SAMPLES; s++) {
        float z;
        vec3 normal;
        bool cap;
        if (impostor_depth(corner + standard_sample_position(s), z, normal, cap)) {
            if (mask == 0) {
                first_normal = normal;
                first_cap = cap;
            }
            mask |= 1 << s;
            nearest = REVERSED_Z ? max(nearest, z) : min(nearest, z);
        }
    }
    if (mask != 0) {
        n = impostor_world_normal(first_normal, first_cap);
    }
    return mask;
}

void main() {
    count_fragment();
    load_setup();
    float z;
    vec3 n;
    if (COVERAGE_SAMPLES > 1) {
        int mask = pixel_coverage(z, n);
        if (mask == 0) {
            discard;
        }
        gl_SampleMask[0] = mask;
    } else {
        // The stage declares the output, so every invocation writes it: the coverage as is.
        gl_SampleMask[0] = gl_SampleMaskIn[0];
        if (!impostor_pixel(gl_FragCoord.xy, z, n)) {
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
