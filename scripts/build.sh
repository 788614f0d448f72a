#!/usr/bin/env bash
# Installs what is missing (scripts/setup.sh), configures build/ and builds dvisph.
# Extra arguments go to CMake's configure step (e.g. -DCMAKE_BUILD_TYPE=Debug).
set -euo pipefail
cd "$(dirname "$0")/.."
kokkos_root=$(bash scripts/setup.sh)
if [ ! -f build/CMakeCache.txt ] || [ $# -gt 0 ]; then
  cmake -S . -B build -DKokkos_ROOT="$kokkos_root" "$@"
fi
jobs=${DVISPH_BUILD_JOBS:-$(nproc)}
cmake --build build -j"$jobs"
