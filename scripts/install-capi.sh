#!/usr/bin/env bash
# Installs the C ABI (crates/capi) under PREFIX: include/ellipsoid_splat.h, the shared library
# (libellipsoid_splat.so.VERSION, with the soname libellipsoid_splat.so.ABI) and the static one,
# a pkg-config file (lib/pkgconfig/ellipsoid_splat.pc) and a CMake package
# (lib/cmake/ellipsoid_splat: find_package(ellipsoid_splat) gives ellipsoid_splat::ellipsoid_splat
# and ellipsoid_splat::static).
#
#   scripts/install-capi.sh PREFIX                 builds the release libraries first
#   scripts/install-capi.sh --prebuilt DIR PREFIX  takes them from DIR (a cargo target/release)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
[ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"

# Paths are taken relative to where the script is called from.
built=""
if [ "${1:-}" = "--prebuilt" ]; then
  built="${2:?--prebuilt needs the directory holding libellipsoid_splat_capi.so and .a}"
  built="$(cd "$built" && pwd)"
  shift 2
fi
prefix="${1:?usage: scripts/install-capi.sh [--prebuilt DIR] PREFIX}"
mkdir -p "$prefix"
prefix="$(cd "$prefix" && pwd)"
cd "$here"
if [ -z "$built" ]; then
  cargo build --release -p ellipsoid-splat-capi
  built="${CARGO_TARGET_DIR:-$here/target}/release"
fi
for lib in libellipsoid_splat_capi.so libellipsoid_splat_capi.a; do
  [ -f "$built/$lib" ] || { echo "install-capi: $built/$lib is missing" >&2; exit 1; }
done

abi="$(sed -n 's/^pub const ES_ABI_VERSION: u32 = \([0-9]*\);$/\1/p' crates/capi/src/lib.rs)"
version="$(sed -n 's/^version = "\(.*\)"$/\1/p' Cargo.toml | head -n 1)"
[ -n "$abi" ] && [ -n "$version" ] || { echo "install-capi: no ABI or package version" >&2; exit 1; }
lib="$prefix/lib"
mkdir -p "$prefix/include" "$lib/pkgconfig" "$lib/cmake/ellipsoid_splat"

install -m 644 crates/capi/include/ellipsoid_splat.h "$prefix/include/ellipsoid_splat.h"
rm -f "$lib"/libellipsoid_splat.so.*.*.* # an earlier version's
install -m 755 "$built/libellipsoid_splat_capi.so" "$lib/libellipsoid_splat.so.$version"
ln -sf "libellipsoid_splat.so.$version" "$lib/libellipsoid_splat.so.$abi"
ln -sf "libellipsoid_splat.so.$abi" "$lib/libellipsoid_splat.so"
install -m 644 "$built/libellipsoid_splat_capi.a" "$lib/libellipsoid_splat.a"
# What Rust's standard library needs from the system when the static library is linked.
static_libs="-lgcc_s -lutil -lrt -lpthread -lm -ldl -lc"

# Relocatable: the prefix is found from the .pc file's own place.
cat >"$lib/pkgconfig/ellipsoid_splat.pc" <<PC
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include

Name: ellipsoid_splat
Description: Exact ray-cast ellipsoids drawn into the host's Vulkan frame (C ABI $abi)
Version: $version
Requires.private: vulkan
Libs: -L\${libdir} -lellipsoid_splat
Libs.private: $static_libs
Cflags: -I\${includedir}
PC

cat >"$lib/cmake/ellipsoid_splat/ellipsoid_splatConfig.cmake" <<CMAKE
# ellipsoid_splat $version (C ABI $abi), installed by scripts/install-capi.sh.
#   find_package(ellipsoid_splat CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE ellipsoid_splat::ellipsoid_splat)  # or ::static
get_filename_component(_ellipsoid_splat_prefix "\${CMAKE_CURRENT_LIST_DIR}/../../.." ABSOLUTE)
include(CMakeFindDependencyMacro)
find_dependency(Vulkan)
if(NOT TARGET ellipsoid_splat::ellipsoid_splat)
  add_library(ellipsoid_splat::ellipsoid_splat SHARED IMPORTED)
  set_target_properties(ellipsoid_splat::ellipsoid_splat PROPERTIES
    IMPORTED_LOCATION "\${_ellipsoid_splat_prefix}/lib/libellipsoid_splat.so.$version"
    IMPORTED_SONAME "libellipsoid_splat.so.$abi"
    INTERFACE_INCLUDE_DIRECTORIES "\${_ellipsoid_splat_prefix}/include"
    INTERFACE_LINK_LIBRARIES "Vulkan::Vulkan")
  add_library(ellipsoid_splat::static STATIC IMPORTED)
  set_target_properties(ellipsoid_splat::static PROPERTIES
    IMPORTED_LOCATION "\${_ellipsoid_splat_prefix}/lib/libellipsoid_splat.a"
    INTERFACE_INCLUDE_DIRECTORIES "\${_ellipsoid_splat_prefix}/include"
    INTERFACE_LINK_LIBRARIES "Vulkan::Vulkan;gcc_s;util;rt;pthread;m;dl")
endif()
set(ellipsoid_splat_ABI_VERSION $abi)
unset(_ellipsoid_splat_prefix)
CMAKE

cat >"$lib/cmake/ellipsoid_splat/ellipsoid_splatConfigVersion.cmake" <<CMAKE
# Compatible when the major version matches (the minor, while the major is 0) and the
# installed version is at least the one asked for.
set(PACKAGE_VERSION "$version")
string(REPLACE "." ";" _have "\${PACKAGE_VERSION}")
string(REPLACE "." ";" _want "\${PACKAGE_FIND_VERSION}")
list(GET _have 0 _have_major)
list(GET _have 1 _have_minor)
set(PACKAGE_VERSION_COMPATIBLE FALSE)
if(PACKAGE_FIND_VERSION STREQUAL "")
  set(PACKAGE_VERSION_COMPATIBLE TRUE)
elseif(NOT PACKAGE_FIND_VERSION VERSION_GREATER PACKAGE_VERSION)
  list(GET _want 0 _want_major)
  list(LENGTH _want _want_parts)
  set(_want_minor 0)
  if(_want_parts GREATER 1)
    list(GET _want 1 _want_minor)
  endif()
  if(_have_major EQUAL _want_major AND (_have_major GREATER 0 OR _have_minor EQUAL _want_minor))
    set(PACKAGE_VERSION_COMPATIBLE TRUE)
  endif()
endif()
if(PACKAGE_FIND_VERSION STREQUAL PACKAGE_VERSION)
  set(PACKAGE_VERSION_EXACT TRUE)
endif()
CMAKE
echo "install-capi: ellipsoid_splat $version (ABI $abi) in $prefix"
