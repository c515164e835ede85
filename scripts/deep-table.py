#!/usr/bin/env python3
"""The table of scripts/deep-scenes.sh from its folder: per scene our still and orbiting frame
(the plan's path), ray casts per visible pixel, the visible-pixel floor and Mitsuba 3's depth
AOV and raw primary rays, each the median over the runs; nothing typed by hand.

    python3 scripts/deep-table.py OUT

scripts/tables.py imports `table` and `median_of` to put the same figures into the docs.
"""

import csv
import re
import statistics
import sys
from pathlib import Path

SCENES = ("lattice", "md-liquid")


def run_count(out: Path) -> int:
    return len(list(out.glob("orbit-run*/results.csv")))


def median_of(out: Path, motion: str, scene: str, method: str, column: str):
    """The median over the runs of one column of `results.csv` (motion: still or orbit)."""
    values = []
    for run in range(1, run_count(out) + 1):
        for row in csv.DictReader((out / f"{motion}-run{run}" / "results.csv").open()):
            if row["scene"] == scene and row["method"] == method and row[column]:
                values.append(float(row[column]))
    return statistics.median(values) if values else None


def tracer(out: Path, scene: str, way: str):
    """Mitsuba's median over the runs, `way` being `depth` (the depth AOV) or `rays`."""
    values = []
    for run in range(1, run_count(out) + 1):
        path = out / f"tracer-{scene}-run{run}.txt"
        if path.exists():
            m = re.search(rf"^{way}: ([0-9.]+) ms", path.read_text(), re.M)
            if m:
                values.append(float(m.group(1)))
    return statistics.median(values) if values else None


def ms(v, unit=" ms") -> str:
    return "-" if v is None else f"{v:.1f}{unit}"


def table(out: Path) -> list[str]:
    runs = run_count(out)
    if runs == 0:
        sys.exit(f"{out}: no orbit-run*/results.csv (run scripts/deep-scenes.sh first)")
    lines = [f"medians over {runs} runs (bench --frames 9; Mitsuba 9 warm frames, orbiting 0.5 deg/frame)", "",
             "| scene | ours still (path) | ours orbiting (path) | ray casts / visible px, still / orbiting | floor-visible | Mitsuba depth AOV | Mitsuba raw rays | orbiting / raw rays |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for scene in SCENES:
        still = median_of(out, "still", scene, "impostor", "wall_ms")
        orbit = median_of(out, "orbit", scene, "impostor", "wall_ms")
        # The plan's paths over every run (several where runs learned differently).
        paths = []
        for motion in ("still", "orbit"):
            taken = sorted({r["plan_path"] for run in range(1, runs + 1)
                            for r in csv.DictReader((out / f"{motion}-run{run}" / "results.csv").open())
                            if r["scene"] == scene and r["method"] == "impostor"})
            paths.append(", ".join(taken) or "?")
        casts = (median_of(out, "still", scene, "impostor", "ray_casts_per_visible_pixel"),
                 median_of(out, "orbit", scene, "impostor", "ray_casts_per_visible_pixel"))
        floor = median_of(out, "orbit", scene, "floor-visible", "wall_ms")
        depth, rays = tracer(out, scene, "depth"), tracer(out, scene, "rays")
        ratio = "-" if orbit is None or rays is None else f"{orbit / rays:.2f}"
        lines.append(f"| {scene} | {ms(still)} ({paths[0]}) | {ms(orbit)} ({paths[1]}) | {casts[0] or 0:.2f} / {casts[1] or 0:.2f} | {ms(floor)} | {ms(depth)} | {ms(rays)} | {ratio} |")
    return lines


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    if run_count(out) == 0:
        sys.exit(f"{out}: no orbit-run*/results.csv (run scripts/deep-scenes.sh first)")
    print((out / "machine.txt").read_text().strip())
    print()
    print("\n".join(table(out)))


if __name__ == "__main__":
    main()
