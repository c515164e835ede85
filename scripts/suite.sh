#!/usr/bin/env bash
# The tests that draw: the workspace's (the fault walks of crates/fault-layer among them, about
# two minutes on 2 cores), the host on VMA, in situ from C, the Python package's (its fault walk
# about 40 s). They run on the Vulkan driver the environment selects (the system's lavapipe
# unless VK_ICD_FILENAMES names another: scripts/test-drivers.sh). Cargo arguments, if any, go
# to the workspace's and the VMA host's cargo runs; in situ from C runs only without them (the
# Python tests always run whole).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
# The tool with its feature `mpi`: `ellipsoid-splat-mpi` and its test under mpirun build and
# run with the rest (one build of the tool for both lines; `ellipsoid-splat` links no MPI).
cargo build --release -q -p ellipsoid-splat-tool --features mpi
target/release/ellipsoid-splat info | sed -n 's/^\(device\|driver\|Vulkan\): */suite: \1 /p'
cargo test --release --workspace --features ellipsoid-splat-tool/mpi "$@"
# The host on VMA needs the library's `vk-mem` feature.
cargo test --release -p ellipsoid-splat --features vk-mem --test vk_mem_host "$@"
# In situ from C under mpirun needs the C ABI's `mpi` feature.
[ $# -gt 0 ] || cargo test --release -p ellipsoid-splat-capi --features mpi --test insitu_mpi
# The Python package (crates/python), built and installed into a virtual environment.
bash "$here/scripts/test-python.sh"
