#!/usr/bin/env bash
# The tests that draw (scripts/suite.sh) on a second lavapipe: Mesa 25's, from Debian's
# bookworm-backports, unpacked into target/drivers/mesa-25 with a private apt state (the
# system's packages and apt configuration are not touched; the suite is added to the mirror the
# system's apt uses) and selected with VK_ICD_FILENAMES, its newer libdrm on LD_LIBRARY_PATH.
# CI runs it after scripts/test.sh (Mesa 22.3.6, the system's).
#
#   scripts/test-drivers.sh [cargo test arguments]     e.g. --test cameras (suite.sh: the
#                                                       Python tests run whatever is given)
#   scripts/test-drivers.sh --env                       fetches the driver if it is missing,
#                                                       then prints the exports and runs no test
#
# The golden hashes recorded for Mesa 25 are for the build below; should backports have moved
# on, the golden test holds the new build to the float64 reference alone (and says so).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
[ "${1:-}" = --env ] || source "$here/scripts/setup.sh"
cd "$here"

drivers="$here/target/drivers"
prefix="$drivers/mesa-25"
state="$drivers/apt"
lib="$prefix/usr/lib/x86_64-linux-gnu"
icd="$prefix/lvp_icd.json"

# The Debian mirror the system's apt already uses (deb822 .sources or one-line lists).
mirror() {
  local uri
  uri="$(sed -n 's/^URIs: *\(http[^ ]*debian\)\/\{0,1\}$/\1/p' /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)"
  [ -n "$uri" ] || uri="$(sed -n 's/^deb \(\[[^]]*\] \)\{0,1\}\(http[^ ]*debian\)\/\{0,1\} .*/\2/p' \
    /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null | head -n 1)"
  echo "${uri:-http://deb.debian.org/debian}"
}

if [ ! -f "$icd" ]; then
  mkdir -p "$state/lists/partial" "$state/archives/partial" "$prefix"
  echo "deb $(mirror) bookworm-backports main" >"$state/sources.list"
  apt=(-o "Dir::State::Lists=$state/lists" -o "Dir::Etc::SourceList=$state/sources.list"
    -o Dir::Etc::SourceParts=/dev/null -o "Dir::Cache::Archives=$state/archives"
    -o Debug::NoLocking=1 -o APT::Architecture=amd64)
  apt-get "${apt[@]}" update -qq
  (cd "$state/archives" && apt-get "${apt[@]}" download -qq \
    mesa-vulkan-drivers/bookworm-backports libdrm2/bookworm-backports \
    libdrm-amdgpu1/bookworm-backports)
  for deb in "$state"/archives/*.deb; do dpkg -x "$deb" "$prefix"; done
  [ -f "$lib/libvulkan_lvp.so" ] || { echo "test-drivers: no libvulkan_lvp.so in $lib" >&2; exit 1; }
  printf '{ "file_format_version": "1.0.0", "ICD": { "library_path": "%s", "api_version": "1.4.305" } }\n' \
    "$lib/libvulkan_lvp.so" >"$icd"
fi

recorded="25.0.7-2~bpo12+1"
fetched="$(ls "$state"/archives/mesa-vulkan-drivers_*_amd64.deb 2>/dev/null | head -n 1 |
  sed -n 's/.*mesa-vulkan-drivers_\(.*\)_amd64\.deb$/\1/p' | sed 's/%3a/:/g; s/%7e/~/g; s/%2b/+/g')"
if [ "$fetched" != "$recorded" ]; then
  echo "test-drivers: fetched mesa-vulkan-drivers ${fetched:-(unknown)};" \
    "golden hashes are recorded for $recorded" >&2
fi
export VK_ICD_FILENAMES="$icd"
export LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
if [ "${1:-}" = --env ]; then
  echo "export VK_ICD_FILENAMES='$VK_ICD_FILENAMES' LD_LIBRARY_PATH='$LD_LIBRARY_PATH'"
  exit 0
fi
bash "$here/scripts/suite.sh" "$@"
