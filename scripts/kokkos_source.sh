#!/usr/bin/env bash
# Prints the path of the Kokkos sources inside Debian's `trilinos` source package
# (bookworm), downloading and extracting them once into $DVISPH_CACHE/kokkos-src
# (default ~/.cache/dvisph). If apt knows no source for trilinos, deb-src entries are
# derived from this machine's own bookworm `deb` entries. Used by scripts/setup.sh
# (Serial + OpenMP) and scripts/build_hip.sh (HIP); scripts/kokkos_install.sh builds them.
set -euo pipefail

log() { echo "[kokkos-source] $*" >&2; }
sudo_() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }
apt_updated=0
apt_update() { [ $apt_updated = 1 ] || { sudo_ apt-get update -qq >&2; apt_updated=1; }; }

cache="${DVISPH_CACHE:-$HOME/.cache/dvisph}"
src="$cache/kokkos-src"
if [ -f "$src/CMakeLists.txt" ]; then
  echo "$src"
  exit 0
fi

# deb-src entries derived from this machine's own bookworm (non-security) `deb` entries.
src_list=/etc/apt/sources.list.d/dvisph-deb-src.sources
# (grep reads all of it: with -q it would stop early and pipefail would see apt-cache's SIGPIPE)
if ! apt-cache showsrc trilinos 2>/dev/null | grep '^Package: trilinos' >/dev/null; then
  log "adding deb-src entries derived from the existing apt sources"
  tmp=$(mktemp)
  # deb822 stanzas: copy those whose Types has `deb` and whose Suites name plain bookworm.
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] && [ "$f" != "$src_list" ] || continue
    awk 'BEGIN{RS=""; ORS="\n\n"}
         /(^|\n)Types:[^\n]*deb([ \n]|$)/ && /(^|\n)Suites:[^\n]*bookworm([ \n]|$)/ {
           gsub(/(^|\n)#[^\n]*/, ""); sub(/Types:[^\n]*/, "Types: deb-src"); print }' "$f" >> "$tmp"
  done
  # one-line format
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    grep -E '^deb[[:space:]]+[^[]' "$f" | grep -E '[[:space:]]bookworm[[:space:]]' |
      awk '{ $1 = ""; sub(/^ /, ""); split($0, a, " ");
             printf "Types: deb-src\nURIs: %s\nSuites: %s\nComponents: main\n\n", a[1], a[2] }' >> "$tmp" || true
  done
  [ -s "$tmp" ] || { log "no bookworm deb entry found in the apt sources"; exit 1; }
  sudo_ install -m 644 "$tmp" "$src_list"
  rm -f "$tmp"
  apt_updated=0
  apt_update
fi

command -v dpkg-source >/dev/null || { apt_update; sudo_ apt-get install -y -qq dpkg-dev xz-utils >&2; }

work="$cache/trilinos-src"
rm -rf "$work"
mkdir -p "$work"
log "downloading the trilinos source package (for its Kokkos)"
(cd "$work" && apt-get source --download-only -qq trilinos >&2)
orig=$(ls "$work"/trilinos_*.orig.tar.* | head -1)
log "extracting packages/kokkos from $(basename "$orig")"
(cd "$work" && tar -xf "$orig" --wildcards '*/packages/kokkos/*' &&
   rm -rf "$src" && mv ./*/packages/kokkos "$src")
rm -rf "$work"
echo "$src"
