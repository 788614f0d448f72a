#!/usr/bin/env bash
# A run that cannot write its output stops with exit code 1 and a message naming the
# file, never silently: an output directory below a regular file (chmod does not stop
# root), a full disk as a file size limit (ulimit -f, SIGXFSZ ignored so that writes
# fail with EFBIG) at every size from nothing up to what the run needs, and /dev/full in
# place of each file the run writes.
# usage: output_failures.sh DVISPH SCENE   (a scene that runs in well under a second)
set -u
dvisph=$1 scene=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# expect_failure WHAT CODE MESSAGE FILE: exit code 1 and FILE named
expect_failure() {
  [ "$2" -eq 1 ] || fail "$1: exit $2, expected 1: $3"
  grep -qF -- "$4" <<<"$3" || fail "$1: message '$3' does not name $4"
  echo "ok: $1 -> 1: $3"
}

touch "$tmp/file"
msg=$("$dvisph" run "$scene" --out "$tmp/file/out" --quiet 2>&1)
expect_failure "--out below a regular file" $? "$msg" "$tmp/file/out"

# the subshell's limit covers dvisph's files only: its output comes back through a pipe
kb=0
while :; do
  out=$tmp/limit_$kb
  msg=$(trap '' XFSZ; ulimit -f $kb; "$dvisph" run "$scene" --out "$out" --quiet 2>&1); code=$?
  [ $code -eq 0 ] && break
  expect_failure "file size limit $kb KiB" $code "$msg" "$out/"
  [ -z "$(find "$out" -name '*.tmp')" ] || fail "file size limit $kb KiB: temporary files left in $out"
  kb=$((kb + 1))
  [ $kb -le 1024 ] || fail "the run does not fit in 1 MiB files"
done
for f in scene.yaml series.csv snapshot_00000.h5 snapshots.xdmf checkpoint.h5 summary.json; do
  [ -s "$out/$f" ] || fail "file size limit $kb KiB: exit 0 without $f"
done
echo "ok: file size limit $kb KiB: the run completes"

[ -w /dev/full ] || fail "no /dev/full"
for f in scene.yaml series.csv snapshot_00000.h5.tmp snapshots.xdmf.tmp checkpoint.h5.tmp summary.json; do
  out=$tmp/full_${f//./_}
  mkdir "$out" && ln -s /dev/full "$out/$f"
  msg=$("$dvisph" run "$scene" --out "$out" --quiet 2>&1)
  expect_failure "$f on /dev/full" $? "$msg" "$out/$f"
done
