#!/usr/bin/env bash
# Key tiles that skip unmarked resolve tiles: the build before (BEFORE, the tool of the commit
# before the change) and after (AFTER), back to back, the order alternating pair by pair.
# Also for later changes: OUT (default this folder) and METHODS (default the key tiles').
set -euo pipefail
cd "${OUT:-$(dirname "$0")}"
methods="${METHODS:-impostor,impostor-visible-first}"
: "${BEFORE:?the tool built before the change}" "${AFTER:?the tool built with it}"
for pair in 1 2 3 4 5; do
  for motion in still orbit; do
    extra=(); [ "$motion" = orbit ] && extra=(--orbit 0.5)
    order=(before after); [ $((pair % 2)) = 0 ] && order=(after before)
    for build in "${order[@]}"; do
      tool=$BEFORE; [ "$build" = after ] && tool=$AFTER
      echo "$build $motion pair $pair $(date -u +%H:%M:%S) $(cut -d' ' -f1-3 /proc/loadavg)" >> log.txt
      "$tool" bench --quick --frames 9 "${extra[@]}" --methods "$methods" \
        --scenes tensor-field,lattice,md-liquid --out "/tmp/pairs-$build" > "$build-$motion-pair$pair.txt" 2>&1 || true
      cp "/tmp/pairs-$build/results.csv" "$build-$motion-pair$pair.csv"
    done
  done
done
