"""What the Python binding costs over the Rust library on a million glyphs (a benchmark, not a
test): each frame uploads new arrays and renders them; the binding's share is the Python-side
wall time less the Rust library's own time for the same upload and frame (checking and shaping
the arrays, wrapping the outputs). Prints medians.

    target/python-venv/bin/python crates/python/bench_overhead.py [FRAMES]
"""

import statistics
import sys
import time

import numpy as np

import ellipsoid_splat as es

frames = int(sys.argv[1]) if len(sys.argv) > 1 else 9
n = 1_000_000
rng = np.random.default_rng(7)
renderer = es.Renderer()
camera = dict(eye=(0.0, 0.0, 60.0), target=(0.0, 0.0, 0.0), width=1280, height=720, near=1.0)
ratios, walls, rusts = [], [], []
for k in range(frames + 2):
    centers = rng.uniform(-20, 20, (n, 3))
    radii = rng.uniform(0.01, 0.03, (n, 3))
    rotations = rng.normal(size=(n, 4))
    rotations /= np.linalg.norm(rotations, axis=1, keepdims=True)
    colors = rng.uniform(0, 1, (n, 3))
    start = time.perf_counter()
    frame = renderer.render(centers, radii, rotations, colors, **camera)
    wall = (time.perf_counter() - start) * 1e3
    rust = renderer.upload_ms + frame.render_ms
    if k >= 2:  # warm
        walls.append(wall)
        rusts.append(rust)
        ratios.append(wall / rust)
print(f"{n} glyphs at 1280x720 on {renderer.device}, {frames} frames (new arrays each):")
print(f"Python {statistics.median(walls):.1f} ms, Rust library {statistics.median(rusts):.1f} ms,"
      f" binding overhead {100 * (statistics.median(ratios) - 1):.1f} %")
