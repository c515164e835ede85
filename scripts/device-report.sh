#!/usr/bin/env bash
# The report of one Vulkan device: `info`, `conformance`, the tests that draw and
# `bench --quick` (with the plan's regret) into one folder, and the per-device table row made
# from them (table.md; committed under docs/results/devices/ and linked from docs/conformance.md).
#
#   bash scripts/device-report.sh [--out DIR] [--device NAME|INDEX] [--tests DIR] [--frames N]
#   bash scripts/device-report.sh --prepare DIR
#
# With cargo it builds what it runs. Where cargo is missing (a GPU machine the checkout is
# copied to), `--prepare DIR` on a build machine puts the tool and the drawing tests'
# executables into DIR, and `--tests DIR` there runs them (the tool is taken from DIR too).
# `--device` picks the device as `render --device` does (also for the tests, through
# ELLIPSOID_SPLAT_DEVICE); by default a real GPU is preferred over lavapipe.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"

out="device-report"
device=""
tests=""
prepare=""
frames=15
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="${2:?--out needs a folder}"; shift 2 ;;
    --device) device="${2:?--device needs a name or index}"; shift 2 ;;
    --tests) tests="${2:?--tests needs a folder}"; shift 2 ;;
    --prepare) prepare="${2:?--prepare needs a folder}"; shift 2 ;;
    --frames) frames="${2:?--frames needs a count}"; shift 2 ;;
    *) echo "device-report: unknown argument '$1' (see the comment at the top of $0)" >&2; exit 2 ;;
  esac
done

# The library's tests that draw, with the benchmark's baselines (as the suite runs them).
test_args=(--release -p ellipsoid-splat --features research --tests)

if [ -n "$prepare" ]; then
  command -v cargo >/dev/null || { echo "device-report: --prepare needs cargo" >&2; exit 1; }
  mkdir -p "$prepare"
  cargo build --release -q -p ellipsoid-splat-tool
  cp target/release/ellipsoid-splat "$prepare/"
  # Each test executable that draws, by its test's name (cargo's names carry a hash); the
  # minimal host's test runs the example beside it, in ../examples.
  cargo test "${test_args[@]}" --no-run --message-format=json 2>/dev/null \
    | python3 -c '
import json, shutil, sys, os
dest = sys.argv[1]
skip = {"public_surface", "committed_spirv", "docs_told_once"}  # they read the sources, draw nothing
for line in sys.stdin:
    message = json.loads(line)
    if message.get("reason") == "compiler-artifact" and message.get("executable") \
            and message["target"]["kind"] == ["test"] and message["target"]["name"] not in skip:
        shutil.copy(message["executable"], os.path.join(dest, "test-" + message["target"]["name"]))
' "$prepare"
  mkdir -p "$prepare/../examples"
  cp target/release/examples/minimal "$prepare/../examples/"
  # Smaller to carry; the tests need no symbols.
  strip "$prepare"/* "$prepare/../examples/minimal" 2>/dev/null || true
  echo "device-report: $(ls "$prepare" | wc -l) executables in $prepare"
  exit 0
fi

mkdir -p "$out"
if [ -n "$tests" ]; then
  tool="$tests/ellipsoid-splat"
else
  cargo build --release -q -p ellipsoid-splat-tool
  tool="target/release/ellipsoid-splat"
fi
[ -x "$tool" ] || { echo "device-report: no tool at $tool" >&2; exit 1; }
device_args=()
if [ -n "$device" ]; then
  device_args=(--device "$device")
  export ELLIPSOID_SPLAT_DEVICE="$device"
fi
date -u '+%Y-%m-%d %H:%M UTC' > "$out/date.txt"
uptime > "$out/load.txt" || true

echo "== info"
"$tool" info "${device_args[@]}" | tee "$out/info.txt"

echo "== conformance"
status=0
"$tool" conformance "${device_args[@]}" --junit "$out/conformance.xml" \
  > "$out/conformance.txt" 2>&1 || status=$?
tail -n 3 "$out/conformance.txt"
echo "$status" > "$out/conformance.status"

echo "== the tests that draw"
: > "$out/tests.txt"
if [ -n "$tests" ]; then
  # Each under a time limit: a test that loses the device may leave the next ones hanging.
  for exe in "$tests"/test-*; do
    echo "-- ${exe##*/}" >> "$out/tests.txt"
    timeout 300 "$exe" --test-threads 1 >> "$out/tests.txt" 2>&1 \
      || echo "-- ${exe##*/} exited $?" >> "$out/tests.txt"
  done
else
  cargo test "${test_args[@]}" --no-fail-fast -- --test-threads 1 >> "$out/tests.txt" 2>&1 || true
fi
grep -E '^test result:' "$out/tests.txt" | tail -n 40 || true

echo "== bench --quick"
"$tool" bench --quick --frames "$frames" "${device_args[@]}" --out "$out/bench" \
  > "$out/bench.txt" 2>&1 || echo "bench exited $? (a missed target exits 1)" >> "$out/bench.txt"
tail -n 40 "$out/bench.txt"

python3 "$here/scripts/device-table.py" "$out" | tee "$out/table.md"
