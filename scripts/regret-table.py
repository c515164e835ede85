#!/usr/bin/env python3
"""The plan's regret over several `bench` runs of one driver, per scene: for the first guess
(`impostor-estimate`) and after learning (`impostor`), the path taken and two ratios over the
fastest fixed path's time (`impostor-draw`, `impostor-compute`, `impostor-visible-first`):

- "own frames": the plan's own timed frames (`plan_regret` in results.csv), which also carry
  the run-to-run noise between two methods that draw the same path;
- "its path": the fixed method of the path the plan took, which isolates the choice.

Each cell is the median over the runs (their range in brackets). Figures come from the runs'
results.csv files only.

    python3 scripts/regret-table.py RESULTS.csv [RESULTS.csv ...]

scripts/tables.py imports `table` to put the same figures into the docs.
"""

import csv
import statistics
import sys

FIXED = {"draw": "impostor-draw", "splat": "impostor-compute",
         "visible-first": "impostor-visible-first"}


def cell(values: list[float]) -> str:
    if not values:
        return "-"
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def table(paths: list[str]) -> list[str]:
    runs = [list(csv.DictReader(open(p))) for p in paths]
    scenes: list[tuple[str, str]] = []
    for rows in runs:
        for r in rows:
            key = (r["scene"], r["count"])
            if r["method"] == "impostor" and key not in scenes:
                scenes.append(key)
    driver = next((r.get("driver", "?") for rows in runs for r in rows), "?")
    lines = [f"{len(runs)} runs on {driver}: the plan's time over the fastest fixed path's, median "
             "over the runs (range)", "",
             "| scene | first guess | own frames | its path | learned | own frames | its path |",
             "|---|---|---:|---:|---|---:|---:|"]
    for scene, count in scenes:
        cells = []
        for method in ("impostor-estimate", "impostor"):
            own, by_path, taken = [], [], []
            for rows in runs:
                here = {r["method"]: r for r in rows if (r["scene"], r["count"]) == (scene, count)}
                row = here.get(method)
                if row is None:
                    continue
                path = row.get("plan_path", "") or "?"
                taken.append(path)
                if row.get("plan_regret"):
                    own.append(float(row["plan_regret"]))
                fixed = [float(here[m]["wall_ms"]) for m in FIXED.values() if m in here]
                if len(fixed) == len(FIXED) and FIXED.get(path) in here:
                    by_path.append(float(here[FIXED[path]]["wall_ms"]) / min(fixed))
            cells += ["/".join(sorted(set(taken))) or "not timed", cell(own), cell(by_path)]
        lines.append(f"| {scene} ({int(count):,}) | " + " | ".join(cells) + " |")
    return lines


def main() -> None:
    paths = sys.argv[1:]
    if not paths:
        sys.exit(__doc__)
    print("\n".join(table(paths)))


if __name__ == "__main__":
    main()
