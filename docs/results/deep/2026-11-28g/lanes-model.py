#!/usr/bin/env python3
"""How much of its 8 lanes a subgroup of the first splat uses (docs/deep-scenes.md, "Lanes
sorted by size"): a model of `lattice`'s glyphs -- semi-axes uniform in [0.1, 0.45], uniform
random rotations, orthographic, scaled to SCALE pixels per unit times a uniform factor in
[0.5, 1.5] for the spread of depths -- walked as splat.comp walks them: row by row over the
pixel centres of the silhouette ellipse, the 8 lanes of a subgroup in step, so a row index
costs the longest of the lanes' rows there. Lane use = pixel centres walked / (8 x steps).
Glyphs 8 at a time in their generated order, then with each 64 sorted by their pixel count.
Standard library only; seeded.

    python3 lanes-model.py
"""
import math
import random


def rotation(rng):
    """A uniform random rotation matrix (from a normalised Gaussian quaternion)."""
    w, x, y, z = (rng.gauss(0, 1) for _ in range(4))
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def glyph_rows(rng, scale):
    """Pixel centres per row of one glyph's silhouette ellipse (rows from its top)."""
    radii = [rng.uniform(0.1, 0.45) * scale for _ in range(3)]
    r = rotation(rng)
    # Screen rows of M = R diag(radii): the silhouette is {p : p^T S^-1 p <= 1}, S = P P^T.
    p = [[r[i][k] * radii[k] for k in range(3)] for i in range(2)]
    s00 = sum(v * v for v in p[0])
    s01 = sum(a * b for a, b in zip(p[0], p[1]))
    s11 = sum(v * v for v in p[1])
    det = s00 * s11 - s01 * s01
    i00, i01, i11 = s11 / det, -s01 / det, s00 / det
    half_height = math.sqrt(s11)
    rows = []
    y = math.floor(-half_height) + 0.5
    while y < half_height:
        # i00 x^2 + 2 i01 x y + i11 y^2 <= 1
        b, c = 2 * i01 * y, i11 * y * y - 1
        d = b * b - 4 * i00 * c
        if d < 0:
            rows.append(0)
        else:
            lo = math.ceil((-b - math.sqrt(d)) / (2 * i00))
            hi = math.floor((-b + math.sqrt(d)) / (2 * i00))
            rows.append(max(0, hi - lo + 1))
        y += 1.0
    return rows


def steps(group):
    """Steps of 8 lanes walking `group` in step, row index by row index."""
    height = max(len(g) for g in group)
    return sum(max(g[i] if i < len(g) else 0 for g in group) for i in range(height))


def main():
    rng = random.Random(1)
    for scale in (15, 30):
        glyphs = [glyph_rows(rng, scale * rng.uniform(0.5, 1.5)) for _ in range(64 * 40)]
        work = sum(sum(g) for g in glyphs)
        in_order = sum(steps(glyphs[i:i + 8]) for i in range(0, len(glyphs), 8))
        in_size = 0
        for w in range(0, len(glyphs), 64):
            block = sorted(glyphs[w:w + 64], key=lambda g: -sum(g))
            in_size += sum(steps(block[i:i + 8]) for i in range(0, 64, 8))
        print(f"{scale} px per unit: lane use {work / (8 * in_order):.2f} in order, "
              f"{work / (8 * in_size):.2f} with each 64 sorted by size")


main()
