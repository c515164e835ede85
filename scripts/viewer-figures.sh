#!/usr/bin/env bash
# The viewer's figures (docs/viewer.md, table `viewer-lavapipe`): each scene in a real window
# under Xvfb, 1280x720, --no-vsync, no validation, driven by scripts/view-pick.script (two
# orbits, still frames, a click at the centre). Writes each scene's printed lines and an
# about.txt into OUT; scripts/tables.py makes the table from them. Timings: run it on a quiet
# machine.
#
#   bash scripts/viewer-figures.sh OUT
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:?viewer-figures: name an output folder}"
tool="$here/target/release/ellipsoid-splat"
[ -x "$tool" ] || { echo "viewer-figures: build the tool first ($tool is missing)" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "viewer-figures: xvfb-run is missing (scripts/setup.sh installs it)" >&2; exit 1; }
[ ! -e "$out" ] || { echo "viewer-figures: $out exists; move it away first" >&2; exit 1; }
mkdir -p "$out"
out="$(cd "$out" && pwd)"  # the scenes are named from the repository root below
started="$(date -u '+%Y-%m-%d %H:%M')"
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
"$tool" info | grep -E '^(device|driver):' > "$out/info.txt"
cd "$here"
for scene in tensor-field data/samples/splats.ply random:1000000; do
  name="$(basename "$scene" .ply)"; name="${name//:/-}"
  xvfb-run -a -s "-screen 0 1280x720x24" "$tool" view --scene "$scene" --no-vsync \
    --width 1280 --height 720 --script "$here/scripts/view-pick.script" > "$out/$name.txt" 2>&1 \
    || { echo "viewer-figures: the viewer failed on $scene (see $out/$name.txt)" >&2; exit 1; }
done
cpu="$(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -n 1)"
cat > "$out/about.txt" <<ABOUT
# When, where and with which build the files here ran (scripts/viewer-figures.sh).
# files | date | machine
* | $started-$(date -u +%H:%M) UTC | $(nproc) CPU cores of ${cpu:-an unnamed CPU} (load average $load_before before, $(cut -d' ' -f1-3 /proc/loadavg) after), build $(git -C "$here" rev-parse --short HEAD)
ABOUT
echo "viewer-figures: wrote $out"
