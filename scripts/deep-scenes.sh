#!/usr/bin/env bash
# Deep scenes against a CPU ray tracer on the same cores: `lattice` and `md-liquid`, the camera
# still and orbiting, our exact paths (bench, with ray casts per visible pixel) alternating run
# by run with Mitsuba 3 (scripts/cpu-raytracer.py, where `python3 -c 'import mitsuba'` works;
# set PYTHON to another interpreter). Writes each run's files into OUT and prints the table of
# the medians over the runs (scripts/deep-table.py OUT makes it again from the files).
# METHODS names other bench methods (research ones: impostor-tiled, or impostor-traced on Mesa
# 25's lavapipe, which DRIVERS=mesa-25 selects); then Mitsuba is left out and each run's lines
# are printed instead of the table.
#
#   bash scripts/deep-scenes.sh [RUNS [OUT]]      (RUNS 3, OUT deep-scenes)
#   METHODS=impostor-compute,impostor-visible-first,floor-visible,impostor-tiled bash scripts/deep-scenes.sh 2 tiled
#   DRIVERS=mesa-25 METHODS=impostor-compute,impostor-traced,impostor-visible-first,impostor-traced-rebuild,floor-visible bash scripts/deep-scenes.sh 2 traced
#
# Uses target/release/ellipsoid-splat (cargo build --release -p ellipsoid-splat-tool).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/target/release/ellipsoid-splat"
runs="${1:-3}"
out="${2:-deep-scenes}"
python="${PYTHON:-python3}"
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "deep-scenes: RUNS must be a positive whole number, not '$runs'" >&2; exit 2; }
[ -x "$tool" ] || { echo "deep-scenes: build the tool first ($tool is missing)" >&2; exit 1; }
mkdir -p "$out"
default_methods=impostor,impostor-draw,impostor-compute,impostor-visible-first,floor-visible
methods="${METHODS:-$default_methods}"
case "${DRIVERS:-}" in
  "") ;;
  mesa-25) eval "$(bash "$here/scripts/test-drivers.sh" --env)" ;;
  *) echo "deep-scenes: DRIVERS is empty or mesa-25, not '$DRIVERS'" >&2; exit 2 ;;
esac
tracer=yes
if [ "$methods" != "$default_methods" ]; then
  tracer=no
elif ! "$python" -c 'import mitsuba' 2>/dev/null; then
  tracer=no; echo "deep-scenes: no Mitsuba for $python (pip install mitsuba): our side alone" >&2
fi
started="$(date -u '+%Y-%m-%d %H:%M')"
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$tracer" = yes ]; then  # the scene files the ray tracer reads
  for scene in lattice md-liquid; do
    "$tool" render --scene "$scene" --save-scene "$out/$scene.csv" --output "$out/$scene.png" > /dev/null 2>&1
  done
fi
{ echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"; echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "cpu: $(nproc) cores of $(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -n 1)"; echo "build: $(git -C "$here" rev-parse --short HEAD)"; "$tool" info | grep -E '^(device|driver):'; } > "$out/machine.txt"
for run in $(seq "$runs"); do
  for motion in still orbit; do
    flag=(); [ "$motion" = orbit ] && flag=(--orbit 0.5)
    "$tool" bench --quick --frames 9 "${flag[@]}" --methods "$methods" --scenes lattice,md-liquid \
      --out "$out/$motion-run$run" > "$out/$motion-run$run.txt" 2>&1 || true
    echo "load after $motion-run$run: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
  done
  if [ "$tracer" = yes ]; then
    for scene in lattice md-liquid; do
      "$python" "$here/scripts/cpu-raytracer.py" "$out/$scene.csv" --frames 9 --orbit 0.5 \
        > "$out/tracer-$scene-run$run.txt"
    done
  fi
done
# When, where and with which build: the line scripts/tables.py sets beside the folder's tables.
cat > "$out/about.txt" <<ABOUT
# scripts/deep-scenes.sh with methods $methods; machine.txt has the load after each run.
# files | date | machine
* | $started-$(date -u +%H:%M) UTC | $(nproc) CPU cores of $(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -n 1) (load average $load_before before, $(cut -d' ' -f1-3 /proc/loadavg) after), build $(git -C "$here" rev-parse --short HEAD)
ABOUT
if [ "$methods" = "$default_methods" ]; then
  python3 "$here/scripts/deep-table.py" "$out"
else
  grep -H -E '^(impostor|floor)' "$out"/*-run*.txt
fi
