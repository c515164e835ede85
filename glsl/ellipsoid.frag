#version 460
#extension GL_GOOGLE_include_directive : require
// Closed-form ray/ellipsoid hit in the silhouette frame (DESIGN.md section 3):
//   p = (r q, -(u + alpha)) / (1 + u alpha),  alpha = sqrt(1 - |q|^2)
// is both the hit point and the parameter-space normal, with no cancellation at any distance.
// Handles near-plane caps and a camera inside the ellipsoid; writes reversed-Z depth.
#include "ellipsoid_common.glsl"

// Outputs beyond colour only when the pipeline has those attachments.
layout(constant_id = 1) const bool AUX_OUTPUTS = true;

layout(location = 0) in vec3 v_ray;
layout(location = 1) flat in vec4 v_k;
layout(location = 2) flat in vec4 v_depth;
layout(location = 3) flat in vec4 v_misc;
layout(location = 4) flat in mat3 v_to_normal;
layout(location = 7) flat in uint v_id;
layout(location = 8) flat in uint v_flags;
layout(location = 9) flat in vec3 v_color;

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out uint out_id;
// Written depth never exceeds the quad's (reversed-Z: nearer is larger).
layout(depth_less) out float gl_FragDepth;

vec3 shade(vec3 n, vec3 to_eye, vec3 base) {
    vec3 r = cam.right_sx.xyz, up = cam.up_sy.xyz, f = cam.forward.xyz;
    float ka = cam.material.x, kd = cam.material.y, ks = cam.material.z, shininess = cam.material.w;
    // A head-light at the eye and a key light above-left, fixed to the camera.
    vec3 key = normalize(-0.45 * r + 0.65 * up - 0.6 * f);
    vec3 lights[2] = vec3[2](to_eye, key);
    float weights[2] = float[2](0.55, 0.6);
    vec3 color = ka * base;
    for (int i = 0; i < 2; i++) {
        vec3 l = lights[i];
        float nl = dot(n, l);
        if (nl > 0.0) {
            vec3 h = normalize(l + to_eye);
            float spec = pow(max(dot(n, h), 0.0), shininess);
            color += weights[i] * (kd * nl * base + ks * spec * cam.specular_color.rgb);
        }
    }
    return color;
}

// The pixel's ray relative to the eye: origin offset (orthographic) and direction with unit
// forward component, so the ray parameter is the view depth.
void pixel_ray(out vec3 origin, out vec3 dir) {
    vec2 ndc = vec2(gl_FragCoord.x * cam.viewport.x - 1.0, 1.0 - gl_FragCoord.y * cam.viewport.y);
    vec3 offset = ndc.x * cam.right_sx.w * cam.right_sx.xyz + ndc.y * cam.up_sy.w * cam.up_sy.xyz;
    origin = ORTHOGRAPHIC ? offset : vec3(0.0);
    dir = ORTHOGRAPHIC ? cam.forward.xyz : cam.forward.xyz + offset;
}

// Textbook baseline: |O + t D|^2 = 1 in parameter space with the discriminant b^2 - ac, all in
// float32. v_depth.xyz holds the centre relative to the eye, v_to_normal the world->parameter map.
bool hit_textbook(out float depth, out vec3 normal, out bool cap) {
    float near = cam.eye_near.w;
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

// The closed form in the silhouette frame (see the top of this file).
bool hit_stable(out float depth, out vec3 normal, out bool cap) {
    float near = cam.eye_near.w;
    vec3 g = v_depth.xyz;
    float cz = v_depth.w;
    cap = false;
    depth = near;
    normal = vec3(0.0);
    if ((v_flags & FLAG_EYE_INSIDE) != 0u) {
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
    normal = v_to_normal * p;
    // Perspective: the ray parameter t with unit forward step is the view depth, and from the
    // eye at z = -|e~| it is t = r^2 scale / ((1 + u alpha) den) -- a product of positive
    // factors, so no cancellation when the surface is much nearer than the centre.
    // Orthographic rays start on the eye plane: depth = cz + g.p.
    float r2 = v_misc.z, scale = v_misc.w;
    depth = ORTHOGRAPHIC ? cz + dot(g, p) : r2 * scale / ((1.0 + u * alpha) * den);
    if (depth < near) {
        if ((v_flags & FLAG_MAY_CAP) == 0u) {
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
    float near = cam.eye_near.w;
    float depth;
    vec3 normal;
    bool cap;
    bool hit = TEXTBOOK ? hit_textbook(depth, normal, cap) : hit_stable(depth, normal, cap);
    if (!hit) {
        discard;
    }
    vec3 f = cam.forward.xyz;
    vec3 n = cap ? -f : normalize(normal);
    gl_FragDepth = cap ? 1.0 : near / depth;

    // Direction to the eye for lighting: the pixel's ray reversed.
    vec3 origin, dir;
    pixel_ray(origin, dir);
    vec3 to_eye = -normalize(dir);
    out_color = vec4(shade(n, to_eye, v_color), 1.0);
    if (AUX_OUTPUTS) {
        out_normal = vec4(n, 0.0);
        out_id = v_id;
    }
}
