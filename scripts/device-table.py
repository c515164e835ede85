#!/usr/bin/env python3
"""The per-device rows that docs/conformance.md links, made from one folder of
scripts/device-report.sh: the device and driver, conformance, the tests that draw, and per
bench scene the plan's path and regret (the first guess's and after learning: the plan's time
over the fastest fixed path's, from one interleaved run). Figures come from the run's files
only; nothing is typed by hand.

    python3 scripts/device-table.py REPORT_DIR

scripts/tables.py imports `device_rows` and `regret_rows` to put the same figures into the docs.
"""

import csv
import re
import sys
from pathlib import Path


def read(path: Path) -> str:
    return path.read_text(errors="replace") if path.exists() else ""


def info_field(info: str, name: str) -> str:
    match = re.search(rf"^{name}:\s*(.+)$", info, re.MULTILINE)
    return match.group(1).strip() if match else "?"


def conformance(report: Path) -> str:
    text = read(report / "conformance.txt")
    match = re.search(r"(\d+) of (\d+) cases? pass", text)
    if match:
        return f"{match.group(1)} of {match.group(2)} pass"
    status = read(report / "conformance.status").strip()
    return f"did not finish (exit {status or '?'})"


def tests(report: Path) -> str:
    passed = failed = 0
    for match in re.finditer(r"test result: \w+\. (\d+) passed; (\d+) failed", read(report / "tests.txt")):
        passed += int(match.group(1))
        failed += int(match.group(2))
    if passed + failed == 0:
        return "not run"
    failing = sorted(set(re.findall(r"^test (\S+) \.\.\. FAILED", read(report / "tests.txt"), re.MULTILINE)))
    note = f" (failing: {', '.join(failing)})" if failing else ""
    return f"{passed} of {passed + failed} pass{note}"


def regrets(report: Path) -> list[tuple[str, str, str, str]]:
    """(scene, first guess, learned, fastest) per scene with a regret, from results.csv; a
    scene of several glyph counts (the clouds) has a row per count."""
    path = report / "bench" / "results.csv"
    if not path.exists():
        return []
    rows = list(csv.DictReader(path.open()))
    scenes: list[tuple[str, str]] = []
    for row in rows:
        key = (row["scene"], row["count"])
        if row["method"] in ("impostor", "impostor-estimate") and key not in scenes:
            scenes.append(key)
    out = []
    for scene, count in scenes:
        of_scene = [r for r in rows if r["scene"] == scene and r["count"] == count]

        def cell(method: str) -> str:
            row = next((r for r in of_scene if r["method"] == method), None)
            if row is None:
                return "not timed"
            regret = row.get("plan_regret", "")
            path_taken = row.get("plan_path", "") or "?"
            return f"{path_taken} {float(regret):.2f}" if regret else f"{path_taken} (no regret)"
        fixed = [r for r in of_scene
                 if r["method"] in ("impostor-draw", "impostor-compute", "impostor-visible-first")]
        fastest = min(fixed, key=lambda r: float(r["wall_ms"]), default=None)
        best = f"{fastest['plan_path'] or fastest['method']} {float(fastest['wall_ms']):.2f} ms" if fastest else "?"
        out.append((f"{scene} ({int(count):,})", cell("impostor-estimate"), cell("impostor"), best))
    return out


def device_rows(report: Path) -> list[str]:
    info = read(report / "info.txt")
    device, driver = info_field(info, "device"), info_field(info, "driver")
    return ["| device | driver | conformance | tests that draw |",
            "|---|---|---|---|",
            f"| {device} | {driver} | {conformance(report)} | {tests(report)} |"]


def regret_rows(report: Path) -> list[str]:
    lines = ["| scene | first guess | after learning | fastest fixed path |",
             "|---|---|---|---|"]
    for scene, guess, learned, fastest in regrets(report):
        lines.append(f"| {scene} | {guess} | {learned} | {fastest} |")
    return lines


def main() -> None:
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    report = Path(sys.argv[1])
    info = read(report / "info.txt")
    date = read(report / "date.txt").strip() or "?"
    print(f"Device report, {date}: {info_field(info, 'device')}, driver {info_field(info, 'driver')}.\n")
    print("\n".join(device_rows(report)))
    if regrets(report):
        print("\nThe plan's regret (its time over the fastest fixed path's; path and ratio), "
              "`bench --quick`, one interleaved run:\n")
        print("\n".join(regret_rows(report)))


if __name__ == "__main__":
    main()
