#!/usr/bin/env bash
# Set up, then run every test on lavapipe with the validation layer on.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
source "$here/scripts/setup.sh"
cd "$here"
bash "$here/scripts/suite.sh" "$@"
# The library as a dependent gets it: publish dry run, the package's contents, a build
# without glslangValidator on the committed SPIR-V, the docs as docs.rs builds them.
bash "$here/scripts/package-check.sh"
