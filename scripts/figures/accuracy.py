"""Tables of the accuracy runs: `stress`'s sweeps and `conformance`'s JUnit per driver."""

import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

from figures.results import ROOT, ResultsError, about, files, measured, read_csv, report_device, sig


def stress(folder: str) -> list[str]:
    """`stress`'s sweeps summed up per sweep, from its stress.csv."""
    csv_path = files(f"{folder}/stress.csv")[0]
    rows = read_csv(csv_path)
    size = {(r["width"], r["height"]) for r in rows}
    lines = [measured(csv_path, *report_device(csv_path.parent)) +
             f" `stress`, {sum(r['method'] == 'stable' for r in rows)} points of "
             + ", ".join(f"{w}x{h}" for w, h in sorted(size)) + "; worst error / bound is the "
             "largest ratio over all six bounds, depth and normal judged beyond the float32 floor.",
             "",
             "| sweep | points | stable: worst error / bound | stable: raw depth p99 (worst point) | "
             "stable: raw normal p99 (worst point, deg) | stable: coverage mismatches | "
             "textbook: points breaking a bound | textbook: worst error / bound |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for sweep in dict.fromkeys(r["sweep"] for r in rows):
        stable = [r for r in rows if r["sweep"] == sweep and r["method"] == "stable"]
        textbook = [r for r in rows if r["sweep"] == sweep and r["method"] == "textbook"]
        worst = lambda rs, col: max(float(r[col]) for r in rs)
        lines.append(
            f"| {sweep} | {len(stable)} | {worst(stable, 'worst_over_bound'):.2f} | "
            f"{sig(worst(stable, 'depth_rel_p99'))} | {sig(worst(stable, 'normal_deg_p99'))} | "
            f"{sum(int(r['coverage_mismatch']) for r in stable)} | "
            f"{sum(r['pass'] != 'yes' for r in textbook)} | "
            f"{sig(worst(textbook, 'worst_over_bound'), 3) if textbook else '-'} |")
    return lines


def junit_cases(path: Path) -> dict[str, str]:
    """Each case of `conformance --junit`'s file: its name -> pass or FAIL and what it measured."""
    cases = {}
    for case in ElementTree.parse(path).getroot().iter("testcase"):
        out = case.findtext("system-out") or ""
        verdict = "FAIL" if case.find("failure") is not None else "pass"
        depth = re.search(r"depth rel p99 (\S+)", out)
        normal = re.search(r"normal p99 (\S+)", out)
        samples = re.search(r"(\d+) partly covered, (\d+) wrong", out)
        if depth and normal:
            cases[case.get("name")] = f"{verdict}: {depth.group(1)}, {normal.group(1)} deg"
        elif samples:
            cases[case.get("name")] = f"{verdict}: {samples.group(2)} of {samples.group(1)} partly covered wrong"
        else:
            cases[case.get("name")] = verdict
    return cases


def conformance(folder: str) -> list[str]:
    """`conformance` per case on every driver of one day (mesa-X.Y.Z.xml with info-mesa-X.Y.Z.txt)."""
    runs = files(f"{folder}/*.xml")
    date, machine = about(runs[0])
    drivers, columns = [], []
    for xml in runs:
        info = xml.parent / f"info-{xml.stem}.txt"
        if not info.exists():
            raise ResultsError(f"{info.relative_to(ROOT)} is missing (`ellipsoid-splat info` of that driver)")
        text = info.read_text()
        driver = re.search(r"^driver:\s*(.+)$", text, re.M)
        if driver is None:
            raise ResultsError(f"{info.relative_to(ROOT)} names no driver")
        drivers.append(driver.group(1))
        columns.append(junit_cases(xml))
    names = list(dict.fromkeys(n for c in columns for n in c))
    lines = [f"Measured {date}; {machine}; lavapipe (no GPU), drivers " + " and ".join(drivers) +
             ". Each case against the float64 reference: depth rel p99 and normal p99, or the "
             "samples of partly covered pixels resolved wrong.", "",
             "| case | " + " | ".join(drivers) + " |", "|---|" + "---|" * len(drivers)]
    for name in names:
        lines.append(f"| {name} | " + " | ".join(c.get(name, "not run") for c in columns) + " |")
    return lines
