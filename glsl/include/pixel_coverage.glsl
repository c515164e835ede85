// Pixel-rate coverage on a multisampled target (COVERAGE_SAMPLES 2 or 4): the fragment stage
// runs once per pixel and decides here which samples the glyph covers, the pixel's one depth
// and its normal. Needs impostor_hit.glsl first.
//
// Depth: the nearest covered sample's. Wherever the glyph lies in front of host geometry at
// every sample it covers, it then shows at all of them, so silhouettes stay exact against
// meshes behind. The pixel is shaded at that sample (the standard positions lie 0.35 px (2
// samples) and 0.4 px (4) from the centre).
//
// lavapipe runs both sides of a divergent branch, so the two ways are chosen at compile time:
// - in perspective, with nothing in front of the near plane and no far plane, the silhouette
//   alone decides each sample (a quadratic form per sample, no division), and the hit is
//   computed once, at the nearest covered sample (NO_CAPS keeps every glyph beyond the near
//   plane by a margin far above float32 rounding, so the full hit's near-plane rejection
//   could not apply);
// - otherwise each sample runs the full hit (caps, eye inside and both planes included; the
//   benchmark's textbook hit too, whose frame differs).
const bool SILHOUETTE_DECIDES = !ORTHOGRAPHIC && !TEXTBOOK && NO_CAPS && !FAR_PLANE;

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

// The silhouette's test per sample. hit_stable's ray r = frame_ray(p) meets the ellipsoid
// where den = k.x + k.z r.z > 0 and |q| < 1 for q = k.y r.xy / den, that is where
// f = den^2 - k.y^2 |r.xy|^2 > 0; then den alpha = sqrt(f), and the hit's view depth is
// r^2 scale / (den + u sqrt(f)). Both r.xy and den are affine in the window position, so each
// sample steps from the pixel centre's.
int silhouette_coverage(out float nearest, out vec3 n) {
    vec3 ray = frame_ray(camera_pixel(gl_FragCoord.xy));
    float den = v_k.x + v_k.z * ray.z;
    // Window x grows with NDC x, window y against NDC y.
    vec3 step_x = v_ray_x * cam.ndc_per_pixel.x, step_y = -v_ray_y * cam.ndc_per_pixel.y;
    vec2 den_step = v_k.z * vec2(step_x.z, step_y.z);
    float k2 = v_k.y * v_k.y, u = v_misc.x;
    int mask = 0;
    float most = 0.0; // den + u sqrt(f) of the nearest covered sample
    vec2 best_xy = vec2(0.0);
    float best_den = 1.0, best_root = 0.0;
    for (int s = 0; s < COVERAGE_SAMPLES; s++) {
        vec2 o = standard_sample_position(s) - 0.5;
        vec2 xy = ray.xy + o.x * step_x.xy + o.y * step_y.xy;
        float d = den + dot(o, den_step);
        float f = d * d - k2 * dot(xy, xy);
        if (d > 0.0 && f > 0.0) {
            float root = sqrt(f);
            float nearness = d + u * root;
            if (mask == 0 || nearness > most) {
                most = nearness;
                best_xy = xy;
                best_den = d;
                best_root = root;
            }
            mask |= 1 << s;
        }
    }
    // The hit at the nearest covered sample, as hit_stable computes it from q and alpha.
    vec2 q = v_k.y * best_xy / best_den;
    float alpha = best_root / best_den;
    float r = v_k.w, r2 = v_misc.z, scale = v_misc.w;
    vec3 p = vec3(r * q, -(u + alpha)) / (1.0 + u * alpha);
    // Both computed, then selected (see the top of this file): an empty mask writes nothing
    // anyway, but its depth is the far one rather than a division by zero.
    float z = clamp(depth_value(r2 * scale / most), 0.0, 1.0);
    vec3 world = impostor_world_normal(p, false);
    nearest = mask != 0 ? z : (REVERSED_Z ? 0.0 : 1.0);
    n = mask != 0 ? world : vec3(0.0);
    return mask;
}

// Each sample's full hit.
int sample_coverage(out float nearest, out vec3 n) {
    vec2 corner = floor(camera_pixel(gl_FragCoord.xy));
    nearest = REVERSED_Z ? 0.0 : 1.0;
    n = vec3(0.0);
    vec3 nearest_normal = vec3(0.0);
    bool nearest_cap = false;
    int mask = 0;
    for (int s = 0; s < COVERAGE_SAMPLES; s++) {
        float z;
        vec3 normal;
        bool cap;
        if (impostor_depth(corner + standard_sample_position(s), z, normal, cap)) {
            if (mask == 0 || (REVERSED_Z ? z > nearest : z < nearest)) {
                nearest = z;
                nearest_normal = normal;
                nearest_cap = cap;
            }
            mask |= 1 << s;
        }
    }
    if (mask != 0) {
        n = impostor_world_normal(nearest_normal, nearest_cap);
    }
    return mask;
}

// Which samples the glyph covers (0: none), the pixel's depth-buffer value and unit world
// normal.
int pixel_coverage(out float nearest, out vec3 n) {
    return SILHOUETTE_DECIDES ? silhouette_coverage(nearest, n) : sample_coverage(nearest, n);
}
