// Sample 0 of a multisampled attachment, copied into the offscreen read-back buffer: the
// depth (float bits) or the instance ID of each pixel. An integer or depth resolve with
// SAMPLE_ZERO would do it inside the pass, but one driver (NVIDIA 580) resolves R32_UINT from
// another sample where a pixel's samples differ; a fetch of sample 0 is what every driver
// must return. The including file defines SAMPLE_TEXTURE, the texture type to read.
#extension GL_EXT_samplerless_texture_functions : require

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 0) uniform SAMPLE_TEXTURE multisampled;

// The output's region of the read-back buffer: one 32-bit word per pixel, row-major.
layout(set = 0, binding = 1, std430) writeonly buffer SampleZeroWords {
    uint words[];
};

uint sample_zero_word(ivec2 pixel);

void main() {
    ivec2 size = textureSize(multisampled);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= size.x || pixel.y >= size.y) {
        return;
    }
    words[pixel.y * size.x + pixel.x] = sample_zero_word(pixel);
}
