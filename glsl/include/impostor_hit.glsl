// The impostor's exact hit at a pixel centre, shared by the fragment stage
// (ellipsoid_frag.glsl), the compute splat (splat.comp) and its resolve (resolve.frag). Needs
// ellipsoid_common.glsl, shading.glsl and impostor_state.glsl first.
// Closed-form ray/ellipsoid hit in the silhouette frame (docs/design.md §4.2):
//   p = (r q, -(u + alpha)) / (1 + u alpha),  alpha = sqrt(1 - |q|^2)
// is both the hit point and the parameter-space normal, with no cancellation at any distance.
// Handles near-plane caps and a camera inside the ellipsoid.

// Textbook baseline: |O + t D|^2 = 1 in parameter space with the discriminant b^2 - ac, all in
// float32. v_depth.xyz holds the centre relative to the eye, v_to_normal the world->parameter map.
bool hit_textbook(vec2 pixel, out float depth, out vec3 normal, out bool cap) {
    float near = cam.near_plane;
    vec3 origin, dir;
    pixel_ray(pixel, origin, dir);
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

// The ray through the pixel centre `pixel` in the silhouette frame (see
// instance_setup.glsl).
vec3 frame_ray(vec2 pixel) {
    vec2 d = pixel_ndc(pixel) - v_ray_origin;
    return v_ray_x * d.x + v_ray_y * d.y + v_ray_c;
}

// The closed form in the silhouette frame (see the top of this file).
bool hit_stable(vec2 pixel, out float depth, out vec3 normal, out bool cap) {
    vec3 v_ray = frame_ray(pixel);
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


// Whether instance v_id shows at the pixel centre `pixel`, and if so its depth-buffer
// value z (clamped to [0, 1]), its normal in the silhouette frame (world with TEXTBOOK) and
// whether it is the near-plane cap. Needs only the hit part of the set-up.
bool impostor_depth(vec2 pixel, out float z, out vec3 normal, out bool cap) {
    float near = cam.near_plane;
    float depth;
    bool hit = TEXTBOOK ? hit_textbook(pixel, depth, normal, cap)
                        : hit_stable(pixel, depth, normal, cap);
    // Beyond the far plane (a finite one) nothing shows; rounding at the planes is clamped.
    z = depth_value(cap ? near : depth);
    bool shows = hit && z >= -1e-6 && z <= 1.0 + 1e-6;
    z = clamp(z, 0.0, 1.0);
    return shows;
}

// The unit world normal of a hit `impostor_depth` found (its silhouette-frame normal and
// whether it is the cap); loads the shading part of the set-up.
vec3 impostor_world_normal(vec3 normal, bool cap) {
    load_shading();
    if (!TEXTBOOK) {
        normal = v_to_normal * normal;
    }
    if (cap) {
        return -cam.forward;
    } else if (FAST_NORMAL) {
        return normal / (abs(normal.x) + abs(normal.y) + abs(normal.z));
    }
    return normalize(normal);
}

// What instance v_id shows at the pixel centre `pixel` (in the camera's image:
// `camera_pixel(gl_FragCoord.xy)` in the fragment stages): false where it shows nothing; else its depth-buffer value z in the camera's
// convention and its unit world normal n. Loads the shading part of the set-up only for a
// hit. The fragment stage, the compute splat and the resolve all decide with this function.
bool impostor_pixel(vec2 pixel, out float z, out vec3 n) {
    vec3 normal;
    bool cap;
    n = vec3(0.0);
    if (!impostor_depth(pixel, z, normal, cap)) {
        return false;
    }
    n = impostor_world_normal(normal, cap);
    return true;
}
