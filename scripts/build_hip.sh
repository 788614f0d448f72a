#!/usr/bin/env bash
# Compiles dvisph, its tests and benchmarks for AMD GPUs (Kokkos' HIP backend) with
# Debian's ROCm (hipcc 5.2.3), into build-hip/. No AMD GPU is needed to compile, and
# none is used: this checks that the one source builds for HIP.
#   1. installs what the HIP build needs from Debian (hipcc, libamdhip64-dev);
#   2. builds Kokkos 3.4.01 with HIP (+ Serial on the host) from the Kokkos sources in
#      Debian's trilinos source package (scripts/kokkos_source.sh) for one target
#      architecture, cached in $DVISPH_CACHE/kokkos-3.4.01-hip-<arch>;
#   3. configures and builds dvisph with hipcc against it.
# Environment:
#   DVISPH_HIP_ARCH  Kokkos architecture option (default VEGA908: MI100, gfx908; Kokkos
#                    3.4 knows VEGA900, VEGA906 and VEGA908, not MI200's gfx90a)
#   DVISPH_CACHE     as for scripts/setup.sh (default ~/.cache/dvisph)
#   Kokkos_ROOT      a Kokkos already built with HIP: step 2 is skipped
set -euo pipefail
cd "$(dirname "$0")/.."

log() { echo "[build-hip] $*" >&2; }

# the common packages and the HIP compiler (and the host Kokkos, cached)
DVISPH_EXTRA_PACKAGES="hipcc libamdhip64-dev" bash scripts/setup.sh >/dev/null

arch="${DVISPH_HIP_ARCH:-VEGA908}"
jobs=${DVISPH_BUILD_JOBS:-$(nproc)}
if [ -z "${Kokkos_ROOT:-}" ]; then
  cache="${DVISPH_CACHE:-$HOME/.cache/dvisph}"
  Kokkos_ROOT="$cache/kokkos-3.4.01-hip-$arch"
  if [ ! -f "$Kokkos_ROOT/.complete" ]; then
    src=$(bash scripts/kokkos_source.sh)
    log "building Kokkos (HIP, $arch) into $Kokkos_ROOT"
    bash scripts/kokkos_install.sh "$Kokkos_ROOT" "$src" \
      -DCMAKE_CXX_COMPILER=hipcc -DKokkos_ENABLE_HIP=ON -DKokkos_ENABLE_SERIAL=ON \
      -DKokkos_ARCH_"$arch"=ON -DBUILD_SHARED_LIBS=OFF
  fi
fi

log "building dvisph for HIP ($arch) in build-hip/"
start=$(date +%s)
cmake -S . -B build-hip -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=hipcc \
  -DKokkos_ROOT="$Kokkos_ROOT" >&2
cmake --build build-hip -j"$jobs" >&2
log "dvisph, tests and benchmarks compiled for HIP in $(( $(date +%s) - start )) s"
