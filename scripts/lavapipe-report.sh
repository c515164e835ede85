#!/usr/bin/env bash
# The lavapipe runs that the docs' one-off figures lack (they say "a one-off, not committed"):
# scripts/device-report.sh on lavapipe (info, conformance, the tests that draw, `bench --quick`
# with its antialiasing run), then `bench --skip --quick`, into
# docs/results/devices/lavapipe-mesa-VERSION-DATE/ with the about.txt scripts/tables.py reads.
# Timings: run it on a quiet machine (nothing else building; on 2 cores it takes about an
# hour), under the driver the environment selects (for Mesa 25:
# eval "$(bash scripts/test-drivers.sh --env)" first). Then register the folder's tables in
# scripts/tables.py beside the H200's (the same makers take it), put their markers in the docs,
# and run python3 scripts/tables.py.
#
#   bash scripts/lavapipe-report.sh
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"

cargo build --release -q -p ellipsoid-splat-tool
tool="target/release/ellipsoid-splat"
mesa="$("$tool" info --device llvmpipe | sed -n 's/^driver:.*Mesa \([0-9][0-9.]*\).*/\1/p')"
[ -n "$mesa" ] || { echo "lavapipe-report: 'info --device llvmpipe' names no Mesa version" >&2; exit 1; }
out="docs/results/devices/lavapipe-mesa-$mesa-$(date -u +%Y-%m-%d)"
[ ! -e "$out" ] || { echo "lavapipe-report: $out exists; move it away first" >&2; exit 1; }
started="$(date -u '+%Y-%m-%d %H:%M')"
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
# Every lavapipe time depends on the CPU: its model goes beside the figures.
cpu="$(sed -n 's/^model name[[:space:]]*: *//p' /proc/cpuinfo | head -n 1)"
cpu="${cpu:-an unnamed CPU}"

bash scripts/device-report.sh --device llvmpipe --out "$out"
echo "== bench --skip --quick"
"$tool" bench --skip --quick --device llvmpipe --out "$out/skip" > "$out/skip.txt" 2>&1 \
  || echo "bench --skip exited $? (a missed target exits 1)" >> "$out/skip.txt"
mv "$out/skip/skip.csv" "$out/skip.csv"

# When, where and with which build: the line tables.py sets beside every table of the folder.
cat > "$out/about.txt" <<EOF
# When, where and with which build the files here ran; scripts/tables.py sets this line beside
# every table it makes from them (device and driver it reads from the files themselves).
# files | date | machine
* | $started-$(date -u +%H:%M) UTC | $(nproc) CPU cores of $cpu (load average $load_before before, $(cut -d' ' -f1-3 /proc/loadavg) after), build $(git rev-parse --short HEAD)
EOF
echo "lavapipe-report: wrote $out"
