#!/usr/bin/env bash
# Installs what ellipsoid-splat needs on Debian 12 if it is missing: the shader compiler,
# lavapipe (Mesa's CPU Vulkan driver) with the loader, the Khronos validation layer, and Xvfb
# (with xauth, for xvfb-run) so the `view` tests open a real window without a display; and for
# the C ABI's tests the Vulkan headers, a C and C++ compiler, CMake, pkg-config and Dear ImGui;
# for the Python package's, venv (maturin, NumPy and pytest come from PyPI into target/); and
# ffmpeg, which `render --movie` pipes frames to (its tests read the movie back with ffprobe);
# and for sort-last compositing (crates/mpi), Debian's OpenMPI with libclang for its bindings.
set -euo pipefail

packages=(glslang-tools mesa-vulkan-drivers libvulkan1 vulkan-validationlayers fonts-dejavu-core xvfb xauth
  libvulkan-dev g++ cmake pkg-config libimgui-dev python3-venv python3-dev ffmpeg
  openmpi-bin libopenmpi-dev libclang-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

if ! command -v cargo >/dev/null 2>&1; then
  [ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
fi
if ! command -v cargo >/dev/null 2>&1; then
  echo "cargo not found: install Rust (stable, 1.85 or newer) with rustup, see https://rustup.rs" >&2
  exit 1
fi
