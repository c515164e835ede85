#!/usr/bin/env python3
"""The table of scripts/plan-orbit.sh from its printed log: per scene the median over the runs
of the measuring plan's GPU time of all frames over the fixed path's (and their range). Reads
the lines `RUN SCENE PLAN: all frames MS ms; ...` the script prints; nothing typed by hand.

    python3 scripts/orbit-table.py LOG

scripts/tables.py imports `table` to put the same figures into the docs.
"""

import re
import statistics
import sys

LINE = re.compile(r"^(\d+) (\S+) (\S+): all frames ([0-9.]+) ms", re.MULTILINE)


def table(text: str) -> list[str]:
    rows = LINE.findall(text)
    if not rows:
        raise ValueError("no 'RUN SCENE PLAN: all frames MS ms' lines (a plan-orbit.sh log?)")
    fixed = next(plan for _, _, plan, _ in rows if plan != "measure")
    times: dict[tuple[str, str], dict[str, float]] = {}
    for run, scene, plan, ms in rows:
        times.setdefault((scene, run), {})[plan] = float(ms)
    lines = [f"| scene | measure / {fixed}, all frames (median of runs) | range | runs |",
             "|---|---:|---|---:|"]
    for scene in dict.fromkeys(s for _, s, _, _ in rows):
        ratios = [t["measure"] / t[fixed] for (s, _), t in times.items()
                  if s == scene and "measure" in t and fixed in t]
        lines.append(f"| {scene} | {statistics.median(ratios):.3f} | "
                     f"{min(ratios):.3f}-{max(ratios):.3f} | {len(ratios)} |")
    return lines


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    try:
        print("\n".join(table(open(sys.argv[1]).read())))
    except (OSError, ValueError) as err:
        sys.exit(f"orbit-table: {sys.argv[1]}: {err}")


if __name__ == "__main__":
    main()
