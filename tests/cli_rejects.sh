#!/usr/bin/env bash
# `dvisph check` and `dvisph run` reject a bad scene with exit code 2 and a message
# naming the key, and write nothing into the output directory.
# usage: cli_rejects.sh DVISPH SCENE EXPECTED_MESSAGE_FRAGMENT
set -u
dvisph=$1 scene=$2 expected=$3
out=$(mktemp -d)/out
for cmd in check run; do
  if [ $cmd = run ]; then args=(run "$scene" --out "$out" --quiet); else args=(check "$scene"); fi
  msg=$("$dvisph" "${args[@]}" 2>&1); code=$?
  [ $code -eq 2 ] || { echo "FAIL: dvisph $cmd exited $code, expected 2: $msg"; exit 1; }
  grep -qF -- "$expected" <<<"$msg" || { echo "FAIL: message '$msg' does not name '$expected'"; exit 1; }
  echo "ok: dvisph $cmd -> 2: $msg"
done
[ ! -e "$out" ] || { echo "FAIL: $out was created for a rejected scene"; exit 1; }
