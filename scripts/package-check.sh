#!/usr/bin/env bash
# The library as a dependent gets it: `cargo publish --dry-run` passes (it packages the crate
# and builds the package); the package holds no tests, data or pictures; a throw-away crate
# that depends on the packaged library builds where glslangValidator is missing (build.rs
# then copies the committed SPIR-V); and the documentation builds as docs.rs builds it.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
cd "$here"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$here/target}"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

step() { echo "package-check: [${SECONDS}s] $*"; }

# Where build.rs took the SPIR-V from (`compiled` or `committed`), from cargo's JSON messages.
spirv_origin() {
  local out_dir
  out_dir="$(grep '"reason":"build-script-executed"' "$1" |
    grep -E '#ellipsoid-splat@|"ellipsoid-splat [0-9]' |
    sed -E 's/.*"out_dir":"([^"]*)".*/\1/' | head -n 1)"
  head -n 1 "$out_dir/spirv-origin.txt" 2>/dev/null || echo "unknown"
}

registry_reachable() {
  timeout 10 bash -c '</dev/tcp/index.crates.io/443' 2>/dev/null
}

# 1. Publishing, dry: packages, then verifies by building the package. It asks the registry
#    about the version, so without a network it is `cargo package --offline` (the same
#    packaging and build, without that question).
step "cargo publish --dry-run"
if registry_reachable; then
  CARGO_HTTP_TIMEOUT=30 CARGO_NET_RETRY=1 \
    cargo publish --dry-run -p ellipsoid-splat --allow-dirty 2>"$scratch/publish.log" || {
    cat "$scratch/publish.log" >&2
    exit 1
  }
else
  step "NOTICE: index.crates.io is unreachable: cargo package --offline instead"
  cargo package -p ellipsoid-splat --allow-dirty --offline 2>"$scratch/publish.log" || {
    cat "$scratch/publish.log" >&2
    exit 1
  }
fi

# 2. What the package holds.
step "the package's files"
cargo package --list -p ellipsoid-splat --allow-dirty --offline 2>/dev/null >"$scratch/files"
if grep -E '^(tests|benches|examples|data|docs)/|\.(png|jpe?g|svg|gif|exr|ppm|csv|ply|nii|gz|pdb|cif)$' \
  "$scratch/files"; then
  echo "package-check: the package holds the files above: tests, data or pictures" >&2
  exit 1
fi
for needed in build.rs src/lib.rs glsl/include/gpu_layout.glsl spirv/cull.comp.spv \
  README.md CHANGELOG.md; do
  grep -qx "$needed" "$scratch/files" || {
    echo "package-check: the package lacks $needed" >&2
    exit 1
  }
done

# 3. A dependent without glslangValidator, on the package as extracted by step 1.
step "a dependent crate without glslangValidator"
package="$(cd "$CARGO_TARGET_DIR/package" && pwd)/ellipsoid-splat-$(
  sed -n 's/^version = "\(.*\)"/\1/p' Cargo.toml | head -n 1
)"
[ -f "$package/Cargo.toml" ] || {
  echo "package-check: no extracted package at $package" >&2
  exit 1
}
# PATH without any glslangValidator: each directory holding one is replaced by links to the
# rest of its entries (the linker and the other tools stay).
stripped=""
index=0
IFS=: read -r -a dirs <<<"$PATH"
for dir in "${dirs[@]}"; do
  if [ -e "$dir/glslangValidator" ]; then
    index=$((index + 1))
    shadow="$scratch/path$index"
    mkdir "$shadow"
    for entry in "$dir"/*; do
      [ "$(basename "$entry")" = glslangValidator ] || ln -s "$entry" "$shadow/"
    done
    dir="$shadow"
  fi
  stripped="${stripped:+$stripped:}$dir"
done
dependent="$scratch/dependent"
mkdir -p "$dependent/src"
# The workspace's profiles and lock file, so the dependencies already built are reused.
cat >"$dependent/Cargo.toml" <<EOF
[package]
name = "ellipsoid-splat-dependent"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
ellipsoid-splat = { path = "$package", default-features = false }

[profile.dev]
opt-level = 1

[profile.dev.package."*"]
opt-level = 3

[workspace]
EOF
cp Cargo.lock "$dependent/"
cat >"$dependent/src/main.rs" <<'EOF'
fn main() {
    println!("{}", std::any::type_name::<ellipsoid_splat::EllipsoidRenderer>());
}
EOF
(
  cd "$dependent"
  PATH="$stripped" GLSLANG_VALIDATOR=/nonexistent/glslangValidator \
    cargo build --offline --message-format=json-render-diagnostics >"$scratch/dependent.json" \
    2>"$scratch/dependent.log" || {
    cat "$scratch/dependent.log" >&2
    exit 1
  }
  origin="$(spirv_origin "$scratch/dependent.json")"
  [ "$origin" = committed ] || {
    echo "package-check: the dependent's build.rs took its SPIR-V from: $origin" >&2
    exit 1
  }
  "$CARGO_TARGET_DIR/debug/ellipsoid-splat-dependent" | grep -q EllipsoidRenderer
)

# 4. The documentation as docs.rs builds it: DOCS_RS set (build.rs copies spirv/).
step "DOCS_RS=1 cargo doc"
DOCS_RS=1 RUSTDOCFLAGS="-D warnings" cargo doc -p ellipsoid-splat --no-deps \
  --message-format=json-render-diagnostics >"$scratch/doc.json" 2>"$scratch/doc.log" || {
  cat "$scratch/doc.log" >&2
  exit 1
}
origin="$(spirv_origin "$scratch/doc.json")"
[ "$origin" = committed ] || {
  echo "package-check: under DOCS_RS build.rs took its SPIR-V from: $origin" >&2
  exit 1
}
step "ok"
