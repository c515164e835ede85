// The impostor fragment stage, shared by ellipsoid.frag, ellipsoid_setup_once.frag and the
// benchmark's research/ellipsoid_flat_depth.frag.
// Closed-form ray/ellipsoid hit in the silhouette frame (docs/design.md §4.2):
//   p = (r q, -(u + alpha)) / (1 + u alpha),  alpha = sqrt(1 - |q|^2)
// is both the hit point and the parameter-space normal, with no cancellation at any distance.
// Handles near-plane caps and a camera inside the ellipsoid. Writes the depth in the camera's
// convention (depth_value) unless FLAT_DEPTH is defined (then the quad's constant depth stands: a measured approximation).
#include "ellipsoid_common.glsl"
#include "shading.glsl"
#include "fragment_counter.glsl"

// The instance's set-up (include/instance_setup.glsl): flat varyings, or with SETUP_ONCE
// the record the culling pre-pass wrote, read at the start of main.
layout(location = 7) flat in uint v_id;
#ifdef SETUP_ONCE
#define SETUP_ONCE_FRAGMENT
#include "setup_records.glsl"
vec3 v_ray_x, v_ray_y, v_ray_c;
vec2 v_ray_origin;
vec4 v_k, v_depth, v_misc;
mat3 v_to_normal;
uint v_flags;
vec3 v_color;

// What the hit test needs (see store_setup for the layout and the derived values).
void load_setup() {
    float r = shading[v_id].radius, u = shading[v_id].inv_eye_dist;
    float cz = shading[v_id].centre_depth, eye_dist = 0.0;
    v_ray_x = shading[v_id].ray_x;
    v_ray_y = shading[v_id].ray_y;
    v_flags = shading[v_id].flags;
    bool origin = (v_flags & FLAG_OFFSET_ORIGIN) != 0u;
    v_ray_origin = shading[v_id].ray_origin;
    v_ray_c = vec3(0.0);
    if (!origin) {
        v_ray_c = shading[v_id].ray_c;
        eye_dist = shading[v_id].eye_dist;
    }
    v_k = ORTHOGRAPHIC ? vec4(1.0, 1.0, 0.0, 1.0)
        : (origin ? vec4(1.0, r * cz, cz * u, r) : vec4(0.0, r, u, r));
    // Only orthographic depth reads g.
    v_depth = vec4(ORTHOGRAPHIC ? shading[v_id].depth_gradient : vec3(0.0), cz);
    float depth_scale = origin && !ORTHOGRAPHIC ? cz : 1.0;
    v_misc = vec4(u, eye_dist, r * r, depth_scale);
}

// What shading a hit needs: loaded only for fragments that hit.
void load_shading() {
    v_to_normal = mat3(shading[v_id].to_normal_x, shading[v_id].to_normal_y,
                       shading[v_id].to_normal_z);
    v_color = vec3(shading[v_id].color_r, shading[v_id].color_g, shading[v_id].color_b);
}
#else
layout(location = 0) flat in vec3 v_ray_x;
layout(location = 10) flat in vec3 v_ray_y;
layout(location = 11) flat in vec3 v_ray_c;
layout(location = 12) flat in vec2 v_ray_origin;
layout(location = 1) flat in vec4 v_k;
layout(location = 2) flat in vec4 v_depth;
layout(location = 3) flat in vec4 v_misc;
layout(location = 4) flat in mat3 v_to_normal;
layout(location = 8) flat in uint v_flags;
layout(location = 9) flat in vec3 v_color;

void load_setup() {}
void load_shading() {}
#endif

layout(location = 0) out vec4 out_color;
#ifdef AUX_OUTPUTS
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
#endif
#ifndef FLAT_DEPTH
// Written depth never exceeds the quad's (reversed-Z: nearer is larger).
layout(depth_less) out float gl_FragDepth;
#endif

// Textbook baseline: |O + t D|^2 = 1 in parameter space with the discriminant b^2 - ac, all in
// float32. v_depth.xyz holds the centre relative to the eye, v_to_normal the world->parameter map.
bool hit_textbook(out float depth, out vec3 normal, out bool cap) {
    float near = cam.near_plane;
    vec3 origin, dir;
    pixel_ray(origin, dir);
    mat3 m = v_to_normal;
    vec3 o = m * (origin - v_depth.xyz);
    vec3 d = m * dir;
    float a = dot(d, d), b = dot(o, d), c = dot(o, o) - 1.0;
    float disc = b * b - a * c;
    if (disc < 0.0) {
        return false;
    }
    float root = sqrt(disc);
    depth = (-b - root) / a;
    cap = false;
    if (depth < near) {
        if ((-b + root) / a < near) {
            return false;
        }
        cap = true;
    }
    normal = transpose(m) * (o + depth * d);
    return true;
}

// This pixel's ray in the silhouette frame (see instance_setup.glsl).
vec3 frame_ray() {
    vec2 ndc = vec2(gl_FragCoord.x * cam.ndc_per_pixel.x - 1.0, 1.0 - gl_FragCoord.y * cam.ndc_per_pixel.y);
    vec2 d = ndc - v_ray_origin;
    return v_ray_x * d.x + v_ray_y * d.y + v_ray_c;
}

// The closed form in the silhouette frame (see the top of this file).
bool hit_stable(out float depth, out vec3 normal, out bool cap) {
    vec3 v_ray = frame_ray();
    float near = cam.near_plane;
    vec3 g = v_depth.xyz;
    float cz = v_depth.w;
    cap = false;
    depth = near;
    normal = vec3(0.0);
    if (!NO_CAPS && (v_flags & FLAG_EYE_INSIDE) != 0u) {
        // Eye inside: from O = (0, 0, -|e~|) along D the ray leaves the unit sphere once ahead;
        // the pixel shows the cap wherever that exit lies beyond the near plane.
        float eye_dist = v_misc.y;
        vec3 o = vec3(0.0, 0.0, -eye_dist);
        vec3 d = v_ray;
        float dd = dot(d, d), b = dot(o, d), c0 = (1.0 - eye_dist) * (1.0 + eye_dist);
        float s = sqrt(b * b + dd * c0);
        float t = b > 0.0 ? c0 / (b + s) : (s - b) / dd;
        // D has unit forward component in view space, so t is the exit's view depth.
        cap = true;
        return t >= near;
    }
    float den = v_k.x + v_k.z * v_ray.z;
    if (!(den > 0.0)) {
        return false; // the ray points away from the ellipsoid
    }
    vec2 q = v_k.y * v_ray.xy / den;
    float qq = dot(q, q);
    if (!(qq < 1.0)) {
        return false;
    }
    float u = v_misc.x, r = v_k.w;
    float alpha = sqrt(1.0 - qq);
    vec3 p = vec3(r * q, -(u + alpha)) / (1.0 + u * alpha);
    normal = p; // the caller maps it to the world (after load_shading)
    // Perspective: the ray parameter t with unit forward step is the view depth, and from the
    // eye at z = -|e~| it is t = r^2 scale / ((1 + u alpha) den) -- a product of positive
    // factors, so no cancellation when the surface is much nearer than the centre.
    // Orthographic rays start on the eye plane: depth = cz + g.p.
    float r2 = v_misc.z, scale = v_misc.w;
    depth = ORTHOGRAPHIC ? cz + dot(g, p) : r2 * scale / ((1.0 + u * alpha) * den);
    if (depth < near) {
        if (NO_CAPS || (v_flags & FLAG_MAY_CAP) == 0u) {
            return false;
        }
        // Entered before the near plane: a cap if the ray leaves after it.
        float exit_depth = ORTHOGRAPHIC ? cz + dot(g, vec3(q, alpha)) : r2 * scale / ((1.0 - u * alpha) * den);
        cap = true;
        return exit_depth >= near;
    }
    return true;
}

void main() {
    count_fragment();
    load_setup();
    float near = cam.near_plane;
    float depth;
    vec3 normal;
    bool cap;
    bool hit = TEXTBOOK ? hit_textbook(depth, normal, cap) : hit_stable(depth, normal, cap);
    // Beyond the far plane (a finite one) nothing shows; rounding at the planes is clamped.
    float z = depth_value(cap ? near : depth);
    if (!hit || z < -1e-6 || z > 1.0 + 1e-6) {
        discard;
    }
    load_shading();
    if (!TEXTBOOK) {
        normal = v_to_normal * normal;
    }
    vec3 f = cam.forward;
    vec3 n;
    if (cap) {
        n = -f;
    } else if (FAST_NORMAL) {
        n = normal / (abs(normal.x) + abs(normal.y) + abs(normal.z));
    } else {
        n = normalize(normal);
    }
#ifndef FLAT_DEPTH
    gl_FragDepth = clamp(z, 0.0, 1.0);
#endif

    out_color = vec4(shade(n, v_color), 1.0);
#ifdef AUX_OUTPUTS
    out_normal = vec4(n, 0.0);
    out_id = v_id + cam.first_instance;
#endif
}
