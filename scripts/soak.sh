#!/usr/bin/env bash
# The viewer's long run: `view` under Xvfb with validation on, driven by a script that orbits,
# zooms, recolours glyphs, steps through a trajectory (a whole new scene each step), resizes,
# minimises and restores, over and over for about MINUTES minutes. Every 30 seconds it samples
# the viewer's resident memory, open files and threads; the viewer's own `memory` lines give
# the GPU memory. Writes OUT/soak.csv (the samples), OUT/view.txt (the viewer's output) and
# OUT/machine.txt. The run ends by `--exit-after`, a frame count measured from a first minute,
# so the viewer closes itself and reports its validation messages.
#   bash scripts/soak.sh [MINUTES] [OUT] [--no-validation]   (defaults: 60, target/soak)
# Without validation the memory figures are the viewer's own (the layer keeps state of its own).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
minutes="${1:-60}"
out="${2:-$here/target/soak}"
validation="--validation"; validated=on
[ "${3:-}" = "--no-validation" ] && validation="" && validated=off
tool="$here/target/release/ellipsoid-splat"
scene="$here/data/samples/gay-berne.lammpstrj"
# The viewer's command line as `ps` shows it, to find it and to stop the calibration.
viewer="$tool view ${validation:+$validation }--no-vsync"
[ -x "$tool" ] || { echo "soak: build the tool first (cargo build --release)" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "soak: xvfb-run is missing (scripts/setup.sh)" >&2; exit 1; }
mkdir -p "$out"

# One cycle of 200 frames; the script repeats it up to the frame count.
cycle() {
  local f=$1
  echo "$((f + 0)) drag left 320 240 480 250 60"
  echo "$((f + 65)) wheel 320 240 2"
  echo "$((f + 70)) animate 30"
  echo "$((f + 105)) key N"
  echo "$((f + 115)) wheel 320 240 -2"
  echo "$((f + 120)) resize 800 600"
  echo "$((f + 140)) resize 640 480"
  echo "$((f + 150)) minimise"
  echo "$((f + 160)) restore"
  echo "$((f + 170)) key C"
  echo "$((f + 180)) key R"
  echo "$((f + 190)) memory"
}
script_for() {
  local frames=$1 f=10
  while [ "$f" -lt "$frames" ]; do cycle "$f"; f=$((f + 200)); done
}

run_view() { # FRAMES SCRIPT LOG
  nice -n 10 xvfb-run -a -s "-screen 0 1024x768x24" "$tool" view $validation --no-vsync \
    --width 640 --height 480 --script "$2" --exit-after "$1" "$scene" >"$3" 2>&1
}

# The frame rate on this machine now, from one minute with the same script.
script_for 2000000 >"$out/calibrate.script"
run_view 2000000 "$out/calibrate.script" "$out/calibrate.txt" &
started=$(date +%s)
sleep 60
pkill -f "^$viewer" || true
wait || true
calibrated=$(grep -o '^memory: frame [0-9]*' "$out/calibrate.txt" | tail -1 | awk '{print $3}')
elapsed=$(( $(date +%s) - started ))
[ -n "$calibrated" ] || { echo "soak: the calibration drew no frames:" >&2; cat "$out/calibrate.txt" >&2; exit 1; }
frames=$(( calibrated * minutes * 60 / elapsed ))
echo "soak: about $((calibrated / elapsed)) frames a second; running $frames frames"
script_for "$frames" >"$out/soak.script"

{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "machine: $(nproc) cores, $(awk '/MemTotal/ {print int($2/1048576)}' /proc/meminfo) GiB"
  "$tool" info | sed -n 's/^\(device\|driver\|Vulkan\): */\1: /p'
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "scene: data/samples/gay-berne.lammpstrj, 640x480 window, validation $validated"
} >"$out/machine.txt"

run_view "$frames" "$out/soak.script" "$out/view.txt" &
runner=$!
echo "seconds,rss_kib,open_files,threads" >"$out/soak.csv"
start=$(date +%s)
pid=""
while kill -0 "$runner" 2>/dev/null; do
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null || pid=$(pgrep -f "^$viewer" | head -1 || true)
  if [ -n "$pid" ] && [ -r "/proc/$pid/status" ]; then
    rss=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo "")
    threads=$(awk '/Threads/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo "")
    files=$(ls "/proc/$pid/fd" 2>/dev/null | wc -l)
    [ -n "$rss" ] && echo "$(( $(date +%s) - start )),$rss,$files,$threads" >>"$out/soak.csv"
  fi
  sleep 30
done
wait "$runner"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/machine.txt"
echo "wall seconds: $(( $(date +%s) - start ))" >>"$out/machine.txt"
grep -E '^(validation messages|frames|memory: frame)' "$out/view.txt" | tail -3
