#!/usr/bin/env bash
# What reading a file in shares costs: a million-glyph Ellipsoid CSV (random:1000000 saved by
# `render --save-scene`, 225 MB) drawn at 640x360 by one-process `ellipsoid-splat render` and
# by `ellipsoid-splat-mpi render` under mpirun with 1, 2 and 4 processes (as processes on this
# machine's cores, --oversubscribe), the file in the page cache: each run's load or share
# reading time, and its wall and CPU time (user and system, every process together: on a
# machine shared with other work the wall time is the scheduler's). Writes the runs' lines with
# the date, load and driver to OUT.
#
#   bash scripts/mpi-tool-figures.sh [OUT]      (OUT tool-shares.txt)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="$(realpath "${1:-tool-shares.txt}")"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
cd "$here"
cargo build --release -q -p ellipsoid-splat-tool --features mpi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
scene="$work/million.csv"
target/release/ellipsoid-splat render --scene random:1000000 --save-scene "$scene" \
  --width 64 --height 48 --plan draw --output "$work/made.png" >/dev/null
cat "$scene" >/dev/null
flags=(--scene "$scene" --width 640 --height 360 --plan draw --output "$work/out.png")
timing="wall %e s, CPU user %U s, system %S s"
{
  echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg) (uptime: $(uptime))"
  echo "cores: $(nproc)"
  target/release/ellipsoid-splat info | grep -E '^(device|driver):'
  mpirun --version | head -1
  echo "scene: random:1000000 as Ellipsoid CSV, $(stat -c %s "$scene") bytes;" \
    "image 640x360, --plan draw"
  echo
  echo "one process (ellipsoid-splat render; 'scene' is the whole file's load):"
  /usr/bin/time -f "$timing" target/release/ellipsoid-splat render "${flags[@]}" 2>&1 |
    grep -E '^(wrote|wall)'
  for ranks in 1 2 4; do
    echo
    echo "$ranks process(es) (ellipsoid-splat-mpi render; 'reading the shares' is the" \
      "fastest to the slowest process's):"
    /usr/bin/time -f "$timing" mpirun --oversubscribe --allow-run-as-root -n "$ranks" \
      target/release/ellipsoid-splat-mpi render "${flags[@]}" 2>&1 | grep -E '^(wrote|wall)'
  done
  echo
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$out"
