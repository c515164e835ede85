#!/usr/bin/env bash
# What trajectories cost on this machine: a LAMMPS dump of three frames of 100,000 ellipsoids
# loaded frame by frame (crates/loaders/examples/particle_load_time.rs), and a 100-frame,
# 8,000-particle trajectory (scripts/make-md-samples.py, the samples' density) drawn to PNGs by
# `render --frames all` at 1920x1080, end to end (RUNS times). Writes the outputs with the
# date, load and driver into OUT.
#
#   bash scripts/trajectory-figures.sh [RUNS [OUT]]     (RUNS 3, OUT trajectory-figures)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
runs="${1:-3}"
out="${2:-trajectory-figures}"
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "trajectory-figures: RUNS must be a positive whole number, not '$runs'" >&2; exit 2; }
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
cd "$here"
cargo build --release -q -p ellipsoid-splat-tool
cargo build --release -q -p ellipsoid-splat-loaders --example particle_load_time
tool="$here/target/release/ellipsoid-splat"
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
{ echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"; echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"; echo "cores: $(nproc)"; "$tool" info | grep -E '^(device|driver):'; } > "$out/machine.txt"
target/release/examples/particle_load_time "$work" 100000 | tee "$out/load-100000.txt"
python3 scripts/make-md-samples.py --particles 8000 --frames 100 --out "$work" > /dev/null
: > "$out/render-8000x100.txt"
for run in $(seq "$runs"); do
  "$tool" render --scene "$work/gay-berne.lammpstrj" --frames all --output "$work/frame.png" \
    | tee -a "$out/render-8000x100.txt"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
