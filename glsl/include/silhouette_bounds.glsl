// Screen bounds of an ellipsoid's exact projected silhouette, shared by the impostor vertex
// stage and the culling pre-pass. Needs ellipsoid_common.glsl first.

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
    // The root away from zero directly, the other as C / q (Vieta, C = |a|^2 - c_side^2): no
    // cancellation as lead -> 0, when the ellipsoid nearly touches the eye plane.
    float q = half_b + (half_b >= 0.0 ? s : -s);
    float k1 = q / lead;
    float k2 = q != 0.0 ? (dot(a, a) - c_side * c_side) / q : (half_b - s) / lead;
    return vec2(min(k1, k2), max(k1, k2));
}

// The axis-aligned rectangle (x0, y0, x1, y1) in the image's NDC (y up as in the pixel
// contract, `image_ndc`) around the instance's silhouette, and false when nothing of it lies
// beyond the near plane. A silhouette reaching the eye plane gets the whole screen.
bool silhouette_rect(Instance inst, out vec4 rect) {
    vec3 r = cam.right, u_axis = cam.up, f = cam.forward;
    float sx = cam.ndc_scale_x, sy = cam.ndc_scale_y, near = cam.near_plane;
    mat3 Rt = transpose(instance_rotation(inst));
    vec3 radii = instance_radii(inst);
    vec3 c = vec3(dot(inst.center, r), dot(inst.center, u_axis), dot(inst.center, f)) - cam.eye_view;
    vec3 a_r = (Rt * r) * radii, a_u = (Rt * u_axis) * radii, a_f = (Rt * f) * radii;
    float half_z = length(a_f);
    rect = vec4(-1.0, -1.0, 1.0, 1.0);
    if (c.z + half_z < near) {
        return false;
    }
    if (ORTHOGRAPHIC) {
        vec2 h = vec2(length(a_r), length(a_u));
        rect = vec4((c.xy - h) / vec2(sx, sy), (c.xy + h) / vec2(sx, sy)) - cam.ndc_shift.xyxy;
    } else if (c.z > half_z) {
        vec2 kx = tangent_slopes(a_r, a_f, c.x, c.z, half_z);
        vec2 ky = tangent_slopes(a_u, a_f, c.y, c.z, half_z);
        rect = vec4(kx.x / sx, ky.x / sy, kx.y / sx, ky.y / sy) - cam.ndc_shift.xyxy;
    }
    return true;
}
