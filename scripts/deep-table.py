#!/usr/bin/env python3
"""The table of scripts/deep-scenes.sh from its folder: per scene our still and orbiting frame
(the plan's path), ray casts per visible pixel, the visible-pixel floor and Mitsuba 3's depth
AOV and raw primary rays, each the median over the runs; nothing typed by hand.

    python3 scripts/deep-table.py OUT
"""

import csv
import re
import statistics
import sys
from pathlib import Path

if len(sys.argv) != 2:
    sys.exit(__doc__)
out = Path(sys.argv[1])
runs = len(list(out.glob("orbit-run*/results.csv")))
if runs == 0:
    sys.exit(f"{out}: no orbit-run*/results.csv (run scripts/deep-scenes.sh first)")
def ours(motion, scene, method, column):
    values = []
    for run in range(1, runs + 1):
        for row in csv.DictReader((out / f"{motion}-run{run}" / "results.csv").open()):
            if row["scene"] == scene and row["method"] == method and row[column]:
                values.append(float(row[column]))
    return statistics.median(values) if values else None
def tracer(scene, way):
    values = []
    for run in range(1, runs + 1):
        path = out / f"tracer-{scene}-run{run}.txt"
        if path.exists():
            m = re.search(rf"^{way}: ([0-9.]+) ms", path.read_text(), re.M)
            if m:
                values.append(float(m.group(1)))
    return statistics.median(values) if values else None
fmt = lambda v, unit=" ms": "-" if v is None else f"{v:.1f}{unit}"
print((out / "machine.txt").read_text().strip())
print(f"\nmedians over {runs} runs (bench --frames 9; Mitsuba 9 warm frames, orbiting 0.5 deg/frame)\n")
print("| scene | ours still (path) | ours orbiting (path) | ray casts / visible px, still / orbiting | floor-visible | Mitsuba depth AOV | Mitsuba raw rays | orbiting / raw rays |")
print("|---|---:|---:|---:|---:|---:|---:|---:|")
for scene in ("lattice", "md-liquid"):
    still, orbit = ours("still", scene, "impostor", "wall_ms"), ours("orbit", scene, "impostor", "wall_ms")
    # The plan's paths over every run (several where runs learned differently).
    paths = []
    for motion in ("still", "orbit"):
        taken = sorted({r["plan_path"] for run in range(1, runs + 1)
                        for r in csv.DictReader((out / f"{motion}-run{run}" / "results.csv").open())
                        if r["scene"] == scene and r["method"] == "impostor"})
        paths.append(", ".join(taken) or "?")
    casts = (ours("still", scene, "impostor", "ray_casts_per_visible_pixel"), ours("orbit", scene, "impostor", "ray_casts_per_visible_pixel"))
    floor = ours("orbit", scene, "floor-visible", "wall_ms")
    depth, rays = tracer(scene, "depth"), tracer(scene, "rays")
    ratio = "-" if orbit is None or rays is None else f"{orbit / rays:.2f}"
    print(f"| {scene} | {fmt(still)} ({paths[0]}) | {fmt(orbit)} ({paths[1]}) | {casts[0] or 0:.2f} / {casts[1] or 0:.2f} | {fmt(floor)} | {fmt(depth)} | {fmt(rays)} | {ratio} |")
