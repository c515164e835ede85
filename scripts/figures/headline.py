"""The README's headline table: ours against the CPU ray tracer on the same cores (the deep
scenes' runs) and ours on a card (a device report's `bench`)."""

import re

from figures.results import ROOT, ResultsError, about, device_of, files, helper, read_csv, sci


def headline(deep: str, report: str) -> list[str]:
    """From a deep-scenes folder (ours on lavapipe, Mitsuba on the same cores) and a device
    report's `bench` (ours on its card)."""
    deep_table = helper("deep-table")
    folder = ROOT / deep
    lava = [r for p in files(f"{deep}/*-run*/results.csv") for r in read_csv(p)]
    gpu_csv = files(f"{report}/bench/results.csv")[0]
    gpu = read_csv(gpu_csv)
    tracer_text = files(f"{deep}/tracer-*-run1.txt")[0].read_text()
    mitsuba = re.search(r"(Mitsuba [0-9.]+ [a-z_]+)", tracer_text)
    if mitsuba is None:
        raise ResultsError(f"{deep}: the tracer's files do not name Mitsuba's version")
    _, lava_driver = device_of(lava)
    card, card_driver = device_of(gpu)
    date, machine = about(folder / "table.md")
    gpu_date, gpu_machine = about(gpu_csv)
    runs = deep_table.run_count(folder)
    lines = [f"Lavapipe and Mitsuba rows: measured {date}; {machine}; lavapipe (no GPU), driver "
             f"{lava_driver}, and {mitsuba.group(1)} on the same cores; medians of {runs} runs. "
             f"Card rows: measured {gpu_date}; {gpu_machine}; card {card}, driver {card_driver}; "
             "`bench --quick`, one run. 1920x1080; errors against the float64 reference.", "",
             "| scene | renderer | runs on | ms a frame | coverage mismatch | depth rel p99 | normal p99 (deg) |",
             "|---|---|---|---:|---:|---:|---:|"]
    for scene in deep_table.SCENES:
        count = next(int(r["count"]) for r in lava if r["scene"] == scene)
        name = f"{scene} ({count:,})"

        def ours(motion: str, label: str) -> str:
            ms = deep_table.median_of(folder, motion, scene, "impostor", "wall_ms")
            errors = [deep_table.median_of(folder, motion, scene, "impostor", c)
                      for c in ("coverage_mismatch", "depth_rel_p99", "normal_deg_p99")]
            if ms is None or None in errors:
                raise ResultsError(f"{deep}: no impostor rows of {scene} ({motion})")
            return (f"| {name} | ellipsoid-splat, {label} | lavapipe | {ms:.1f} | "
                    + " | ".join(sci(str(e)) for e in errors) + " |")
        lines.append(ours("still", "still camera"))
        lines.append(ours("orbit", "camera orbiting"))
        for way, label in (("rays", "raw primary rays"), ("depth", "depth AOV")):
            ms = deep_table.tracer(folder, scene, way)
            if ms is None:
                raise ResultsError(f"{deep}: no Mitsuba '{way}' time of {scene}")
            lines.append(f"| {name} | Mitsuba 3, {label} | the same CPU cores | {ms:.1f} | "
                         "not measured | not measured | not measured |")
        row = next((r for r in gpu if r["scene"] == scene and r["method"] == "impostor"), None)
        if row is None:
            raise ResultsError(f"{gpu_csv.relative_to(ROOT)}: no impostor row of {scene}")
        lines.append(f"| {name} | ellipsoid-splat, still camera | {card} | {float(row['wall_ms']):.2f} | "
                     f"{sci(row['coverage_mismatch'])} | {sci(row['depth_rel_p99'])} | "
                     f"{sci(row['normal_deg_p99'])} |")
    return lines
