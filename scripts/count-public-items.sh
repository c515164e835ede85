#!/usr/bin/env bash
# The free public items of the library reachable without features, counted from rustdoc's JSON
# (needs a nightly toolchain): the figure tests/public_surface.rs counts from the sources on
# stable. Run it when that test's count changes, to check the two still agree.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo +nightly rustdoc -q -p ellipsoid-splat --no-default-features -- \
    -Z unstable-options --output-format json
python3 - target/doc/ellipsoid_splat.json <<'EOF'
import json, sys

doc = json.load(open(sys.argv[1]))
index = doc["index"]
# Free items: not associated ones, not re-exports themselves (their targets count).
FREE = {"struct", "enum", "union", "trait", "trait_alias", "function", "constant", "static",
        "type_alias", "module", "macro"}
seen = {}

def kind(item):
    return next(iter(item["inner"]))

def walk(module, prefix):
    for child in index[module]["inner"]["module"]["items"]:
        item = index.get(str(child))
        if item is None or item.get("visibility") != "public":
            continue
        target, name = str(child), item["name"]
        if kind(item) == "use":
            use = item["inner"]["use"]
            if use.get("is_glob") or use.get("id") is None or str(use["id"]) not in index:
                sys.exit(f"cannot follow `pub use {use['source']}`")
            target, name = str(use["id"]), use["name"]
        if kind(index[target]) in FREE:
            seen.setdefault(target, prefix + name)
            if kind(index[target]) == "module":
                walk(target, prefix + name + "::")

walk(str(doc["root"]), "")
print(len(seen), "free items without features:", ", ".join(sorted(seen.values())))
EOF
