#version 450
// The host's mesh: the square [-S, S]^2 of the plane y = 0, two triangles, no vertex buffer.
layout(push_constant) uniform Push { mat4 clip_from_world; float half_size; } push;
void main() {
    const vec2 corners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1),
                                   vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 c = corners[gl_VertexIndex] * push.half_size;
    gl_Position = push.clip_from_world * vec4(c.x, 0.0, c.y, 1.0);
}
