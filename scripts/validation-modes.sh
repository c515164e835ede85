#!/usr/bin/env bash
# The opt-in validation runs (not part of the default suite): the whole test suite again with
# GPU-assisted validation, then with the best-practices checks, each message printed as it
# arrives. Prints each run's outcome and the distinct message IDs with their counts.
# Usage: bash scripts/validation-modes.sh [minutes per run, default 30]
set -uo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
source "$here/scripts/setup.sh"
set +e # setup.sh sets -e; here a failing run is a result to report
cd "$here"
minutes="${1:-30}"
cargo test --release --workspace --no-run || { echo "build failed"; exit 1; }
for mode in gpu-assisted best-practices; do
    log="target/validation-$mode.log"
    echo "== $mode (up to $minutes min) =="
    start=$(date +%s)
    ELLIPSOID_SPLAT_EXTRA_VALIDATION="$mode" ELLIPSOID_SPLAT_PRINT_VALIDATION=1 \
        timeout "${minutes}m" cargo test --release --workspace --no-fail-fast -- --test-threads=1 --nocapture >"$log" 2>&1
    status=$?
    echo "exit status $status after $(( $(date +%s) - start )) s (124: timed out); log: $log"
    grep -E "^test result" "$log" | awk '{p+=$4; f+=$6} END {print "tests passed", p, "failed", f}'
    echo "distinct messages (count, ID):"
    # Each message once: as printed (not its copy inside a test's panic text).
    grep -v 'first: "' "$log" | grep -oE "\[(ERROR|WARNING|INFO|VERBOSE)\] [A-Za-z0-9_-]+" \
        | sort | uniq -c | sort -rn || true
done
