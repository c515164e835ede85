// The nearest view depth any hit of an instance can have, with a margin that float32 rounding
// cannot close: the culling's occlusion tests and the visible-first splat's tile skip compare
// it with depths already held. Needs ellipsoid_common.glsl first.

// Relative depth gap that float32 rounding (in the pre-pass and the fragment stage) cannot
// close.
const float DEPTH_GAP = 1e-4;

// View depth of the instance's centre and its half-extent along the view axis.
vec2 depth_range(Instance inst) {
    vec3 f = cam.forward;
    vec3 a_f = (transpose(instance_rotation(inst)) * f) * instance_radii(inst);
    return vec2(dot(inst.center, f) - cam.eye_view.z, length(a_f));
}

// The ellipsoid's nearest view depth, moved nearer by DEPTH_GAP of the depths involved: far
// more than float32 rounds the difference (its terms may be far larger than it) or the hit.
float nearest_with_gap(Instance inst) {
    vec2 z = depth_range(inst);
    return z.x - z.y - DEPTH_GAP * (abs(z.x) + z.y);
}

// Whether a pixel holding a hit at depth-buffer bits `held` hides every hit of an instance
// whose `nearest_with_gap` is `nearest`: that lies beyond the near plane and its depth-buffer
// value more than two float steps beyond `held`, so the instance can neither win nor tie the
// pixel. Never for an instance that may reach the near plane (a cap), nor for an empty pixel.
bool hides_every_hit(uint held, float nearest) {
    if (!(nearest > cam.near_plane) || held == (REVERSED_Z ? 0u : 0xffffffffu)) {
        return false;
    }
    // Bits of a depth in [0, 1] (never of -0.0, whose sign bit would order it last).
    float depth = depth_value(nearest);
    uint bound = depth > 0.0 ? floatBitsToUint(min(depth, 1.0)) : 0u;
    return REVERSED_Z ? bound + 2u < held : bound > 2u && held < bound - 2u;
}
