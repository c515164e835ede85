#version 460
// The compute splat's resolve: one triangle covering the whole image (its depth is replaced
// by the fragment stage's).
void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
