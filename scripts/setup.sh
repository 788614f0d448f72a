#!/usr/bin/env bash
# Installs what dvisph needs on Debian bookworm and, unless a Kokkos is given or
# already cached, builds Kokkos 3.4.01 (Serial + OpenMP) from the Kokkos sources in
# Debian's `trilinos` source package. Idempotent: a second run only checks.
#
# Prints, as its last line, the Kokkos prefix to pass as -DKokkos_ROOT.
# Environment:
#   Kokkos_ROOT      use this Kokkos install (e.g. a CUDA build); nothing is built
#   DVISPH_CACHE     where the Kokkos build is cached (default ~/.cache/dvisph)
#   DVISPH_EXTRA_PACKAGES  more Debian packages to install (e.g. scripts/build_hip.sh's)
set -euo pipefail

log() { echo "[setup] $*" >&2; }

packages=(cmake g++ make pkg-config libeigen3-dev libhdf5-dev catch2 libyaml-cpp-dev
          libcli11-dev libfmt-dev libbenchmark-dev python3 python3-h5py python3-matplotlib
          python3-numpy python3-yaml ${DVISPH_EXTRA_PACKAGES:-})

sudo_() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
apt_updated=0
apt_update() { [ $apt_updated = 1 ] || { sudo_ apt-get update -qq >&2; apt_updated=1; }; }
if [ ${#missing[@]} -gt 0 ]; then
  log "installing ${missing[*]}"
  apt_update
  DEBIAN_FRONTEND=noninteractive sudo_ apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

if [ -n "${Kokkos_ROOT:-}" ]; then
  log "using Kokkos_ROOT=$Kokkos_ROOT"
  echo "$Kokkos_ROOT"
  exit 0
fi

cache="${DVISPH_CACHE:-$HOME/.cache/dvisph}"
prefix="$cache/kokkos-3.4.01"
if [ -f "$prefix/.complete" ]; then
  log "Kokkos cached at $prefix"
  echo "$prefix"
  exit 0
fi

src=$(bash "$(dirname "$0")/kokkos_source.sh")
version=$(grep -E 'set\(Kokkos_VERSION_(MAJOR|MINOR|PATCH)' "$src/CMakeLists.txt" | grep -oE '[0-9]+\)' | tr -d ')' | paste -sd.)
log "building Kokkos $version (Serial + OpenMP) into $prefix"
bash "$(dirname "$0")/kokkos_install.sh" "$prefix" "$src" \
  -DKokkos_ENABLE_SERIAL=ON -DKokkos_ENABLE_OPENMP=ON -DBUILD_SHARED_LIBS=OFF \
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON
echo "$prefix"
