#!/usr/bin/env bash
# Set up, then run every test on lavapipe with the validation layer on.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
source "$here/scripts/setup.sh"
cd "$here"
cargo test --release --workspace "$@"
# The host on VMA needs the library's `vk-mem` feature.
cargo test --release -p ellipsoid-splat --features vk-mem --test vk_mem_host "$@"
# The library as a dependent gets it: publish dry run, the package's contents, a build
# without glslangValidator on the committed SPIR-V, the docs as docs.rs builds them.
bash "$here/scripts/package-check.sh"
# The Python package (crates/python), built and installed into a virtual environment.
bash "$here/scripts/test-python.sh"
