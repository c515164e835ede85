// The pre-pass's keep bits and group slots (binding 4, `CullGroups`): per group of
// CULL_GROUP instances, 8 words of keep bits, then (after all groups' bits) each group's count
// of kept instances, which the SCAN step replaces by its first output slot. Written by the
// culling's CLASSIFY step, or by the compute splat for the glyphs it leaves to the draw.
// Needs the IndirectDraw block (for `total`) declared first.
const uint CULL_GROUP = 256u;
layout(std430, set = 0, binding = 4) buffer CullGroups {
    uint groups[];
};

// Groups of the chunk.
uint group_count() {
    return (total + CULL_GROUP - 1u) / CULL_GROUP;
}
