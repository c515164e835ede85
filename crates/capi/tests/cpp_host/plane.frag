#version 450
// Pure green and unlit, so the test tells the plane's pixels from the glyphs' by colour.
layout(location = 0) out vec4 color;
void main() { color = vec4(0.0, 1.0, 0.0, 1.0); }
