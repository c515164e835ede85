#version 450
// Host-engine mesh (examples/embed): a coloured triangle list transformed by one matrix.
// The colour is passed flat so every pixel of a face has exactly that face's colour.

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 color;

layout(push_constant) uniform PushConstants {
    mat4 view_projection;
} pc;

layout(location = 0) flat out vec3 v_color;

void main() {
    gl_Position = pc.view_projection * vec4(position, 1.0);
    v_color = color;
}
