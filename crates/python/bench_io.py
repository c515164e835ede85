"""What float32 input and saving EXR cost (a benchmark, not a test): a million float32 glyphs
uploaded (median wall time, and the Python-side allocation peak that tracemalloc sees, which
counts NumPy's buffers but not Rust's), and a 1920 x 1080 depth and normal frame saved as EXR
(median wall time). Prints one line each.

    target/python-venv/bin/python crates/python/bench_io.py [REPEATS]
"""

import os
import statistics
import sys
import tempfile
import time
import tracemalloc

import numpy as np

import ellipsoid_splat as es

repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 5
renderer = es.Renderer()

n = 1_000_000
rng = np.random.default_rng(7)
centers = rng.uniform(-20, 20, (n, 3)).astype(np.float32)
radii = rng.uniform(0.01, 0.03, (n, 3)).astype(np.float32)
times = []
for _ in range(repeats):
    start = time.perf_counter()
    renderer.upload(centers, radii)
    times.append((time.perf_counter() - start) * 1e3)
    renderer.upload(centers[:1], radii[:1])  # so that the next upload is not skipped
tracemalloc.start()
renderer.upload(centers, radii)
_, peak = tracemalloc.get_traced_memory()
tracemalloc.stop()
print(f"upload of {n} float32 glyphs: {statistics.median(times):.0f} ms median of {repeats}, "
      f"Python-side allocation peak {peak / 1e6:.1f} MB (input arrays {(centers.nbytes + radii.nbytes) / 1e6:.0f} MB)")

# A real frame: depth +inf where nothing is hit, as a render gives it.
small = rng.uniform(-3, 3, (2000, 3))
renderer.upload(small, rng.uniform(0.1, 0.4, (2000, 3)))
frame = renderer.render_uploaded(eye=(0.0, 0.0, 12.0), target=(0.0, 0.0, 0.0), width=1920,
                                 height=1080)
with tempfile.TemporaryDirectory() as tmp:
    for what in ("depth", "normal"):
        path = os.path.join(tmp, f"{what}.exr")
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            frame.save(path, what)
            times.append((time.perf_counter() - start) * 1e3)
        print(f"Frame.save 1920x1080 {what} EXR: {statistics.median(times):.1f} ms median of "
              f"{repeats} ({os.path.getsize(path) / 1e6:.1f} MB)")
