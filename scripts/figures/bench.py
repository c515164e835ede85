"""Tables of one `bench` run's files: every method on a scene, the compact format, the
compute splat and its roofline, hidden layers, the targets, `--skip` and `--antialias`."""

import re
from pathlib import Path

from figures.results import (ROOT, ResultsError, device_of, files, measured, printed,
                             read_csv, report_device, sci, timed)


def methods_side_by_side(path: str, scene: str) -> list[str]:
    """Every method of one bench run on one scene: time, its ratio to `impostor`, and error."""
    csv_path = files(path)[0]
    rows = [r for r in read_csv(csv_path) if r["scene"] == scene]
    if not rows:
        raise ResultsError(f"{path}: no rows of scene {scene}")
    base = next((float(r["wall_ms"]) for r in rows if r["method"] == "impostor"), None)
    if base is None:
        raise ResultsError(f"{path}: no impostor row on {scene}")
    lines = [measured(csv_path, *device_of(rows)) +
             f" `bench --quick`, one run; {scene} ({int(rows[0]['count']):,} glyphs, "
             f"{rows[0]['width']}x{rows[0]['height']}).", "",
             "| method | wall ms | time / impostor | shaded / covered px | coverage mismatch | depth rel p99 | normal p99 (deg) |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if r["method"].startswith("floor-"):
            continue  # the roofline's floors draw nothing to judge: compute-splat.md's table
        wall = float(r["wall_ms"])
        # Shaded pixels (the exact count), as the tool's own table divides.
        fragments = float(r["shaded_pixels"]) / float(r["covered_pixels"])
        lines.append(f"| {r['method']} | {wall:.2f} | {wall / base:.2f} | {fragments:.3f} | "
                     f"{sci(r['coverage_mismatch'])} | {sci(r['depth_rel_p99'])} | "
                     f"{sci(r['normal_deg_p99'])} |")
    return lines


def compact(path: str) -> list[str]:
    """`impostor` against `impostor-compact` per scene of one bench run."""
    csv_path = files(path)[0]
    rows = read_csv(csv_path)
    by = {(r["scene"], r["count"], r["method"]): r for r in rows}
    lines = [measured(csv_path, *device_of(rows)) + " `bench --quick`, one run; wall ms, "
             "depth rel p99, normal p99 in degrees.", "",
             "| scene (count) | impostor | impostor-compact |", "| --- | --- | --- |"]
    for scene, count, method in by:
        if method != "impostor-compact":
            continue
        cells = []
        for m in ("impostor", "impostor-compact"):
            r = by[(scene, count, m)]
            cells.append(f"{float(r['wall_ms']):.2f} ms, {sci(r['depth_rel_p99'])}, "
                         f"{sci(r['normal_deg_p99'])}")
        lines.append(f"| {scene} ({int(count):,}) | {cells[0]} | {cells[1]} |")
    return lines


def bench_rows(path: str) -> tuple[Path, list[dict], dict]:
    """A bench run's results.csv, its rows, and the rows by (scene, count, method)."""
    csv_path = files(path)[0]
    rows = read_csv(csv_path)
    return csv_path, rows, {(r["scene"], r["count"], r["method"]): r for r in rows}


def splat(path: str) -> list[str]:
    """The shipped mix against the draw, the splat and the visibility buffer, per scene."""
    csv_path, rows, by = bench_rows(path)
    methods = ["impostor", "impostor-draw", "impostor-compute", "impostor-visbuffer", "flat-fill"]
    lines = [measured(csv_path, *device_of(rows)) + " `bench --quick`, one run; medians of the "
             "timed frames, 1920x1080; a method left out was over the vertex budget.", "",
             "| scene (count) | " + " | ".join(f"{m} ms" for m in methods) +
             " | mix over the draw (its path) |",
             "|---|" + "---:|" * (len(methods) + 1)]
    for scene, count in dict.fromkeys((r["scene"], r["count"]) for r in rows):
        mix = by.get((scene, count, "impostor"))
        if mix is None:
            continue
        cells = [f"{float(by[(scene, count, m)]['wall_ms']):.2f}" if (scene, count, m) in by else "-"
                 for m in methods]
        draw = by.get((scene, count, "impostor-draw"))
        ratio = f"{float(draw['wall_ms']) / float(mix['wall_ms']):.2f}x" if draw else "-"
        lines.append(f"| {scene} ({int(count):,}) | " + " | ".join(cells) +
                     f" | {ratio} ({mix['plan_path'] or '?'}) |")
    return lines


def roofline(path: str) -> list[str]:
    """The mix against the floors (reading every instance; ray casting every centre)."""
    csv_path, rows, by = bench_rows(path)
    lines = [measured(csv_path, *device_of(rows)) + " `bench --quick`, one run; 1920x1080.", "",
             "| scene (count) | impostor (mix) ms | arithmetic floor ms | memory floor ms | mix / arithmetic | mix / memory |",
             "|---|---:|---:|---:|---:|---:|"]
    for scene, count in dict.fromkeys((r["scene"], r["count"]) for r in rows):
        if not (scene == "tensor-field" or (scene == "cloud-2px" and int(count) >= 100_000)):
            continue
        try:
            mix, arith, memory = (float(by[(scene, count, m)]["wall_ms"])
                                  for m in ("impostor", "floor-arithmetic", "floor-memory"))
        except KeyError as missing:
            raise ResultsError(f"{csv_path.relative_to(ROOT)}: {scene} ({count}) lacks {missing}")
        lines.append(f"| {scene} ({int(count):,}) | {mix:.2f} | {arith:.2f} | {memory:.2f} | "
                     f"{mix / arith:.2f}x | {mix / memory:.2f}x |")
    return lines


HIDDEN_SCENES = ("tensor-field", "lattice", "md-liquid")


def hidden_layers(paths: list[str]) -> list[str]:
    """The deep scenes' frames -- still (`impostor`), first of a camera, drawn -- beside the
    floors, with ray casts per visible pixel: a table per run, one row per scene."""
    lines = []
    for pattern in paths:
        csv_path, rows, by = bench_rows(pattern)
        if lines:
            lines.append("")
        lines += [measured(csv_path, *device_of(rows)) + " `bench --quick`, one run; medians of "
                  "the timed frames in ms, 1920x1080; in brackets ray casts per visible pixel.", "",
                  "| scene (count) | still | first frame | drawn | arithmetic floor | visible floor "
                  "| memory floor | still / visible floor |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|"]
        for scene, count in dict.fromkeys((r["scene"], r["count"]) for r in rows):
            if scene not in HIDDEN_SCENES:
                continue
            methods = ("impostor", "impostor-first-frame", "impostor-draw", "floor-arithmetic",
                       "floor-visible", "floor-memory")
            missing = [m for m in methods if (scene, count, m) not in by]
            if missing:
                raise ResultsError(f"{csv_path.relative_to(ROOT)}: {scene} lacks {', '.join(missing)}")
            # The memory floor casts no ray (its count is the read-back frame's resolve).
            cells = [timed(by[(scene, count, m)]) if m != "floor-memory"
                     else f"{float(by[(scene, count, m)]['wall_ms']):.2f}" for m in methods]
            still = float(by[(scene, count, "impostor")]["wall_ms"])
            floor = float(by[(scene, count, "floor-visible")]["wall_ms"])
            lines.append(f"| {scene} ({int(count):,}) | " + " | ".join(cells) +
                         f" | {still / floor:.2f}x |")
    return lines


TARGET = re.compile(r"^\[(met|MISSED)\] (.+)$", re.M)


def targets(report: str) -> list[str]:
    """The targets `bench` checks, as its log printed them: met or missed, and the figure."""
    log = files(f"{report}/bench.txt")[0]
    found = printed(log, TARGET, "[met] or [MISSED]")
    lines = [measured(log, *report_device(ROOT / report)) + " `bench --quick`, one run.", "",
             "| verdict | target: figures |", "|---|---|"]
    for m in found:
        verdict = "met" if m.group(1) == "met" else "**missed**"
        lines.append(f"| {verdict} | {m.group(2)} |")
    return lines


def skip(paths: list[str]) -> list[str]:
    """`bench --skip`'s pieces on and off, a table per run: lavapipe's named by the file
    (skip-mesa-X.Y.Z.csv), a device report's by its info.txt."""
    lines = []
    for pattern in paths:
        csv_path = files(pattern)[0]
        mesa = re.search(r"mesa-([0-9]+(?:\.[0-9]+)*)", csv_path.name)
        if mesa:
            device, driver = "llvmpipe", f"llvmpipe (Mesa {mesa.group(1)})"
        else:
            device, driver = report_device(csv_path.parent)
        if lines:
            lines.append("")
        lines += [measured(csv_path, device, driver) + " `bench --skip --quick`, 1920x1080.", "",
                  "| feature | scene | applies | on ms | off ms | speed-up | pixels changed |",
                  "|---|---|---|---:|---:|---:|---:|"]
        for r in read_csv(csv_path):
            on, off = float(r["on_ms"]), float(r["off_ms"])
            lines.append(f"| {r['feature']} | {r['scene']} | {r['applies']} | {on:.2f} | {off:.2f} | "
                         f"{off / on:.2f}x | {r['pixels_changed']} |")
    return lines


ANTIALIAS_VARIANTS = [("1-sample", "1 sample"), ("1-sample-drawn", "1 sample, drawn"),
                      ("msaa4-per-pixel", "4x per pixel"), ("msaa4-per-sample", "4x per sample"),
                      ("supersample2", "2 x 2 supersampled"), ("supersample4", "4 x 4 supersampled")]


def antialias(report: str) -> list[str]:
    """`bench --antialias`'s time against error per variant, a table per scene."""
    folder = ROOT / report
    csv_path = files(f"{report}/bench/antialias.csv")[0]
    rows = read_csv(csv_path)
    lines = [measured(csv_path, *report_device(folder)) + " The antialiasing run of `bench` "
             "(`antialias.csv`), one run; times at 1920x1080 (ratio to one sample), errors on "
             "the 480 x 270 view."]
    for scene in dict.fromkeys(r["scene"] for r in rows):
        here = {r["variant"]: r for r in rows if r["scene"] == scene}
        missing = [v for v, _ in ANTIALIAS_VARIANTS if v not in here]
        if missing:
            raise ResultsError(f"{csv_path.relative_to(ROOT)}: {scene} lacks {', '.join(missing)}")
        lines += ["", f"| {scene} | " + " | ".join(name for _, name in ANTIALIAS_VARIANTS) + " |",
                  "|---|" + "---:|" * len(ANTIALIAS_VARIANTS),
                  "| time | " + " | ".join(f"{float(here[v]['wall_ms']):.2f} ms ({float(here[v]['ratio_to_1_sample']):.2f}x)"
                                          for v, _ in ANTIALIAS_VARIANTS) + " |",
                  "| error (px) | " + " | ".join(f"{float(here[v]['area_error_px']):.4f}"
                                                for v, _ in ANTIALIAS_VARIANTS) + " |"]
    return lines
