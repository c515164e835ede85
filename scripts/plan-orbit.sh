#!/usr/bin/env bash
# What exploring costs the viewer: 100 frames of orbit (scripts/view-orbit-100.script, then
# nine still frames) with the plan measuring against the same frames with the plan fixed to
# one path, interleaved run by run, under Xvfb. Prints each run's GPU time of all frames and
# the frames per path taken, and per scene the median over the runs of measure's time over
# the fixed path's.
#
#   bash scripts/plan-orbit.sh [RUNS [FIXED [SCENE ...]]]
#       RUNS 5, FIXED splat (the fastest fixed path of both default scenes' moving frames on
#       lavapipe), scenes md-liquid tensor-field
#
# Uses target/release/ellipsoid-splat (cargo build --release -p ellipsoid-splat-tool).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
tool="$here/target/release/ellipsoid-splat"
runs="${1:-5}"
fixed="${2:-splat}"
shift $(($# > 2 ? 2 : $#))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(md-liquid tensor-field)
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "plan-orbit: RUNS must be a positive whole number, not '$runs'" >&2; exit 2; }
case "$fixed" in draw | splat | visible-first | estimate) ;;
  *) echo "plan-orbit: FIXED must be draw, splat, visible-first or estimate, not '$fixed'" >&2; exit 2 ;;
esac
[ -x "$tool" ] || { echo "plan-orbit: build the tool first ($tool is missing)" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "plan-orbit: xvfb-run is missing (scripts/setup.sh)" >&2; exit 1; }

log="$(mktemp)"
trap 'rm -f "$log"' EXIT
echo "plan-orbit: $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
for run in $(seq "$runs"); do
  for scene in "${scenes[@]}"; do
    for plan in measure "$fixed"; do
      out="$(timeout 600 xvfb-run -a "$tool" view --no-vsync --plan "$plan" --scene "$scene" \
        --script "$here/scripts/view-orbit-100.script" --width 1920 --height 1080 2>&1)" || {
        echo "plan-orbit: the viewer failed on $scene with --plan $plan:" >&2
        echo "$out" | tail -n 5 >&2
        exit 1
      }
      total="$(echo "$out" | sed -n 's/.*all frames \([0-9.]*\) ms.*/\1/p')"
      [ -n "$total" ] || { echo "plan-orbit: no frame times from the viewer ($scene, $plan)" >&2; exit 1; }
      echo "$run $scene $plan: all frames $total ms; $(echo "$out" | grep '^paths (frames)' || true)" | tee -a "$log"
    done
  done
done
echo
python3 "$here/scripts/orbit-table.py" "$log"
