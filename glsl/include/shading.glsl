// Shading shared by every fragment shader: Blinn-Phong with Gumhold's material parameters,
// and the pixel's ray of the camera contract. Needs ellipsoid_common.glsl first.

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

