#!/usr/bin/env bash
# The instance-order runs (about.txt): a tool built from 6d79985 with
# ../../2026-11-28e/frame-stamps.diff and ../instance-order-shuffled.diff, run ROUNDS times on
# lattice and md-liquid orbiting, the scene order (scene-order/) and the shuffled one
# (shuffled/) taking turns, each run's log and results.csv in the stage profile's layout.
#
#   bash run.sh TOOL OUT_DIR [ROUNDS]
set -euo pipefail
tool="$(realpath "${1:?run.sh: give the tool built with both diffs}")"
out="${2:?run.sh: give the results folder}"
rounds="${3:-8}"
for round in $(seq 1 "$rounds"); do
  for scene in md-liquid lattice; do
    for order in scene-order shuffled; do
      run="$out/$order/orbit-$scene-run$round"
      mkdir -p "$out/$order"
      shuffle=""; [ "$order" = shuffled ] && shuffle=shuffle
      # bench exits 1 where a target of its own is missed: only a missing result is a failure.
      ES_ORDER="$shuffle" ES_STAMPS=1 "$tool" bench --quick --frames 9 --orbit 0.5 \
        --scenes "$scene" --methods impostor-visible-first --out "$run" > "$run.txt" 2>&1 || true
      [ -s "$run/results.csv" ] || { echo "run.sh: $run: no results.csv (its log says why)" >&2; exit 1; }
      rm -f "$run"/*.png
    done
  done
done
