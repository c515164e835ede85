// Shading shared by every fragment shader: Blinn-Phong with Gumhold's material parameters,
// and the pixel's ray of the camera contract. Needs ellipsoid_common.glsl first.

// Schlick's rational stand-in for pow(x, n): close in shape, no transcendental functions.
float specular_lobe(float x, float n) {
    return x / (n - n * x + x);
}

// Blinn-Phong with a head-light and a key light above-left, both fixed to the camera, seen by
// an infinitely distant viewer: in view axes (r, u, -f) every light and half vector is a
// constant, so a fragment pays for three dot products and two divisions. `n` is the unit
// world normal.
vec3 shade(vec3 n, vec3 base) {
    vec3 nv = vec3(dot(n, cam.right), dot(n, cam.up), -dot(n, cam.forward));
    float ka = cam.ambient, kd = cam.diffuse, ks = cam.specular, shininess = cam.shininess;
    // key = normalize(-0.45, 0.65, 0.6); half = normalize(key + (0, 0, 1)).
    const vec3 KEY = vec3(-0.45, 0.65, 0.6) / 0.99247166;
    const vec3 HALF_KEY = (KEY + vec3(0.0, 0.0, 1.0)) / length(KEY + vec3(0.0, 0.0, 1.0));
    float head = max(nv.z, 0.0);
    float side = max(dot(nv, KEY), 0.0);
    float spec_head = specular_lobe(head, shininess);
    float spec_side = side > 0.0 ? specular_lobe(max(dot(nv, HALF_KEY), 0.0), shininess) : 0.0;
    return ka * base
        + 0.55 * (kd * head * base + ks * spec_head * cam.specular_color)
        + 0.6 * (kd * side * base + ks * spec_side * cam.specular_color);
}

// The pixel's ray relative to the eye: origin offset (orthographic) and direction with unit
// forward component, so the ray parameter is the view depth.
void pixel_ray(vec2 pixel, out vec3 origin, out vec3 dir) {
    vec2 ndc = pixel_ndc(pixel);
    vec3 offset = ndc.x * cam.ndc_scale_x * cam.right + ndc.y * cam.ndc_scale_y * cam.up;
    origin = ORTHOGRAPHIC ? offset : vec3(0.0);
    dir = ORTHOGRAPHIC ? cam.forward : cam.forward + offset;
}

