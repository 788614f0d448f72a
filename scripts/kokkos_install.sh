#!/usr/bin/env bash
# Builds and installs a Kokkos from a source tree into a prefix, once: a prefix that
# holds `.complete` is kept as it is. Used by scripts/setup.sh (Serial + OpenMP),
# scripts/build_hip.sh (HIP) and scripts/build_cuda.sh (CUDA).
#   scripts/kokkos_install.sh PREFIX SOURCE [CMAKE_ARGS...]
# Release, C++17 and no Kokkos tests are always set; the build tree is PREFIX.build,
# removed once installed. Jobs: DVISPH_BUILD_JOBS (default: all cores).
set -euo pipefail

prefix=$1 src=$2
shift 2
[ -f "$prefix/.complete" ] && exit 0
build="$prefix.build"
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_STANDARD=17 \
  -DCMAKE_INSTALL_PREFIX="$prefix" -DKokkos_ENABLE_TESTS=OFF "$@" >&2
cmake --build "$build" -j"${DVISPH_BUILD_JOBS:-$(nproc)}" >&2
cmake --install "$build" >&2
touch "$prefix/.complete"
rm -rf "$build"
