#!/usr/bin/env bash
# The main job: set up, build, and render the default demo to ./ellipsoids.png.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
source "$here/scripts/setup.sh"
cargo build --release --manifest-path "$here/Cargo.toml" -p ellipsoid-splat-tool
"$here/target/release/ellipsoid-splat" "$@"
