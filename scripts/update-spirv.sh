#!/usr/bin/env bash
# Refreshes spirv/, the committed SPIR-V that build.rs falls back to where glslangValidator is
# missing (and on docs.rs): builds the library with every feature, so build.rs compiles every
# shader and variant with the installed compiler, and copies what it made. Run after changing
# anything under glsl/; the test `committed_spirv` fails until then.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"

compiler="${GLSLANG_VALIDATOR:-glslangValidator}"
if ! compiler="$(command -v "$compiler")"; then
  echo "update-spirv: glslangValidator not found (sudo apt-get install glslang-tools)" >&2
  exit 1
fi
# An explicit compiler path makes build.rs run again if its last run used the committed files.
export GLSLANG_VALIDATOR="$compiler"
unset DOCS_RS

# Only build.rs matters here: the library failing to compile does not stop the copy.
messages="$(cargo check --release -p ellipsoid-splat --features research --message-format=json || true)"
out_dir="$(printf '%s\n' "$messages" \
  | grep '"reason":"build-script-executed"' \
  | grep -E '#ellipsoid-splat@|"ellipsoid-splat [0-9]' \
  | sed -E 's/.*"out_dir":"([^"]*)".*/\1/')"
if [ -z "$out_dir" ] || ! head -n 1 "$out_dir/spirv-origin.txt" | grep -qx compiled; then
  echo "update-spirv: build.rs did not compile the shaders (out dir: '${out_dir}')" >&2
  exit 1
fi

rm -f spirv/*.spv
while read -r file; do
  cp "$out_dir/$file" "spirv/$file"
done <"$out_dir/spirv-files.txt"
sed -n 2p "$out_dir/spirv-origin.txt" >spirv/COMPILER
cp "$out_dir/spirv-sources.txt" spirv/SOURCES
echo "update-spirv: $(wc -l <"$out_dir/spirv-files.txt") files from $(cat spirv/COMPILER)"
