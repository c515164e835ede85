#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
// The compute splat's resolve, inside the host's pass, once per chunk: each pixel whose
// visibility key names an instance of this chunk takes that instance's set-up -- the record
// the splat stored (SPLAT_SETUP_ONCE), or derived again with the vertex stage's own function
// -- and its hit with the fragment stage's, shades it once and writes colour, normal, ID and
// the depth in the camera's convention, so host meshes drawn before depth-test against it
// exactly.
#define SETUP_HERE
#include "ellipsoid_common.glsl"
#include "silhouette_bounds.glsl"
#include "instance_setup.glsl"
#include "shading.glsl"
#include "fragment_counter.glsl"
#include "impostor_state.glsl"

layout(location = 0) out vec4 out_color;
#ifdef AUX_OUTPUTS
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
#endif

#include "impostor_hit.glsl"
#include "visibility.glsl"
#include "shading_record_texels.glsl"

void main() {
    vec2 pixel = camera_pixel(gl_FragCoord.xy);
    uvec2 p = uvec2(pixel);
    uint64_t key = packUint2x32(key_words(p.y * image_size().x + p.x));
    uint id = visibility_id(key) - cam.first_instance;
    if (key == visibility_empty() || id >= chunk_instances()) {
        discard;
    }
    count_fragment();
    if (SPLAT_SETUP_ONCE) {
        ShadingRecord record = shading_record(id);
        use_record_setup(record);
        use_record_shading(record);
    } else {
        use_setup(setup_instance(load_instance(id)));
    }
    float z;
    vec3 n;
    if (!impostor_pixel(pixel, z, n)) {
        // Not reached where the stages compute the hit alike (lavapipe: tested bit for bit);
        // a driver that rounds differently gets a lit pixel, never a hole.
        n = -cam.forward;
    }
    // The depth the splat kept, which decided this pixel.
    gl_FragDepth = uintBitsToFloat(uint(key >> 32));
    out_color = vec4(shade(n, v_color), 1.0);
#ifdef AUX_OUTPUTS
    out_normal = vec4(n, 0.0);
    out_id = id + cam.first_instance;
#endif
}
