#!/usr/bin/env bash
# `dvisph check` and `dvisph run` reject a bad scene with exit code 2 and a message
# naming the key, and write nothing into the output directory.
# usage: cli_rejects.sh DVISPH SCENE EXPECTED_MESSAGE_FRAGMENT [ARGS...]
# ARGS go to both commands (e.g. --set key=value); with --restart only `run` is tried
# (`check` has none). @checkpoint@ in ARGS stands for a checkpoint of
# scenes/bead_collision.yaml, made first. The commands run in the scene's folder, so
# that relative paths in a scene (solids.bed) are taken from there.
set -u
dvisph=$1 scene=$2 expected=$3
shift 3
args=("$@")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
out=$tmp/out
if [[ "${args[*]}" == *@checkpoint@* ]]; then
  "$dvisph" run "$(dirname "$0")/../scenes/bead_collision.yaml" --out "$tmp/made" --quiet >/dev/null 2>&1 ||
    { echo "FAIL: cannot make a checkpoint of scenes/bead_collision.yaml"; exit 1; }
  args=("${args[@]//@checkpoint@/$tmp/made/checkpoint.h5}")
fi
commands=(check run)
[[ " ${args[*]} " == *" --restart "* ]] && commands=(run)
cd "$(dirname "$scene")" || exit 1
for cmd in "${commands[@]}"; do
  if [ $cmd = run ]; then argv=(run "$scene" --out "$out" --quiet "${args[@]}"); else argv=(check "$scene" "${args[@]}"); fi
  msg=$("$dvisph" "${argv[@]}" 2>&1); code=$?
  [ $code -eq 2 ] || { echo "FAIL: dvisph $cmd exited $code, expected 2: $msg"; exit 1; }
  grep -qF -- "$expected" <<<"$msg" || { echo "FAIL: message '$msg' does not name '$expected'"; exit 1; }
  echo "ok: dvisph $cmd -> 2: $msg"
done
[ ! -e "$out" ] || { echo "FAIL: $out was created for a rejected scene"; exit 1; }
