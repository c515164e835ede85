#!/usr/bin/env bash
# What the visible-first splat's first pass walks (docs/deep-scenes.md, "What would reach the
# ray tracer"): for each deep scene, the glyphs its frame shows benched alone with the same
# camera (SCENE-visible/) beside the whole scene as the same file's rows (SCENE-all/), and how
# many shown pixels keep their glyph a bench orbit step later (SCENE-turned.csv). Only
# counts are read (covered centres, ray casts), no timings. The scene CSVs and images go to a
# temporary folder; each render's output stays beside the results.
#
#   bash run.sh TOOL OUT_DIR
set -euo pipefail
tool="$(realpath "${1:?run.sh: give the tool (target/release/ellipsoid-splat)}")"
out="${2:?run.sh: give the results folder}"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
for scene in lattice md-liquid tensor-field; do
  "$tool" render --scene "$scene" --width 1920 --height 1080 --output "$work/$scene.png" \
    --id "$work/$scene-id.png" --save-scene "$work/$scene.csv" > "$out/$scene-render.txt" 2>&1 \
    || { echo "run.sh: render of $scene failed ($out/$scene-render.txt says why)" >&2; exit 1; }
  flags="$(python3 "$here/visible-glyphs.py" "$work/$scene.csv" "$work/$scene-id.png" \
    "$work/$scene-visible.csv")"
  [ -n "$flags" ] || { echo "run.sh: visible-glyphs.py gave no camera for $scene" >&2; exit 1; }
  read -r -a camera <<<"$flags"
  # The near plane render chose (visible-glyphs.py leaves it out of the bench's flags).
  near="$(head -n 1 "$work/$scene.csv" | sed -n 's/.*--near \([^ ]*\).*/\1/p')"
  tail -n +2 "$work/$scene.csv" > "$work/$scene-all.csv"
  # The same frame a bench orbit step later (0.5 degree): which pixels keep their glyph.
  turned_flags="$(python3 "$here/turned-camera.py" 0.5 <<<"$flags")"
  [ -n "$turned_flags" ] || { echo "run.sh: turned-camera.py gave no camera for $scene" >&2; exit 1; }
  read -r -a turned <<<"$turned_flags"
  "$tool" render --scene "$scene" "${turned[@]}" --near "$near" --output "$work/$scene-turned.png" \
    --id "$work/$scene-turned-id.png" > "$out/$scene-turned-render.txt" 2>&1 \
    || { echo "run.sh: render of $scene turned failed ($out/$scene-turned-render.txt)" >&2; exit 1; }
  python3 "$here/same-glyph.py" "$work/$scene-id.png" "$work/$scene-turned-id.png" > "$out/$scene-turned.csv"
  for part in visible all; do
    # bench exits 1 where a target of its own is missed: only a missing result is a failure.
    "$tool" bench --quick --frames 3 --scene "$work/$scene-$part.csv" "${camera[@]}" \
      --methods impostor-compute --out "$out/$scene-$part" > "$out/$scene-$part.txt" 2>&1 || true
    [ -s "$out/$scene-$part/results.csv" ] || { echo "run.sh: $scene-$part: no results.csv" >&2; exit 1; }
    rm -f "$out/$scene-$part"/*.png
  done
done
