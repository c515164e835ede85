#!/usr/bin/env bash
# Set-up once on the bench's clouds: the build before (BEFORE) and after (AFTER), back to
# back, the order alternating pair by pair: bench --quick --frames 9, METHODS (default the
# plain splat, impostor-compute) on SCENES (default cloud), into OUT (default this folder).
# log.txt: start times and load averages.
set -euo pipefail
cd "${OUT:-$(dirname "$0")}"
methods="${METHODS:-impostor-compute}"
scenes="${SCENES:-cloud}"
: "${BEFORE:?the tool built before the change}" "${AFTER:?the tool built with it}"
for pair in 1 2; do
  order=(before after); [ $((pair % 2)) = 0 ] && order=(after before)
  for build in "${order[@]}"; do
    tool=$BEFORE; [ "$build" = after ] && tool=$AFTER
    echo "$build pair $pair $(date -u +%H:%M:%S) $(cut -d' ' -f1-3 /proc/loadavg)" >> log.txt
    "$tool" bench --quick --frames 9 --methods "$methods" --scenes "$scenes" \
      --out "/tmp/clouds-$build" > "$build-pair$pair.txt" 2>&1 || true
    cp "/tmp/clouds-$build/results.csv" "$build-pair$pair.csv"
  done
done
