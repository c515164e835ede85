// The pixel centres a splatted glyph may cover: those within its silhouette ellipse's bounding
// box, widened by a twentieth of a pixel (more than float32 moves the bounds of a glyph on
// screen): the hit decides each of them, and outside the box no hit can be. Shared by the
// compute splat (splat.comp) and the benchmark's tiled splat (research/tiled_bins.comp).
// Needs ellipsoid_common.glsl and instance_setup.glsl first.

// The box [lo, hi] (inclusive, clipped to the image) of set-up `f`; false where it is not
// known (the glyph reaches the eye plane: its box is the whole screen). An empty box has lo
// above hi in some axis.
bool splat_pixel_box(Setup f, out ivec2 lo, out ivec2 hi) {
    ivec2 size = ivec2(image_size());
    lo = ivec2(0);
    hi = size - 1;
    bool bounds_known = f.bounded;
    if (f.bounded) {
        // The silhouette is centre + cos(t) axis1 + sin(t) axis2 (screen-plane units).
        vec2 half_extent = vec2(length(vec2(f.axis1.x, f.axis2.x)),
                                length(vec2(f.axis1.y, f.axis2.y)));
        vec2 sxy = vec2(cam.ndc_scale_x, cam.ndc_scale_y);
        vec2 a = image_ndc((f.centre - half_extent) / sxy), b = image_ndc((f.centre + half_extent) / sxy);
        vec2 px_lo = vec2(a.x + 1.0, 1.0 - b.y) * vec2(size) * 0.5 - 0.05;
        vec2 px_hi = vec2(b.x + 1.0, 1.0 - a.y) * vec2(size) * 0.5 + 0.05;
        bounds_known = !any(isnan(px_lo)) && !any(isnan(px_hi));
        // Pixel x's centre is x + 0.5.
        lo = max(lo, ivec2(ceil(clamp(px_lo, vec2(-2.0), vec2(size) + 2.0) - 0.5)));
        hi = min(hi, ivec2(floor(clamp(px_hi, vec2(-2.0), vec2(size) + 2.0) - 0.5)));
    }
    return bounds_known;
}
