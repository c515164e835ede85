"""Tables of the per-run helpers (regret-table.py, before-after-table.py, orbit-table.py,
deep-table.py, device-table.py), with the line that says when and where they ran."""

import re
import statistics
from pathlib import Path

from figures.results import (ROOT, ResultsError, device_of, files, helper, measured, printed,
                             read_csv, report_device, timed)


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


def research(folder: str, method: str) -> list[str]:
    """A research method's runs on the deep scenes (scripts/deep-scenes.sh with METHODS): per
    motion, run and scene each method's median ms and ray casts per visible pixel, and `method`
    over the splat and over the visible-first splat of the same run; a table per line of the
    folder's about.txt (runs of another date or load)."""
    # Still runs first, then orbiting, each by run number (not the file system's order).
    paths = sorted(files(f"{folder}/*-run*/results.csv"),
                   key=lambda p: (p.parent.name.startswith("orbit"), int(p.parent.name.rsplit("run", 1)[1])))
    methods = list(dict.fromkeys(r["method"] for p in paths for r in read_csv(p)))
    bases = ("impostor-compute", "impostor-visible-first")
    lines, said = [], None
    for path in paths:
        rows = read_csv(path)
        line = measured(path, *device_of(rows))
        if line != said:
            lines += ([""] if lines else []) + [
                line + " `bench --quick --frames 9`, 1920x1080; medians in ms, in brackets ray "
                "casts per visible pixel; orbit: 0.5 degree a frame.", "",
                "| run | scene | " + " | ".join(methods) + " | " +
                " | ".join(f"{method} / {base}" for base in bases) + " |",
                "|---|---|" + "---:|" * (len(methods) + len(bases))]
            said = line
        for scene in dict.fromkeys(r["scene"] for r in rows):
            by = {r["method"]: r for r in rows if r["scene"] == scene}
            cells = [timed(by[m], 1) if m in by else "-" for m in methods]
            cells += [f"{float(by[method]['wall_ms']) / float(by[base]['wall_ms']):.2f}"
                      if method in by and base in by else "-" for base in bases]
            lines.append(f"| {path.parent.name} | {scene} | " + " | ".join(cells) + " |")
    return lines


def deep_device(folder: str) -> list[str]:
    """A device's deep scenes still and orbiting (`bench --scenes ...` into `still-runN/` and
    `orbit-runN/`): per run and scene the path the plan took, each path's median ms with its ray
    casts per visible pixel, and the plan's frame over the visible-pixel floor."""
    paths = sorted(files(f"{folder}/*-run*/results.csv"),
                   key=lambda p: (int(p.parent.name.rsplit("run", 1)[1]), p.parent.name.startswith("orbit")))
    methods = ["impostor", "impostor-compute", "impostor-visible-first", "impostor-draw", "floor-visible"]
    rows = [r for p in paths for r in read_csv(p)]
    lines = [measured(paths[0], *device_of(rows)) + " `bench --quick --frames 31`, 1920x1080; "
             "medians in ms, in brackets ray casts per visible pixel; orbit: 0.5 degree a frame; "
             "`impostor` is the plan's frame.", "",
             "| run | scene | plan's path | " + " | ".join(methods) + " | impostor / floor-visible |",
             "|---|---|---|" + "---:|" * (len(methods) + 1)]
    for path in paths:
        found = read_csv(path)
        for scene in dict.fromkeys(r["scene"] for r in found):
            by = {r["method"]: r for r in found if r["scene"] == scene}
            missing = [m for m in methods if m not in by]
            if missing:
                raise ResultsError(f"{path.relative_to(ROOT)} has no {', '.join(missing)} row for {scene}")
            ratio = float(by["impostor"]["wall_ms"]) / float(by["floor-visible"]["wall_ms"])
            cells = [by["impostor"]["plan_path"]] + [timed(by[m]) for m in methods] + [f"{ratio:.2f}"]
            lines.append(f"| {path.parent.name} | {scene} | " + " | ".join(cells) + " |")
    return lines


# The visible-first splat's pre-pass dispatches in order (`prepass_dispatches` in
# src/renderer/prepass/mod.rs), grouped as the stage profile's columns; a frame with the
# first pass's occluders has one more dispatch before that pass.
STAGES = {"list shown": [0, 1, 2], "splat shown": [3], "key tiles": [4], "list rest": [5, 6, 7],
          "splat rest": [8], "mark shown": [9], "list drawn": [10, 11, 12]}
OCCLUDERS_AT = STAGES["splat shown"][0]
STAGES_WITH_OCCLUDERS = {
    **{name: ks for name, ks in STAGES.items() if ks[0] < OCCLUDERS_AT},
    "occluders": [OCCLUDERS_AT],
    **{name: [k + 1 for k in ks] for name, ks in STAGES.items() if ks[0] >= OCCLUDERS_AT},
}
# The stages of a visible-first frame's stamps line, by the dispatches it holds.
LAYOUTS = {sum(len(ks) for ks in stages.values()): stages
           for stages in (STAGES, STAGES_WITH_OCCLUDERS)}
STAGE_NAMES = list(STAGES_WITH_OCCLUDERS)


def stamped_frames(log: Path) -> list[dict[str, float]]:
    """The visible-first frames of a stage-profile log's bench run, each as its stages' times
    (ms): its first unbroken block of `stamps:` lines with every dispatch (a tensor field's
    log goes on with the antialiasing study's frames, first frames and others, which are not
    the run's)."""
    block, block_length = [], None
    for line in log.read_text().splitlines():
        if not line.startswith("stamps:"):
            continue
        values = [float(x) for x in line.split()[1:]]
        stages = LAYOUTS.get(len(values))
        if stages and block_length in (None, len(values)):
            block_length = len(values)
            block.append({name: sum(values[k] for k in ks) for name, ks in stages.items()})
        elif block:
            break
    if not block:
        raise ResultsError(f"{log.relative_to(ROOT)} holds no visible-first frame's stamps")
    return block


def stamped_resolves(log: Path) -> list[float]:
    """The resolve's time (ms) in each of `stamped_frames`' frames, from the `frame:` line that
    follows each `stamps:` line in logs of builds that time the pass too (frame-stamps.diff of
    results/deep/2026-11-28e); empty for logs without them."""
    resolves, stamps = [], 0
    for line in log.read_text().splitlines():
        if line.startswith("stamps:"):
            if len(line.split()) - 1 not in LAYOUTS:
                if resolves:
                    break
                stamps = 0
                continue
            stamps += 1
        elif line.startswith("frame:") and stamps:
            words = line.split()
            resolves.append(float(words[words.index("resolve") + 1]))
    return resolves


def stage_runs(folder: str) -> tuple[list[Path], dict]:
    """A stage profile's runs in `folder` (`MOTION-SCENE-runN.txt` logs beside their
    `MOTION-SCENE-runN/results.csv`): the logs, and per (motion, scene) every run's stamped
    frames, the resolves timed with them, the runs' GPU medians and their results rows."""
    logs = files(f"{folder}/*-run*.txt")
    groups = {}
    for log in logs:
        motion, scene = log.stem.split("-", 1)
        scene = scene.rsplit("-run", 1)[0]
        results = log.parent / log.stem / "results.csv"
        rows = read_csv(results) if results.exists() else []
        if not rows:
            raise ResultsError(f"{results.relative_to(ROOT)} is missing or empty (the run's bench failed)")
        entry = groups.setdefault((motion, scene), {"frames": [], "gpu": [], "rows": [],
                                                    "resolves": []})
        stamped, resolves = stamped_frames(log), stamped_resolves(log)
        if resolves and len(resolves) != len(stamped):
            raise ResultsError(f"{log.relative_to(ROOT)}: {len(stamped)} frames' stamps but "
                               f"{len(resolves)} resolves")
        entry["frames"] += stamped
        entry["resolves"] += resolves
        entry["gpu"].append(float(rows[0]["gpu_ms"]))
        entry["rows"] += rows
    return logs, groups


def stages(folders: list[str], frames: int = 15) -> list[str]:
    """Where the visible-first splat's frame goes (a temporary build's timestamps before each
    pre-pass dispatch, the `stamps:` lines of each run's log), one table per folder: per motion
    and scene the median over the runs' frames of each group of dispatches and of the
    pre-pass, and the frame's GPU time (median of the runs' medians); the pass (resolve,
    clears) is the rest. `frames`: the runs' `bench --frames`."""
    lines = []
    for folder in folders:
        logs, groups = stage_runs(folder)
        if any("occluders" in f for e in groups.values() for f in e["frames"]):
            raise ResultsError(f"{folder}: frames with the first pass's occluders, which this "
                               "table has no column for (stage_builds shows them)")
        device = device_of([r for e in groups.values() for r in e["rows"]])
        # Builds that time the pass too have the resolve's own timestamps: a column of them.
        timed_pass = all(e["resolves"] for e in groups.values())
        lines += ([""] if lines else []) + [
            measured(logs[0], *device) + f" `bench --quick --frames {frames}`, impostor-visible-first, "
            "1920x1080; each part the median over the runs' frames (their warm-up included), "
            "the frame the median of the runs' medians; orbit: 0.5 degree a frame.", "",
            "| motion | scene | frame | pre-pass | " + " | ".join(STAGES) + " | the pass (frame - pre-pass) |"
            + (" resolve |" if timed_pass else ""),
            "|---|---|---:|---:|" + "---:|" * (len(STAGES) + 1 + timed_pass)]
        for (motion, scene), entry in sorted(groups.items(), key=lambda kv: (kv[0][0] != "still", kv[0][1])):
            frame = statistics.median(entry["gpu"])
            prepass = statistics.median(sum(f.values()) for f in entry["frames"])
            cells = [statistics.median(f[stage] for f in entry["frames"]) for stage in STAGES]
            resolve = f" {statistics.median(entry['resolves']):.1f} |" if timed_pass else ""
            lines.append(f"| {motion} | {scene} | {frame:.1f} | {prepass:.1f} | "
                         + " | ".join(f"{c:.1f}" for c in cells) + f" | {frame - prepass:.1f} |"
                         + resolve)
    return lines


def stage_builds(folders: list[str], frames: int, stage_names: tuple[str, ...] = ("splat shown",)) -> list[str]:
    """Several builds' stage profiles (scripts/stage-profile.sh with a tool per folder, taking
    turns run by run) side by side: per motion and scene, each build's `stage_names` (by default the
    first splat, `splat shown`; each the median over its runs' frames) and frame (the median of
    its runs' medians), in ms. `frames`: the runs' `bench --frames`."""
    for stage in stage_names:
        if stage not in STAGE_NAMES:
            raise ResultsError(f"no stage named {stage!r} (the stages: {', '.join(STAGE_NAMES)})")
    names = {"splat shown": "first splat", "splat rest": "second splat"}
    what = " / ".join(f"{names.get(s, s)} (`{s}`)" for s in stage_names)
    builds, logs = {}, []
    for folder in folders:
        name = Path(folder).name
        if name in builds:
            raise ResultsError(f"two builds named {name}: each needs a folder name of its own")
        found, groups = stage_runs(folder)
        for (motion, scene), entry in groups.items():
            if len({frozenset(f) for f in entry["frames"]}) > 1:
                raise ResultsError(f"{folder}: the {motion} {scene} runs mix frames with and "
                                   "without the first pass's occluders")
        builds[name] = groups
        logs += found
    first = next(iter(builds.values()))
    for name, cells in builds.items():
        if cells.keys() != first.keys():
            raise ResultsError(f"{name} ran other scenes or motions than {next(iter(builds))}")
    device = device_of([r for cells in builds.values() for e in cells.values() for r in e["rows"]])
    lines = [measured(logs[0], *device) + f" `bench --quick --frames {frames}`, "
             f"impostor-visible-first, 1920x1080; each build's {what} / frame, in ms: each "
             "stage the median over its runs' frames (their warm-up included), the frame the "
             "median of its runs' medians; orbit: 0.5 degree a frame.", "",
             "| motion | scene | " + " | ".join(builds) + " |",
             "|---|---|" + "---:|" * len(builds)]
    for motion, scene in sorted(first, key=lambda k: (k[0] != "still", k[1])):
        row = [builds[b][(motion, scene)] for b in builds]
        # A stage a build does not run (a build without the first pass's occluders) shows
        # as "-"; a build mixing runs with and without it is refused above.
        parts = [[f"{statistics.median(f[stage] for f in e['frames']):.1f}"
                  if stage in e["frames"][0] else "-" for stage in stage_names] for e in row]
        lines.append(f"| {motion} | {scene} | " + " | ".join(
            " / ".join(ps) + f" / {statistics.median(e['gpu']):.1f}"
            for ps, e in zip(parts, row)) + " |")
    return lines


def ray_casts_builds(folder: str, builds: tuple[str, ...]) -> list[str]:
    """Ray casts per visible pixel of several builds' visible-first splat (`bench --frames 9`
    runs into `{build}-{motion}/`, still and orbiting), side by side per motion and scene: the
    counts, which do not depend on the machine's load."""
    runs = {}
    for build in builds:
        for motion in ("still", "orbit"):
            path = ROOT / folder / f"{build}-{motion}" / "results.csv"
            if not path.exists():
                raise ResultsError(f"{path.relative_to(ROOT)} is missing (the {build} build's {motion} run)")
            rows = [r for r in read_csv(path) if r["method"] == "impostor-visible-first"]
            scenes = [r["scene"] for r in rows]
            if not rows or len(set(scenes)) != len(scenes):
                raise ResultsError(f"{path.relative_to(ROOT)}: not one impostor-visible-first row "
                                   f"per scene ({', '.join(scenes) or 'none'})")
            if any(not r["ray_casts_per_visible_pixel"] for r in rows):
                raise ResultsError(f"{path.relative_to(ROOT)}: a row without ray casts (a run "
                                   "without counting frames)")
            runs[build, motion] = {r["scene"]: r for r in rows}
    first = runs[builds[0], "still"]
    for (build, motion), found in runs.items():
        if found.keys() != first.keys():
            raise ResultsError(f"{folder}/{build}-{motion} ran other scenes than "
                               f"{builds[0]}-still ({', '.join(sorted(found))})")
    rows = [r for rs in runs.values() for r in rs.values()]
    lines = [measured(ROOT / folder / f"{builds[0]}-still.txt", *device_of(rows))
             + " `bench --frames 9`, impostor-visible-first, 1920x1080; ray casts per visible "
             "pixel (the resolve's one included); orbit: 0.5 degree a frame.", "",
             "| motion | scene | " + " | ".join(builds) + " |", "|---|---|" + "---:|" * len(builds)]
    for motion in ("still", "orbit"):
        for scene in sorted(first):
            cells = [f"{float(runs[build, motion][scene]['ray_casts_per_visible_pixel']):.2f}"
                     for build in builds]
            lines.append(f"| {motion} | {scene} | " + " | ".join(cells) + " |")
    return lines


def visible_walk(folder: str) -> list[str]:
    """What the visible-first splat's first pass walks: per scene, the glyphs a frame shows
    (`{scene}-visible/`, the plain splat of those glyphs alone, the same camera) beside
    the whole scene (`{scene}-all/`): covered pixel centres (with multiplicity) and the splat's
    ray casts (the resolve's one per shown pixel included) per pixel shown; and the share of
    the pixels shown a bench orbit step later that show the same glyph (`{scene}-turned.csv`)."""
    lines = []
    for visible in files(f"{folder}/*-visible/results.csv"):
        scene = visible.parent.name.removesuffix("-visible")
        whole = ROOT / folder / f"{scene}-all" / "results.csv"
        if not whole.exists():
            raise ResultsError(f"{whole.relative_to(ROOT)} is missing (the whole scene's run)")
        part, full = ({r["method"]: r for r in read_csv(path)}.get("impostor-compute")
                      for path in (visible, whole))
        for path, row in ((visible, part), (whole, full)):
            if row is None:
                raise ResultsError(f"{path.relative_to(ROOT)} has no impostor-compute row")
        turned = ROOT / folder / f"{scene}-turned.csv"
        kept = read_csv(turned) if turned.exists() else []
        if len(kept) != 1:
            raise ResultsError(f"{turned.relative_to(ROOT)} is missing or not one row (same-glyph.py's)")
        if part["visible_pixels"] != full["visible_pixels"]:
            raise ResultsError(f"{visible.relative_to(ROOT)}: the shown glyphs show "
                               f"{part['visible_pixels']} pixels, the scene {full['visible_pixels']}")
        if not lines:
            rows = read_csv(visible) + read_csv(whole)
            lines = [measured(visible, *device_of(rows)) + " `bench --quick --frames 3`, "
                     "1920x1080, each scene's own camera; the splat's ray casts include the "
                     "resolve's one per pixel shown.", "",
                     "| scene | glyphs | glyphs shown | pixels shown per glyph shown "
                     "| covered centres per glyph shown | covered centres per pixel shown: "
                     "glyphs shown, all | ray casts per pixel shown, splat of: glyphs shown, all "
                     "| pixels showing the same glyph 0.5 degree later |",
                     "|---|---:|---:|---:|---:|---:|---:|---:|"]
        shown, glyphs = float(part["visible_pixels"]), float(part["count"])
        lines.append(f"| {scene} | {int(full['count']):,} | {int(glyphs):,} | {shown / glyphs:.0f} | "
                     f"{float(part['covered_pixels']) / glyphs:.0f} | "
                     f"{float(part['covered_pixels']) / shown:.2f}, "
                     f"{float(full['covered_pixels']) / shown:.2f} | "
                     f"{float(part['ray_casts_per_visible_pixel']):.2f}, "
                     f"{float(full['ray_casts_per_visible_pixel']):.2f} | "
                     f"{int(kept[0]['same_glyph']) / int(kept[0]['pixels_shown']):.0%} |")
    return lines


VIEWER = {"the frame summary": re.compile(r"median\): moving ([0-9.]+|-)(?: ms)? \((\d+) frames\), "
                                         r"still ([0-9.]+|-)(?: ms)? \((\d+) frames\)"),
          "'pick (X, Y): ... (T ms)'": re.compile(r"^pick \([^)]*\): .*\(([0-9.]+) ms\)$", re.M),
          "'pick shown'": re.compile(r"presented ([0-9.]+) ms after the click"),
          "'swapchain: WxH'": re.compile(r"^swapchain: (\d+x\d+)", re.M)}


def viewer(folder: str) -> list[str]:
    """scripts/viewer-figures.sh's scenes: GPU time per frame moving and still, the pick's
    read-back and the time until the highlighted frame was presented."""
    report = ROOT / folder
    logs = [p for p in files(f"{folder}/*.txt") if p.name not in ("info.txt", "about.txt")]
    if not logs:
        raise ResultsError(f"{folder} holds no scene's log (scripts/viewer-figures.sh writes them)")
    rows, sizes = [], set()
    for log in logs:
        summary, pick, shown, size = (printed(log, pattern, what)[0] for what, pattern in VIEWER.items())
        sizes.add(size.group(1))
        moving, moving_frames, still, still_frames = summary.groups()
        rows.append(f"| {log.stem} | {moving} ms ({moving_frames} frames) | {still} ms "
                    f"({still_frames} frames) | {pick.group(1)} ms | {shown.group(1)} ms |")
    return [measured(logs[0], *report_device(report)) + f" {', '.join(sorted(sizes))} (the "
            "swapchain), scripts/view-pick.script; GPU time per frame (timestamps), medians.", "",
            "| scene | moving | still | pick read-back | pick shown after |",
            "|---|---:|---:|---:|---:|"] + rows


EMBED = re.compile(r"^(.+), (1 sample|4 samples, shaded per pixel|4 samples, shaded per sample): "
                   r"median ([0-9.]+) ms per frame \((\d+) frames\)$", re.M)


def embed_bench(path: str) -> list[str]:
    """`cargo run --release --example embed -- --bench`: the host's own pass with its mesh,
    one sample against 4x MSAA shaded per pixel and per sample, per scene."""
    log = files(path)[0]
    found = [m.groups() for m in printed(log, EMBED, "'SCENE, VARIANT: median'")]
    variants = ["1 sample", "4 samples, shaded per pixel", "4 samples, shaded per sample"]
    by = {(scene, variant): float(ms) for scene, variant, ms, _ in found}
    for scene in dict.fromkeys(scene for scene, *_ in found):
        missing = [v for v in variants if (scene, v) not in by]
        if missing:
            raise ResultsError(f"{log.relative_to(ROOT)}: {scene} lacks {', '.join(missing)}")
    lines = [measured(log, *report_device(log.parent)) + " `examples/embed --bench`: the host's "
             "4x render pass with its plane mesh, 1280x720, the variants interleaved frame by "
             "frame; medians (ratio to one sample).", "",
             "| scene | " + " | ".join(variants) + " |", "|---|" + "---:|" * len(variants)]
    for scene in dict.fromkeys(scene for scene, *_ in found):
        one = by[(scene, variants[0])]
        lines.append(f"| {scene} | " + " | ".join(f"{by[(scene, v)]:.1f} ms ({by[(scene, v)] / one:.2f}x)"
                                                 for v in variants) + " |")
    return lines


def device_report(folder: str) -> list[str]:
    """scripts/device-report.sh's rows: conformance, the tests that draw, the plan's regret."""
    report = ROOT / folder
    module = helper("device-table")
    return ([measured(report / "info.txt", *report_device(report)), ""] + module.device_rows(report) +
            ["", "The plan's regret (its time over the fastest fixed path's; path and ratio), "
             "`bench --quick`, one interleaved run:", ""] + module.regret_rows(report))
