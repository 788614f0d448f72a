#!/usr/bin/env bash
# A run that fails numerically exits with 3, names what failed (particle, step,
# quantity) and leaves the last good state, from which the run can continue.
# usage: guards.sh DVISPH SOURCE_DIR
set -u
dvisph=$1 src=$2
tmp=$(mktemp -d)
expect_failure() {  # name, expected message fragments..., then -- and the run arguments
  local name=$1; shift
  local fragments=()
  while [ "$1" != "--" ]; do fragments+=("$1"); shift; done
  shift
  msg=$("$dvisph" run "$@" --out "$tmp/$name" --quiet 2>&1); code=$?
  [ $code -eq 3 ] || { echo "FAIL: $name: exit $code, expected 3: $msg"; exit 1; }
  for f in "${fragments[@]}"; do
    grep -qF -- "$f" <<<"$msg" || { echo "FAIL: $name: message does not say '$f': $msg"; exit 1; }
  done
  [ -f "$tmp/$name/last_good.h5" ] || { echo "FAIL: $name: no last_good.h5"; exit 1; }
  echo "ok: $name -> 3: $(grep -m1 . <<<"$msg")"
}
# a bead far too soft for its speed sinks into the floor
expect_failure soft_bead "bead 0" "step " "overlaps" "last_good.h5" -- \
  "$src/scenes/bead_drop.yaml" --set solids.stiffness=1 --set solids.dt_safety=0.001
# a pressure solve allowed too few iterations
expect_failure cg_cap "not converged after 3 CG iterations" "step " "last_good.h5" -- \
  "$src/scenes/hydrostatic_2d.yaml" --set geometry.spacing=0.005 --set numerics.cg_max_iterations=3
# the last good state continues (with the cap lifted)
"$dvisph" run "$src/scenes/hydrostatic_2d.yaml" --set geometry.spacing=0.005 --set end_time=0.01 \
  --restart "$tmp/cg_cap/last_good.h5" --out "$tmp/continued" --quiet >/dev/null ||
  { echo "FAIL: cannot continue from last_good.h5"; exit 1; }
echo "ok: continued from last_good.h5"
