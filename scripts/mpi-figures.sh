#!/usr/bin/env bash
# What sort-last compositing costs on this machine: crates/mpi's composite-bench under mpirun
# with 1, 2, 3, 4 and 8 processes (as processes on this machine's cores, --oversubscribe), a
# million glyphs split evenly, at 640x360 and 1920x1080. Writes each run's output with the
# date, load and driver into OUT.
#
#   bash scripts/mpi-figures.sh [OUT]      (OUT mpi-figures)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-mpi-figures}"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
cd "$here"
cargo build --release -q -p ellipsoid-splat-mpi --bins
cargo build --release -q -p ellipsoid-splat-tool
mkdir -p "$out"
{ echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"; echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"; echo "cores: $(nproc)"; target/release/ellipsoid-splat info | grep -E '^(device|driver):'; mpirun --version | head -1; } > "$out/machine.txt"
for size in 640x360 1920x1080; do
  for ranks in 1 2 3 4 8; do
    mpirun --oversubscribe --allow-run-as-root -n "$ranks" target/release/composite-bench "$size" 1000000 5 \
      > "$out/composite-$size-$ranks.txt"
    tail -n 1 "$out/composite-$size-$ranks.txt"
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
