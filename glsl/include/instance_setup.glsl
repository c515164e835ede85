// Per-instance set-up of the impostor: the footprint polygon on screen and everything the
// fragment stage needs, computed once per instance (by the culling pre-pass, or by each vertex
// of the instance when there is no pre-pass). Needs ellipsoid_common.glsl first.
//
// The ray is an affine function of the pixel's NDC, handed down as coefficients and evaluated
// per fragment from gl_FragCoord relative to the projected centre, so no large nearly-equal
// numbers are ever subtracted and the rasterizer's interpolation adds no error. Its frame is
// the ellipsoid's *silhouette frame* (Gumhold 2003): parameter space, where the ellipsoid is
// the unit sphere, rotated so +z points from the eye towards the centre.

struct Setup {
    bool culled;         // nothing of it can show
    // The footprint: centre + dir.x axis1 + dir.y axis2 over the n-gon's corners dir, or the
    // whole screen's polygon.
    vec2 centre;
    vec2 axis1;
    vec2 axis2;
    bool screen_polygon;
    float quad_z;        // constant depth-buffer value at the nearest point
    // Only for Gumhold's world quad (BOUNDS_WORLD_QUAD).
    bool bounded;
    bool offset_mode;
    vec3 fx, fy, fz, c, a_r, a_u, a_f;
    float rr, u;
    // For the fragment stage (see ellipsoid_frag.glsl).
    vec3 ray_x;          // ray = ray_x (ndc.x - o.x) + ray_y (ndc.y - o.y) + ray_c
    vec3 ray_y;
    vec3 ray_c;
    vec2 ray_origin;     // o: the projected centre's NDC (0 without offset mode)
    vec4 k;              // k0, k1, k2, r: q = k1 ray.xy / (k0 + k2 ray.z)
    vec4 depth;          // xyz: g = frame vector with depth = cz + g.p; w: cz
    vec4 misc;           // u = 1/|e~|, |e~|, r^2 = 1 - u^2, depth scale
    mat3 to_normal;      // frame point -> world normal (unnormalised)
    uint flags;
    uint color;          // sRGB-encoded RGBA8
};

// Hands `s` down to the v_* variables the hit reads (flat varyings in the vertex stage,
// globals where a pass computes the set-up itself): one list for both.
#define HAND_DOWN_SETUP(s) \
    v_ray_x = s.ray_x; \
    v_ray_y = s.ray_y; \
    v_ray_c = s.ray_c; \
    v_ray_origin = s.ray_origin; \
    v_k = s.k; \
    v_depth = s.depth; \
    v_misc = s.misc; \
    v_to_normal = s.to_normal; \
    v_flags = s.flags; \
    v_color = srgb_to_linear(unpackUnorm4x8(s.color).rgb)

// Orthonormal basis with the given unit z (Duff et al. 2017, branchless).
void frame_from_z(vec3 z, out vec3 x, out vec3 y) {
    float s = z.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + z.z);
    float b = z.x * z.y * a;
    x = vec3(1.0 + s * z.x * z.x * a, s * b, -s * z.x);
    y = vec3(b, s + z.y * z.y * a, -z.y);
}

const float SQRT2 = 1.41421356237310;

vec2 normalize_or(vec2 v, vec2 fallback) {
    float len = length(v);
    return len > 0.0 ? v / len : fallback;
}

// Axes (semi-axis vectors) of the ellipse with support function h(n)^2 = n^T S n, S =
// [s00 s01; s01 s11], det = det S computed as accurately as the caller can. The small axis is
// det / l1 plus a few roundings of l1, so thin ellipses are never underestimated.
void ellipse_axes(float s00, float s01, float s11, float det, out vec2 axis1, out vec2 axis2) {
    float h = length(vec2(0.5 * (s00 - s11), s01));
    float l1 = 0.5 * (s00 + s11) + h;
    float l2 = max(det / l1, 0.0) + 4.0 * 1.2e-7 * l1;
    // Eigenvector of l1 from whichever row has no cancellation; no trigonometry.
    vec2 d = s00 >= s11 ? vec2(0.5 * (s00 - s11) + h, s01) : vec2(s01, 0.5 * (s11 - s00) + h);
    d = normalize_or(d, vec2(1.0, 0.0));
    axis1 = sqrt(l1) * d;
    axis2 = sqrt(l2) * vec2(-d.y, d.x);
}


// Corner k of the regular CORNERS-gon circumscribing the unit circle: angle (2k+1) pi / n at
// radius 1 / cos(pi / n). Tables, so no vertex evaluates a trigonometric function.
const float RHO = CORNERS == 8 ? 1.0823922
    : (CORNERS == 6 ? 1.1547005 : (CORNERS == 3 ? 2.0 : 1.4142136));
vec2 corner_direction(int k) {
    if (CORNERS == 8) {
        const vec2 oct[8] = vec2[8](vec2(1.0, 0.41421356), vec2(0.41421356, 1.0),
            vec2(-0.41421356, 1.0), vec2(-1.0, 0.41421356), vec2(-1.0, -0.41421356),
            vec2(-0.41421356, -1.0), vec2(0.41421356, -1.0), vec2(1.0, -0.41421356));
        return oct[k];
    } else if (CORNERS == 6) {
        const vec2 hex[6] = vec2[6](vec2(1.0, 0.57735027), vec2(0.0, 1.1547005),
            vec2(-1.0, 0.57735027), vec2(-1.0, -0.57735027), vec2(0.0, -1.1547005),
            vec2(1.0, -0.57735027));
        return hex[k];
    } else if (CORNERS == 3) {
        const vec2 tri[3] = vec2[3](vec2(1.0, 1.7320508), vec2(-2.0, 0.0), vec2(1.0, -1.7320508));
        return tri[k];
    }
    const vec2 quad[4] = vec2[4](vec2(1.0, 1.0), vec2(-1.0, 1.0), vec2(-1.0, -1.0), vec2(1.0, -1.0));
    return quad[k];
}

Setup setup_instance(Instance inst) {
    Setup s;
    s.culled = false;
    s.screen_polygon = false;
    s.color = inst.color;
    s.flags = 0u;
    s.k = vec4(0.0);
    s.centre = s.axis1 = s.axis2 = vec2(0.0);
    s.quad_z = 0.0;

    vec3 r = cam.right, u_axis = cam.up, f = cam.forward;
    float sx = cam.ndc_scale_x, sy = cam.ndc_scale_y, near = cam.near_plane;
    mat3 R = instance_rotation(inst);
    mat3 Rt = transpose(R);
    vec3 radii = instance_radii(inst);

    // Centre relative to the eye in view coordinates (cx, cy, cz): V centre - V eye.
    vec3 c = vec3(dot(inst.center, r), dot(inst.center, u_axis), dot(inst.center, f)) - cam.eye_view;
    // View axes in the ellipsoid's local axes; M = diag(1/radii) R^T maps world offsets to
    // parameter space, A^T = diag(radii) R^T maps view axes to half-extent vectors.
    vec3 lr = Rt * r, lu = Rt * u_axis, lf = Rt * f;
    vec3 m_r = lr / radii, m_u = lu / radii, m_f = lf / radii;
    vec3 a_r = lr * radii, a_u = lu * radii, a_f = lf * radii;
    float half_z = length(a_f); // half-extent along f: depths lie in cz +- half_z

    if (c.z + half_z < near) {
        s.culled = true; // wholly in front of the near plane
        return s;
    }

    // Eye -> centre in parameter space, and the silhouette frame.
    vec3 e_par = m_r * c.x + m_u * c.y + m_f * c.z;
    // |e~|^2 - 1 decides how near the eye is to the surface: fused multiply-adds keep it exact
    // to rounding of the inputs even when the eye almost touches the ellipsoid.
    float eye_dist2 = fma(e_par.x, e_par.x, fma(e_par.y, e_par.y, e_par.z * e_par.z));
    float eye_dist = sqrt(eye_dist2);
    float r2 = (fma(e_par.x, e_par.x, fma(e_par.y, e_par.y, fma(e_par.z, e_par.z, -1.0)))) / eye_dist2;
    vec3 fz = ORTHOGRAPHIC ? normalize(m_f) : (eye_dist > 0.0 ? e_par / eye_dist : vec3(0.0, 0.0, 1.0));
    vec3 fx, fy;
    frame_from_z(fz, fx, fy);
    mat3 to_frame = transpose(mat3(fx, fy, fz));

    // The footprint: a convex polygon on the screen plane (slope units x/z, y/z for
    // perspective; world units for orthographic) that contains the silhouette. By default the
    // polygon circumscribes an ellipse around the whole screen.
    bool offset_mode = true; // ray attribute = pixel offset from the projected centre
    bool bounded = false;
    float u = 0.0, rr = 1.0, depth_scale = 1.0;
    vec2 centre = cam.ndc_shift * vec2(sx, sy); // the image's centre
    vec2 axis1 = vec2(sx, 0.0) * SQRT2, axis2 = vec2(0.0, sy) * SQRT2;
    if (ORTHOGRAPHIC) {
        s.k = vec4(1.0, 1.0, 0.0, 1.0);
        centre = c.xy;
        if (BOUNDS == BOUNDS_AXIS_RECT) {
            axis1 = vec2(length(a_r), 0.0);
            axis2 = vec2(0.0, length(a_u));
        } else {
            // Support function h(n)^2 = n^T S n of the projected ellipse.
            vec3 ru = cross(a_r, a_u);
            ellipse_axes(dot(a_r, a_r), dot(a_r, a_u), dot(a_u, a_u), dot(ru, ru), axis1, axis2);
        }
        bounded = true;
    } else if (c.z > half_z) {
        // Wholly in front of the eye plane: the silhouette is a bounded conic.
        u = 1.0 / eye_dist;
        rr = sqrt(r2);
        depth_scale = c.z;
        s.k = vec4(1.0, rr * c.z, c.z * u, rr);
        if (BOUNDS == BOUNDS_AXIS_RECT) {
            vec2 kx = tangent_slopes(a_r, a_f, c.x, c.z, half_z);
            vec2 ky = tangent_slopes(a_u, a_f, c.y, c.z, half_z);
            centre = 0.5 * vec2(kx.x + kx.y, ky.x + ky.y);
            axis1 = vec2(0.5 * (kx.y - kx.x), 0.0);
            axis2 = vec2(0.0, 0.5 * (ky.y - ky.x));
            bounded = true;
        } else if (BOUNDS == BOUNDS_TIGHT) {
            // Tangent lines n.x = k of the conic satisfy lead k^2 - 2 (n.beta) k + C(n) = 0, so
            // the conic's centre is beta / lead and its squared support function is
            // n^T S n with S lead^2 = Gram(w) - Gram(x), w_i = cz a_i - c_i a_f,
            // x_i = a_i x a_f: the cancellation-free form of the discriminant.
            float lead = (half_z - c.z) * (half_z + c.z);
            vec2 beta = vec2(dot(a_r, a_f) - c.x * c.z, dot(a_u, a_f) - c.y * c.z);
            vec3 w_r = c.z * a_r - c.x * a_f, w_u = c.z * a_u - c.y * a_f;
            vec3 x_r = cross(a_r, a_f), x_u = cross(a_u, a_f);
            float inv2 = 1.0 / (lead * lead);
            float s00 = (dot(w_r, w_r) - dot(x_r, x_r)) * inv2;
            float s01 = (dot(w_r, w_u) - dot(x_r, x_u)) * inv2;
            float s11 = (dot(w_u, w_u) - dot(x_u, x_u)) * inv2;
            centre = beta / lead;
            ellipse_axes(s00, s01, s11, s00 * s11 - s01 * s01, axis1, axis2);
            bounded = true;
        }
    } else {
        // Crosses the eye plane: full screen, ray attribute = pixel direction.
        offset_mode = false;
        if (eye_dist > 1.0) {
            u = 1.0 / eye_dist;
            rr = sqrt(r2);
            s.k = vec4(0.0, rr, u, rr);
        } else {
            s.flags |= FLAG_EYE_INSIDE;
            s.k = vec4(0.0);
        }
    }
    if (c.z - half_z < near) {
        s.flags |= FLAG_MAY_CAP;
    }

    // Grow by a sliver of a pixel so float rounding never drops a covered pixel centre.
    float margin = QUAD_MARGIN_PX * max(cam.ndc_per_pixel.x * sx, cam.ndc_per_pixel.y * sy);
    if (bounded) {
        axis1 += margin * normalize_or(axis1, vec2(1.0, 0.0));
        axis2 += margin * normalize_or(axis2, vec2(0.0, 1.0));
    }
    // Off screen: cull. Reaching far past the screen: use the screen's polygon instead, so no
    // vertex carries huge coordinates into the interpolation.
    vec2 reach = RHO * sqrt(axis1 * axis1 + axis2 * axis2) / vec2(sx, sy);
    vec2 mid = image_ndc(centre / vec2(sx, sy));
    if (bounded && BOUNDS != BOUNDS_WORLD_QUAD) {
        if (any(greaterThan(abs(mid) - reach, vec2(1.0)))) {
            s.culled = true;
            return s;
        }
        s.screen_polygon = any(greaterThan(abs(mid) + reach, vec2(4.0)));
    }
    s.centre = centre;
    s.axis1 = axis1;
    s.axis2 = axis2;
    s.bounded = bounded;
    s.offset_mode = offset_mode;
    s.fx = fx;
    s.fy = fy;
    s.fz = fz;
    s.c = c;
    s.a_r = a_r;
    s.a_u = a_u;
    s.a_f = a_f;
    s.rr = rr;
    s.u = u;

    // The pixel's screen-plane offset from the projected centre, sx (ndc.x - o.x), mapped into
    // the frame. In offset mode the dropped centre term lies on the frame's z axis only, by
    // construction; otherwise the ray is the pixel's direction (constant term m_f).
    s.ray_x = to_frame * (m_r * sx);
    s.ray_y = to_frame * (m_u * sy);
    if (ORTHOGRAPHIC) {
        s.ray_origin = c.xy / vec2(sx, sy);
        s.ray_c = vec3(0.0);
    } else if (offset_mode) {
        s.ray_origin = c.xy / (c.z * vec2(sx, sy));
        s.ray_c = vec3(0.0);
    } else {
        s.ray_origin = vec2(0.0);
        s.ray_c = to_frame * m_f;
    }

    s.misc = vec4(u, eye_dist, rr * rr, depth_scale);
    if (TEXTBOOK) {
        // The baseline works in world axes: centre relative to the eye, and M = diag(1/a) R^T.
        s.depth = vec4(c.x * r + c.y * u_axis + c.z * f, c.z);
        s.to_normal = transpose(mat3(R[0] / radii.x, R[1] / radii.y, R[2] / radii.z));
    } else {
        s.depth = vec4(to_frame * a_f, c.z);
        s.to_normal = R * mat3(fx / radii, fy / radii, fz / radii);
    }

    // Constant quad depth at the nearest point, nudged nearer so every fragment's written depth
    // is nearer-or-equal in depth order, which makes the conservative-depth layout true
    // (`depth_less` under reversed Z, `depth_greater` under standard Z).
    float nearest = c.z - half_z;
    s.quad_z = clamp(depth_value(max(near, nearest * (1.0 - 1e-5))), 0.0, 1.0);
    return s;
}

// The clip-space position of corner `vertex_index` of the instance's footprint polygon.
vec4 corner_position(Setup s, int vertex_index) {
    // This vertex's corner of the n-gon that circumscribes the unit circle, mapped onto the
    // ellipse (any affine image keeps it circumscribing, with the same area ratio). The strip
    // visits corners 0, 1, n-1, 2, n-2, ...
    int i = vertex_index;
    int k = i == 0 ? 0 : ((i & 1) != 0 ? (i + 1) / 2 : CORNERS - i / 2);
    vec2 dir = corner_direction(k);
    vec2 sxy = vec2(cam.ndc_scale_x, cam.ndc_scale_y);
    vec2 corner = s.screen_polygon ? cam.ndc_shift * sxy + dir * sxy * SQRT2
                                   : s.centre + dir.x * s.axis1 + dir.y * s.axis2;
    if (BOUNDS == BOUNDS_WORLD_QUAD && !ORTHOGRAPHIC && s.offset_mode) {
        // Gumhold's quad: the square around the silhouette circle in the silhouette plane,
        // projected (it inflates under perspective). Off the eye's side: full screen.
        vec2 q = (1.0 + 1e-4) * s.rr * dir;
        vec3 p = s.fx * q.x + s.fy * q.y - s.fz * s.u;
        vec3 x = s.c + vec3(dot(s.a_r, p), dot(s.a_u, p), dot(s.a_f, p));
        corner = x.z > 1e-6 * s.c.z ? x.xy / x.z : s.centre + dir.x * s.axis1 + dir.y * s.axis2;
    }

    if (s.culled || any(isnan(corner))) {
        return vec4(-2.0, -2.0, 0.0, 1.0); // all corners equal: zero area, outside
    }
    vec2 ndc = image_ndc(corner / sxy);
    // Vulkan's NDC y points down; the contract's points up.
    return vec4(ndc.x, -ndc.y, s.quad_z, 1.0);
}

