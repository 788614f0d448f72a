#!/usr/bin/env bash
# Compiles dvisph, its tests and benchmarks for NVIDIA GPUs (Kokkos' CUDA backend) into
# build-cuda/. No GPU is needed to compile; `cd build-cuda && ctest` runs the tests on one.
#   1. installs the common packages (scripts/setup.sh);
#   2. builds Kokkos >= 4 with CUDA (+ Serial on the host) from a Kokkos source tree you
#      name, for one target architecture, cached in $DVISPH_CACHE/kokkos-cuda-<arch>
#      (Kokkos 3.4, the CPU build's, does not build with CUDA 13's nvcc);
#   3. configures and builds dvisph with that Kokkos' nvcc_wrapper.
# Environment:
#   KOKKOS_SRC         a Kokkos >= 4 source tree (a release tarball or a clone); required
#                      unless Kokkos_ROOT is given. Kokkos releases older than CUDA 13
#                      call two runtime functions whose signatures CUDA 13 changed
#                      (cudaGraphAddDependencies, cudaMemPrefetchAsync); the compiler names
#                      them, and a Kokkos release that knows CUDA 13 needs no change
#   DVISPH_CUDA_ARCH   Kokkos architecture option (default HOPPER90: H100/H200; e.g.
#                      AMPERE80 for A100) and the matching nvcc -arch
#   CUDA_HOME          the CUDA toolkit (default /usr/local/cuda)
#   DVISPH_CACHE       as for scripts/setup.sh (default ~/.cache/dvisph)
#   Kokkos_ROOT        a Kokkos already built with CUDA: step 2 is skipped
set -euo pipefail
cd "$(dirname "$0")/.."

log() { echo "[build-cuda] $*" >&2; }
die() { log "$*"; exit 2; }

bash scripts/setup.sh >/dev/null

arch="${DVISPH_CUDA_ARCH:-HOPPER90}"
case "$arch" in
  HOPPER90) sm=sm_90 ;; ADA89) sm=sm_89 ;; AMPERE86) sm=sm_86 ;; AMPERE80) sm=sm_80 ;;
  VOLTA70) sm=sm_70 ;; BLACKWELL100) sm=sm_100 ;;
  *) die "DVISPH_CUDA_ARCH=$arch: one of HOPPER90, ADA89, AMPERE86, AMPERE80, VOLTA70, BLACKWELL100" ;;
esac
export CUDA_HOME="${CUDA_HOME:-/usr/local/cuda}"
[ -x "$CUDA_HOME/bin/nvcc" ] || die "no nvcc at CUDA_HOME=$CUDA_HOME (set CUDA_HOME to the CUDA toolkit)"
export PATH="$CUDA_HOME/bin:$PATH"
jobs=${DVISPH_BUILD_JOBS:-$(nproc)}

if [ -z "${Kokkos_ROOT:-}" ]; then
  [ -n "${KOKKOS_SRC:-}" ] || die "KOKKOS_SRC is not set: name a Kokkos >= 4 source tree (or give Kokkos_ROOT)"
  [ -f "$KOKKOS_SRC/CMakeLists.txt" ] && [ -x "$KOKKOS_SRC/bin/nvcc_wrapper" ] ||
    die "KOKKOS_SRC=$KOKKOS_SRC: not a Kokkos source tree (no CMakeLists.txt or bin/nvcc_wrapper)"
  major=$(sed -n 's/^ *set(Kokkos_VERSION_MAJOR \([0-9]*\)).*/\1/p' "$KOKKOS_SRC/CMakeLists.txt" | head -1)
  [ -n "$major" ] && [ "$major" -ge 4 ] || die "KOKKOS_SRC=$KOKKOS_SRC: Kokkos ${major:-?}, need >= 4"
  cache="${DVISPH_CACHE:-$HOME/.cache/dvisph}"
  Kokkos_ROOT="$cache/kokkos-cuda-$arch"
  if [ ! -f "$Kokkos_ROOT/.complete" ]; then
    log "building Kokkos $major (CUDA, $arch) from $KOKKOS_SRC into $Kokkos_ROOT"
    # nvcc_wrapper compiles for its default architecture wherever it is not given one,
    # as in Kokkos' and CMake's compile checks, and Kokkos 4's default (sm_70) is gone
    # from CUDA 13: a copy defaults to the target instead (the source tree is not touched)
    mkdir -p "$cache"
    wrapper="$cache/nvcc_wrapper-$sm"
    sed "s/^default_arch=.*/default_arch=\"$sm\"/" "$KOKKOS_SRC/bin/nvcc_wrapper" >"$wrapper"
    chmod +x "$wrapper"
    bash scripts/kokkos_install.sh "$Kokkos_ROOT" "$KOKKOS_SRC" \
      -DCMAKE_CXX_COMPILER="$wrapper" -DKokkos_ENABLE_CUDA=ON -DKokkos_ENABLE_SERIAL=ON \
      -DKokkos_ARCH_"$arch"=ON
    cp "$wrapper" "$Kokkos_ROOT/bin/nvcc_wrapper"
  fi
fi

log "building dvisph for CUDA ($arch) in build-cuda/"
start=$(date +%s)
# configured before with another compiler (another Kokkos), CMake would wipe the cache
# and the -D values below with it: start that directory's configuration afresh
compiler=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' build-cuda/CMakeCache.txt 2>/dev/null || true)
if [ -n "$compiler" ] && [ "$compiler" != "$Kokkos_ROOT/bin/nvcc_wrapper" ]; then
  rm -rf build-cuda/CMakeCache.txt build-cuda/CMakeFiles
fi
cmake -S . -B build-cuda -DCMAKE_BUILD_TYPE=Release -DKokkos_ROOT="$Kokkos_ROOT" \
  -DCMAKE_CXX_COMPILER="$Kokkos_ROOT/bin/nvcc_wrapper" >&2
cmake --build build-cuda -j"$jobs" >&2
log "dvisph, tests and benchmarks compiled for CUDA in $(( $(date +%s) - start )) s; run: cd build-cuda && ctest"
