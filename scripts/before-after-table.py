#!/usr/bin/env python3
"""Frame times of two builds from interleaved `bench` runs: per scene and method, the median
over the runs of each build's time and of the pairs' ratios (after / before, with their
range). The pairs are given in the order they ran, before first.

    python3 scripts/before-after-table.py BEFORE.csv AFTER.csv [BEFORE.csv AFTER.csv ...]
        [--same OLD=NEW ...] [--methods NAME,NAME]

`--same impostor=impostor-estimate` sets a method of the before build beside one of the after
build that draws the same way (there, the plan of 878b4bb beside the first guess that keeps its
thresholds); methods of the same name are set side by side anyway. `--methods` keeps only
the before build's methods named. Figures come from the files only; scripts/tables.py imports
`table` to put them into the docs.
"""

import csv
import statistics
import sys


def table(files: list[str], same: dict[str, str] | None = None,
          methods: list[str] | None = None) -> list[str]:
    """`files` are before and after in turn, in the order they ran."""
    same = same or {}
    pairs = [(list(csv.DictReader(open(a))), list(csv.DictReader(open(b))))
             for a, b in zip(files[::2], files[1::2])]
    rows = []
    for r in (r for old, _ in pairs for r in old):
        key = (r["scene"], r["count"], r["method"])
        if key not in rows and (methods is None or r["method"] in methods):
            rows.append(key)
    lines = [f"{len(pairs)} interleaved pairs; medians over the pairs (range of the ratios)", "",
             "| scene | method (before / after) | before ms | after ms | after / before |",
             "|---|---|---:|---:|---:|"]
    for scene, count, method in rows:
        twin = same.get(method, method)
        before, after, ratios = [], [], []
        for old, new in pairs:
            o = next((r for r in old if (r["scene"], r["count"], r["method"]) ==
                      (scene, count, method)), None)
            n = next((r for r in new if (r["scene"], r["count"], r["method"]) ==
                      (scene, count, twin)), None)
            if o and n:
                before.append(float(o["wall_ms"]))
                after.append(float(n["wall_ms"]))
                ratios.append(after[-1] / before[-1])
        if not ratios:
            continue
        name = method if twin == method else f"{method} / {twin}"
        lines.append(f"| {scene} ({int(count):,}) | {name} | {statistics.median(before):.1f} | "
                     f"{statistics.median(after):.1f} | {statistics.median(ratios):.2f} "
                     f"({min(ratios):.2f}-{max(ratios):.2f}) |")
    return lines


def main() -> None:
    args = sys.argv[1:]
    same = {}
    while "--same" in args:
        at = args.index("--same")
        old, new = args[at + 1].split("=")
        same[old] = new
        del args[at:at + 2]
    methods = None
    if "--methods" in args:
        at = args.index("--methods")
        methods = args[at + 1].split(",")
        del args[at:at + 2]
    if not args or len(args) % 2:
        sys.exit(__doc__)
    print("\n".join(table(args, same, methods)))


if __name__ == "__main__":
    main()
