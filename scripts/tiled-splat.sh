#!/usr/bin/env bash
# The benchmark's tiled splat (`impostor-tiled`) beside the compute splat, the visible-first
# splat and the visible-pixel floor on the deep scenes (`lattice`, `md-liquid`), the camera
# still and orbiting 0.5 degree a frame, at 1920x1080: one bench run per motion and run, each
# timing every method in the same process (only ratios inside one run compare on a busy
# machine). Writes each run's results.csv and log into OUT and a line per scene, motion and run
# with each method's median and the tiled splat's time over the splat's.
#
#   bash scripts/tiled-splat.sh [RUNS [OUT]]      (RUNS 3, OUT tiled-splat)
#
# Uses target/release/ellipsoid-splat (cargo build --release -p ellipsoid-splat-tool).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/target/release/ellipsoid-splat"
runs="${1:-3}"
out="${2:-tiled-splat}"
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "tiled-splat: RUNS must be a positive whole number, not '$runs'" >&2; exit 2; }
[ -x "$tool" ] || { echo "tiled-splat: build the tool first ($tool is missing)" >&2; exit 1; }
mkdir -p "$out"
methods=impostor-compute,impostor-visible-first,floor-visible,impostor-tiled
{ echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"; echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"; "$tool" info | grep -E '^(device|driver):'; } > "$out/machine.txt"
for run in $(seq "$runs"); do
  for motion in still orbit; do
    flag=(); [ "$motion" = orbit ] && flag=(--orbit 0.5)
    "$tool" bench --quick --frames 9 "${flag[@]}" --methods "$methods" --scenes lattice,md-liquid \
      --out "$out/$motion-run$run" > "$out/$motion-run$run.txt" 2>&1 || true
    echo "load after $motion-run$run: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
  done
done
# Per scene, motion and run: each method's median ms and ray casts per visible pixel, and the
# tiled splat over the compute splat.
python3 - "$out" <<'PY'
import csv, glob, os, sys
out = sys.argv[1]
for path in sorted(glob.glob(os.path.join(out, "*-run*", "results.csv"))):
    run = os.path.basename(os.path.dirname(path))
    rows = list(csv.DictReader(open(path)))
    for scene in sorted({r["scene"] for r in rows}):
        ms = {r["method"]: r for r in rows if r["scene"] == scene}
        cells = []
        for m in ("impostor-compute", "impostor-visible-first", "floor-visible", "impostor-tiled"):
            if m in ms:
                r = ms[m]
                casts = r.get("ray_casts_per_visible_pixel") or "-"
                cells.append(f"{m} {float(r['wall_ms']):.1f} ms ({casts} casts/visible px)")
        ratio = ""
        if "impostor-tiled" in ms and "impostor-compute" in ms:
            ratio = f" tiled/compute {float(ms['impostor-tiled']['wall_ms']) / float(ms['impostor-compute']['wall_ms']):.2f}"
        print(f"{run} {scene}: " + "; ".join(cells) + ratio)
PY
