#!/usr/bin/env bash
# Where the visible-first splat's frame goes on lavapipe: a timestamp before each pre-pass
# dispatch (stamps.diff in ../2026-11-27e, a temporary build: `git apply` it, build the tool;
# TOOL names it), three rounds of
# each deep scene still and orbiting 0.5 degree a frame, one bench run each. Each run's log
# holds the bench's table and one `stamps:` line per frame (the pre-pass's dispatches in ms,
# in the order of `prepass_dispatches` in src/renderer/prepass/mod.rs).
set -euo pipefail
cd "$(dirname "$0")"
tool=${TOOL:-../../../../target/release/ellipsoid-splat}
uptime > load.txt
for round in 1 2 3; do
  for scene in lattice md-liquid tensor-field; do
    for motion in still orbit; do
      extra=(); [ "$motion" = orbit ] && extra=(--orbit 0.5)
      ES_STAMPS=1 "$tool" bench --quick --frames 15 "${extra[@]}" --scenes "$scene" \
        --methods impostor-visible-first --out "$motion-$scene-run$round" \
        > "$motion-$scene-run$round.txt" 2>&1 || true
    done
  done
done
uptime >> load.txt
