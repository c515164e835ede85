#!/usr/bin/env bash
# Where the visible-first splat's frame goes: three rounds of each deep scene still and
# orbiting 0.5 degree a frame, one `bench --quick --frames 15` run each, with a tool built
# with a timestamp before each pre-pass dispatch (the temporary patch
# docs/results/deep/2026-11-27e/stamps.diff, against commit c663104; not part of the code).
# Each run's log holds the bench's table and one `stamps:` line per frame (the pre-pass's
# dispatches in ms, in the order of `prepass_dispatches` in src/renderer/prepass/mod.rs);
# scripts/tables.py makes the stage profile's table from them. Several patched tools (builds
# to compare) take turns run by run, each into a folder of OUT named after the tool's file.
#
#   bash scripts/stage-profile.sh OUT_DIR PATCHED_TOOL [PATCHED_TOOL...]
set -euo pipefail
out="${1:?stage-profile: give the results folder}"
[ $# -ge 2 ] || { echo "stage-profile: give the patched tool" >&2; exit 2; }
tools=()
for tool in "${@:2}"; do
  for other in "${tools[@]}"; do
    [ "$(basename "$other")" != "$(basename "$tool")" ] \
      || { echo "stage-profile: two tools named $(basename "$tool"): each needs a folder of its own" >&2; exit 2; }
  done
  tools+=("$(realpath "$tool")")
done
mkdir -p "$out"
cd "$out"
uptime > load.txt
for round in 1 2 3; do
  for scene in lattice md-liquid tensor-field; do
    for motion in still orbit; do
      extra=(); [ "$motion" = orbit ] && extra=(--orbit 0.5)
      for tool in "${tools[@]}"; do
        dir=.; [ ${#tools[@]} -gt 1 ] && dir="$(basename "$tool")" && mkdir -p "$dir"
        run="$dir/$motion-$scene-run$round"
        ES_STAMPS=1 "$tool" bench --quick --frames 15 "${extra[@]}" --scenes "$scene" \
          --methods impostor-visible-first --out "$run" > "$run.txt" 2>&1 || true
        # bench exits 1 where a target of its own is missed: only a missing result is a failure.
        [ -s "$run/results.csv" ] \
          || echo "stage-profile: $run: no results.csv (its log says why)" >&2
      done
    done
  done
done
uptime >> load.txt
