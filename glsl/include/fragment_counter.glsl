// With COUNT_FRAGMENTS (build.rs builds every fragment shader so with the `research` feature) each fragment shader
// invocation adds one to a counter, before any discard: the exact number of pixels shaded,
// which lavapipe's pipeline statistics do not give (they count whole 4x4 blocks). The second
// word counts the compute splat's ray casts (COUNT_RAY_CASTS, splat.comp).
#if defined(COUNT_FRAGMENTS) || defined(SPLAT_PASS)
layout(std430, set = 0, binding = 1) buffer FragmentCounter {
    uint shaded_fragments;
    uint compute_ray_casts;
};
#endif
#ifdef COUNT_FRAGMENTS
void count_fragment() {
    atomicAdd(shaded_fragments, 1u);
}
#else
void count_fragment() {
}
#endif
