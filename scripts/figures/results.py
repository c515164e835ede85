"""Reading the committed results under docs/results/ for scripts/tables.py: the files a glob
names, when and where they ran (the `about.txt` beside them), the device and driver they
name, the line set above every table, and the figures' number formats."""

import csv
import fnmatch
import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
RESULTS = "docs/results"


class ResultsError(Exception):
    """A results file is missing or says less than a table needs."""


def helper(name: str):
    """One of the per-run table scripts beside this one, as a module (their names have dashes)."""
    spec = importlib.util.spec_from_file_location(name.replace("-", "_"), ROOT / "scripts" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def files(pattern: str) -> list[Path]:
    """The committed files a glob names, in run order (run2 before run10), by their path from
    the repository root (not the file system's order)."""
    found = sorted(ROOT.glob(pattern), key=lambda p: [int(t) if t.isdigit() else t
                                                      for t in re.split(r"(\d+)", str(p.relative_to(ROOT)))])
    if not found:
        raise ResultsError(f"no file matches {pattern}")
    return found


def about(path: Path) -> tuple[str, str]:
    """(date, machine) of a results file, from the `about.txt` of its folder or one above."""
    folder = path.parent
    while folder != ROOT:
        sheet = folder / "about.txt"
        if sheet.exists():
            for line in sheet.read_text().splitlines():
                if line.startswith("#") or not line.strip():
                    continue
                glob, date, machine = (cell.strip() for cell in line.split("|", 2))
                if fnmatch.fnmatch(str(path.relative_to(folder)), glob):
                    return date, machine
            raise ResultsError(f"{sheet.relative_to(ROOT)} has no line for {path.name}")
        folder = folder.parent
    raise ResultsError(f"no about.txt beside {path.relative_to(ROOT)} (its date and machine)")


def printed(log: Path, pattern: re.Pattern, what: str) -> list[re.Match]:
    """Every match of `pattern` (one printed line each) in a committed log; none is an error
    naming the log and the line it lacks."""
    found = list(pattern.finditer(log.read_text()))
    if not found:
        raise ResultsError(f"{log.relative_to(ROOT)} prints no {what} line")
    return found


def timed(row: dict, digits: int = 2) -> str:
    """A results.csv row's median time, with its ray casts per visible pixel in brackets where
    counted (an empty cell: not counted)."""
    casts = row.get("ray_casts_per_visible_pixel")
    wall = f"{float(row['wall_ms']):,.{digits}f}"
    return f"{wall} ({float(casts):.2f})" if casts else wall


def read_csv(path: Path) -> list[dict]:
    return list(csv.DictReader(path.open()))


def device_of(rows: list[dict]) -> tuple[str, str]:
    """(device, driver) that every row of a results.csv names; several would be a mixed table."""
    seen = {(r["device"], r["driver"]) for r in rows}
    if len(seen) != 1:
        raise ResultsError(f"the rows name {len(seen)} devices: {sorted(seen)}")
    return seen.pop()


def report_device(folder: Path) -> tuple[str, str]:
    """(device, driver) of a device report's `info.txt` (what `ellipsoid-splat info` printed)."""
    if not (folder / "info.txt").exists():
        raise ResultsError(f"{folder.relative_to(ROOT)}/info.txt is missing (the device and driver "
                           "`ellipsoid-splat info` names)")
    info = (folder / "info.txt").read_text()
    found = [re.search(rf"^{key}:\s*(.+)$", info, re.M) for key in ("device", "driver")]
    if None in found:
        raise ResultsError(f"{folder.relative_to(ROOT)}/info.txt names no device or driver")
    return found[0].group(1), found[1].group(1)


def measured(path: Path, device: str, driver: str) -> str:
    """The line set above a table: when, on what, with which driver."""
    date, machine = about(path)
    # lavapipe's driver string names it; a card is named on its own.
    on = "lavapipe (no GPU)" if device.startswith("llvmpipe") else f"card {device}"
    return f"Measured {date}; {machine}; {on}, driver {driver}."


def sci(value: str) -> str:
    """A float of results.csv as the tool's table prints it (0, 4.2e-7, 1.28e-2, inf)."""
    number = float(value)
    if number == 0 or number != number or number in (float("inf"), float("-inf")):
        return "0" if number == 0 else str(number)
    return f"{number:.2e}".replace("e-0", "e-").replace("e+0", "e").replace("e+", "e")


def sig(value: float, digits: int = 2) -> str:
    """A figure to `digits` significant digits, as the docs write them (12,300; 0.059; 1.1e-5)."""
    if value == 0:
        return "0"
    if abs(value) < 1e-3:
        return f"{value:.{digits - 1}e}".replace("e-0", "e-")
    rounded = float(f"{value:.{max(digits, 3) if value >= 100 else digits}g}")
    return f"{rounded:,.0f}" if rounded >= 100 else f"{rounded:g}"
