#!/usr/bin/env bash
# Set up, then run every test on lavapipe with the validation layer on.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
source "$here/scripts/setup.sh"
cd "$here"
cargo test --release --workspace "$@"
# The host on VMA needs the library's `vk-mem` feature.
cargo test --release -p ellipsoid-splat --features vk-mem --test vk_mem_host "$@"
