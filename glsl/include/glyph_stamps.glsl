// The visible-first splat's glyph stamps (binding 10, `GlyphStamps`; `glyph_stamps_bytes` in
// src/gpu_layout.rs): per glyph of the chunk two words, the last frame whose finished
// visibility buffer showed it at a pixel (`frame` of the IndirectDraw block; the pre-pass's
// MARK_SHOWN step writes it) and the last frame a splat pass left it to the draw. A stamp is
// a hint of what to splat first and a list key, never a proof: a stale or wrong one costs
// time, not a pixel. Needs the IndirectDraw block declared first.

layout(std430, set = 0, binding = 10) buffer GlyphStamps {
    uint glyph_stamps[];
};

// Whether the last frame that stamped what it showed (`shown`) showed glyph `i`.
bool shown_last_frame(uint i) {
    return shown != 0u && glyph_stamps[2u * i] == shown;
}

// Whether a splat pass of this frame left glyph `i` to the draw.
bool left_to_draw(uint i) {
    return glyph_stamps[2u * i + 1u] == frame;
}
