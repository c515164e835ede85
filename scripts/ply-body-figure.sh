#!/usr/bin/env bash
# The figure behind `crates/loaders/src/ply.rs`'s own binary body reader: 100,000 reference
# splats read by `parse_ply` and by ply-rs-bw's generic reader, interleaved ROUNDS times
# (crates/loaders/examples/ply_body_time.rs). Prints the date, cores and load with it; run it
# on a quiet machine.
#
#   bash scripts/ply-body-figure.sh [ROUNDS]     (ROUNDS 7)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
rounds="${1:-7}"
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "ply-body-figure: ROUNDS must be a positive whole number, not '$rounds'" >&2; exit 2; }
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
cd "$here"
cargo build --release -q -p ellipsoid-splat-loaders --example ply_body_time
echo "date: $(date -u '+%Y-%m-%d %H:%M UTC'); cores: $(nproc); load: $(cut -d' ' -f1-3 /proc/loadavg)"
target/release/examples/ply_body_time 100000 "$rounds"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
