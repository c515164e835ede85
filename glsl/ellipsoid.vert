#version 460
#extension GL_GOOGLE_include_directive : require
// Expands instance gl_InstanceIndex into a screen-space quad that tightly bounds the projected
// silhouette (the bounding rectangle of the exact conic), and hands the fragment stage the
// pixel's ray in the ellipsoid's *silhouette frame* (Gumhold 2003): parameter space, where the
// ellipsoid is the unit sphere, rotated so +z points from the eye towards the centre.
//
// The interpolated attribute `v_ray` is affine in NDC (every vertex has w = 1), so the
// rasterizer interpolates it exactly. In the common case it is the pixel's offset from the
// projected centre mapped into the frame, so no large nearly-equal numbers are ever subtracted.
#include "ellipsoid_common.glsl"

layout(location = 0) noperspective out vec3 v_ray;
layout(location = 1) flat out vec4 v_k;             // k0, k1, k2, r: q = k1 ray.xy / (k0 + k2 ray.z)
layout(location = 2) flat out vec4 v_depth;         // xyz: g = frame vector with depth = cz + g.p; w: cz
layout(location = 3) flat out vec4 v_misc;          // u = 1/|e~|, |e~|, r^2 = 1 - u^2, depth scale (see the fragment stage)
layout(location = 4) flat out mat3 v_to_normal;     // frame point -> world normal (unnormalised)
layout(location = 7) flat out uint v_id;
layout(location = 8) flat out uint v_flags;
layout(location = 9) flat out vec3 v_color;

// Sorted slopes k (screen-plane x per unit depth) of the two planes through the eye that
// contain the screen line x = k z and touch the ellipsoid: the roots of
// |a - k b|^2 = (cx - k cz)^2 with a = A^T r, b = A^T f. The discriminant is written as
// |cz a - cx b|^2 - |a x b|^2, which has no cancellation when the ellipsoid is far away.
vec2 tangent_slopes(vec3 a, vec3 b, float c_side, float cz, float b_len) {
    float lead = (b_len - cz) * (b_len + cz); // < 0: the ellipsoid lies in front of the eye plane
    float half_b = dot(a, b) - c_side * cz;
    vec3 w = cz * a - c_side * b;
    vec3 ab = cross(a, b);
    float s = sqrt(max(dot(w, w) - dot(ab, ab), 0.0));
    float k1 = (half_b + s) / lead;
    float k2 = (half_b - s) / lead;
    return vec2(min(k1, k2), max(k1, k2));
}

// Orthonormal basis with the given unit z (Duff et al. 2017, branchless).
void frame_from_z(vec3 z, out vec3 x, out vec3 y) {
    float s = z.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + z.z);
    float b = z.x * z.y * a;
    x = vec3(1.0 + s * z.x * z.x * a, s * b, -s * z.x);
    y = vec3(b, s + z.y * z.y * a, -z.y);
}

void cull() {
    gl_Position = vec4(-2.0, -2.0, 0.0, 1.0); // all four corners equal: zero area, outside
}

void main() {
    Instance inst = instances[gl_InstanceIndex];
    v_id = uint(gl_InstanceIndex);
    v_color = srgb_to_linear(unpackUnorm4x8(inst.color).rgb);
    v_flags = 0u;

    vec3 r = cam.right_sx.xyz, u_axis = cam.up_sy.xyz, f = cam.forward.xyz;
    float sx = cam.right_sx.w, sy = cam.up_sy.w, near = cam.eye_near.w;
    mat3 R = quat_to_mat3(inst.rotation);
    mat3 Rt = transpose(R);
    vec3 radii = inst.radii.xyz;

    // Centre relative to the eye in view coordinates (cx, cy, cz): V centre - V eye.
    vec3 c = vec3(dot(inst.center, r), dot(inst.center, u_axis), dot(inst.center, f)) - cam.eye_near.xyz;
    // View axes in the ellipsoid's local axes; M = diag(1/radii) R^T maps world offsets to
    // parameter space, A^T = diag(radii) R^T maps view axes to half-extent vectors.
    vec3 lr = Rt * r, lu = Rt * u_axis, lf = Rt * f;
    vec3 m_r = lr / radii, m_u = lu / radii, m_f = lf / radii;
    vec3 a_r = lr * radii, a_u = lu * radii, a_f = lf * radii;
    float half_z = length(a_f); // half-extent along f: depths lie in cz +- half_z

    if (c.z + half_z < near) {
        cull(); // wholly in front of the near plane
        return;
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

    // Screen rectangle in NDC (x right, y up as in the pixel contract), and the mode.
    vec4 rect = vec4(-1.0, -1.0, 1.0, 1.0);
    bool offset_mode = true; // ray attribute = pixel offset from the projected centre
    float u = 0.0, rr = 1.0, depth_scale = 1.0;
    if (ORTHOGRAPHIC) {
        vec3 h = vec3(length(a_r), length(a_u), 0.0);
        rect = vec4((c.x - h.x) / sx, (c.y - h.y) / sy, (c.x + h.x) / sx, (c.y + h.y) / sy);
        v_k = vec4(1.0, 1.0, 0.0, 1.0);
    } else if (c.z > half_z) {
        // Wholly in front of the eye plane: the silhouette is a bounded conic.
        vec2 kx = tangent_slopes(a_r, a_f, c.x, c.z, half_z);
        vec2 ky = tangent_slopes(a_u, a_f, c.y, c.z, half_z);
        rect = vec4(kx.x / sx, ky.x / sy, kx.y / sx, ky.y / sy);
        u = 1.0 / eye_dist;
        rr = sqrt(r2);
        depth_scale = c.z;
        v_k = vec4(1.0, rr * c.z, c.z * u, rr);
    } else {
        // Crosses the eye plane: full screen, ray attribute = pixel direction.
        offset_mode = false;
        if (eye_dist > 1.0) {
            u = 1.0 / eye_dist;
            rr = sqrt(r2);
            v_k = vec4(0.0, rr, u, rr);
        } else {
            v_flags |= FLAG_EYE_INSIDE;
            v_k = vec4(0.0);
        }
    }
    if (c.z - half_z < near) {
        v_flags |= FLAG_MAY_CAP;
    }

    // Grow by a sliver of a pixel so float rounding never drops a covered pixel centre.
    vec2 margin = cam.viewport.z * cam.viewport.xy;
    rect = clamp(rect + vec4(-margin, margin), -1.0, 1.0);
    if (!(rect.x < rect.z && rect.y < rect.w)) {
        cull(); // off screen (or NaN from a degenerate instance)
        return;
    }

    int corner = gl_VertexIndex & 3;
    vec2 ndc = vec2((corner & 1) != 0 ? rect.z : rect.x, (corner & 2) != 0 ? rect.w : rect.y);

    vec3 s;
    if (ORTHOGRAPHIC) {
        s = vec3(ndc.x * sx - c.x, ndc.y * sy - c.y, 0.0);
    } else if (offset_mode) {
        s = vec3(ndc.x * sx - c.x / c.z, ndc.y * sy - c.y / c.z, 0.0);
    } else {
        s = vec3(ndc.x * sx, ndc.y * sy, 1.0);
    }
    // In offset mode the dropped centre term maps onto the frame's z axis only, by construction.
    v_ray = to_frame * (m_r * s.x + m_u * s.y + m_f * s.z);

    v_misc = vec4(u, eye_dist, rr * rr, depth_scale);
    if (TEXTBOOK) {
        // The baseline works in world axes: centre relative to the eye, and M = diag(1/a) R^T.
        v_depth = vec4(c.x * r + c.y * u_axis + c.z * f, c.z);
        v_to_normal = transpose(mat3(R[0] / radii.x, R[1] / radii.y, R[2] / radii.z));
    } else {
        v_depth = vec4(to_frame * a_f, c.z);
        v_to_normal = R * mat3(fx / radii, fy / radii, fz / radii);
    }

    // Constant quad depth at the nearest point (reversed-Z: near / depth), nudged nearer so
    // every fragment's written depth is <= it, which makes `depth_less` true.
    float nearest = c.z - half_z;
    float quad_z = nearest > near ? min(1.0, near / nearest * (1.0 + 1e-5)) : 1.0;
    // Vulkan's NDC y points down; the contract's points up.
    gl_Position = vec4(ndc.x, -ndc.y, quad_z, 1.0);
}
