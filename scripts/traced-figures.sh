#!/usr/bin/env bash
# The traced path (research method `impostor-traced`, ray queries) against the splats and the
# visible-pixel floor on the deep scenes, on Mesa 25's lavapipe (the driver with ray queries):
# `lattice` and `md-liquid` at 1920x1080, the camera still and orbiting 0.5 degree a frame,
# RUNS runs alternating the two. `impostor-traced-rebuild` builds the hierarchy every frame, so
# its time less `impostor-traced`'s is the build's per upload. Only ratios within one run mean
# anything on a shared machine; run it on a quiet one.
#
#   bash scripts/traced-figures.sh [RUNS [OUT]]      (RUNS 3, OUT traced-figures)
#
# Uses target/release/ellipsoid-splat (cargo build --release -p ellipsoid-splat-tool).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/target/release/ellipsoid-splat"
runs="${1:-3}"
out="${2:-traced-figures}"
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "traced-figures: RUNS must be a positive whole number, not '$runs'" >&2; exit 2; }
[ -x "$tool" ] || { echo "traced-figures: build the tool first ($tool is missing)" >&2; exit 1; }
eval "$(bash "$here/scripts/test-drivers.sh" --env)"
mkdir -p "$out"
methods=impostor-compute,impostor-traced,impostor-visible-first,impostor-traced-rebuild,floor-visible
{ echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"; echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"; "$tool" info | grep -E '^(device|driver):'; } > "$out/machine.txt"
for run in $(seq "$runs"); do
  for motion in still orbit; do
    flag=(); [ "$motion" = orbit ] && flag=(--orbit 0.5)
    "$tool" bench --quick --frames 9 "${flag[@]}" --methods "$methods" --scenes lattice,md-liquid \
      --out "$out/$motion-run$run" > "$out/$motion-run$run.txt" 2>&1 || true
    echo "$motion run $run: load $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
  done
done
grep -h -E '^(impostor|floor)' "$out"/*-run*.txt
