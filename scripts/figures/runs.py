"""Tables of the per-run helpers (regret-table.py, before-after-table.py, orbit-table.py,
deep-table.py, device-table.py), with the line that says when and where they ran."""

import re

from figures.results import (ROOT, ResultsError, device_of, files, helper, measured, read_csv,
                             report_device)


def regret(pattern: str) -> list[str]:
    paths = files(pattern)
    device, driver = device_of([r for p in paths for r in read_csv(p)])
    lines = helper("regret-table").table([str(p) for p in paths])
    return [measured(paths[0], device, driver) + " " + lines[0].split(": ", 1)[1].capitalize() + ".", ""] + lines[2:]


def before_after(before: list[str], after: list[str], same: dict[str, str] | None = None,
                 methods: list[str] | None = None) -> list[str]:
    """Interleaved pairs of two builds' runs, `before[i]` beside `after[i]`."""
    pairs = []
    for old, new in zip(before, after, strict=True):
        pairs += [files(old)[0], files(new)[0]]
    device, driver = device_of([r for p in pairs for r in read_csv(p)])
    lines = helper("before-after-table").table([str(p) for p in pairs], same, methods)
    return [measured(pairs[0], device, driver) + " " + lines[0][0].upper() + lines[0][1:] + ".", ""] + lines[2:]


def orbit(path: str) -> list[str]:
    log = files(path)[0]
    driver = re.search(r"mesa-([0-9]+(?:\.[0-9]+)*)", log.name)
    if driver is None:
        raise ResultsError(f"{path}: the file's name does not say the driver (orbit-mesa-X.Y.Z.txt)")
    line = measured(log, "llvmpipe", f"llvmpipe (Mesa {driver.group(1)})")
    return [line, ""] + helper("orbit-table").table(log.read_text())


def deep(folder: str) -> list[str]:
    """scripts/deep-scenes.sh's table: ours still and orbiting beside Mitsuba, medians of runs."""
    rows = [r for p in files(f"{folder}/*-run*/results.csv") for r in read_csv(p)]
    lines = helper("deep-table").table(ROOT / folder)
    return [measured(ROOT / folder / "table.md", *device_of(rows)) + " " + lines[0][0].upper() +
            lines[0][1:] + ".", ""] + lines[2:]


def device_report(folder: str) -> list[str]:
    """scripts/device-report.sh's rows: conformance, the tests that draw, the plan's regret."""
    report = ROOT / folder
    module = helper("device-table")
    return ([measured(report / "info.txt", *report_device(report)), ""] + module.device_rows(report) +
            ["", "The plan's regret (its time over the fastest fixed path's; path and ratio), "
             "`bench --quick`, one interleaved run:", ""] + module.regret_rows(report))
