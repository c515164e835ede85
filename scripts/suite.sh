#!/usr/bin/env bash
# The tests that draw: the workspace's (the fault walks of crates/fault-layer among them, about
# two minutes on 2 cores), the host on VMA, the Python package's (its fault walk about 40 s). They run on the
# Vulkan driver the environment selects (the system's lavapipe unless VK_ICD_FILENAMES names
# another: scripts/test-drivers.sh). Cargo arguments, if any, go to both cargo runs (the
# Python tests always run whole).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
cargo build --release -q -p ellipsoid-splat-tool
target/release/ellipsoid-splat info | sed -n 's/^\(device\|driver\|Vulkan\): */suite: \1 /p'
cargo test --release --workspace "$@"
# The host on VMA needs the library's `vk-mem` feature.
cargo test --release -p ellipsoid-splat --features vk-mem --test vk_mem_host "$@"
# The Python package (crates/python), built and installed into a virtual environment.
bash "$here/scripts/test-python.sh"
