#!/usr/bin/env bash
# A run killed with SIGKILL at any moment leaves a readable latest checkpoint, and the
# run continues from it. Kills a run that checkpoints every few steps at random
# moments, checks checkpoint.h5 each time and restarts from it.
# usage: checkpoint_kill.sh DVISPH SCENE
set -u
dvisph=$1 scene=$2
out=$(mktemp -d)/run
set_args=(--set geometry.spacing=0.005 --set output.checkpoint_every=0.002 --set end_time=5)
# Debian's python3-h5py (scripts/setup.sh) or, elsewhere, the first python3 with h5py
python=
for p in /usr/bin/python3 "$(command -v python3)"; do
  [ -x "$p" ] && "$p" -c "import h5py" 2>/dev/null && { python=$p; break; }
done
[ -n "$python" ] || { echo "FAIL: no python3 with h5py (scripts/setup.sh installs python3-h5py)"; exit 1; }
checkpoint_time() {  # prints t of the checkpoint, fails if it is not whole
  "$python" - "$1" <<'PY'
import sys, h5py, numpy as np
with h5py.File(sys.argv[1], "r") as f:
    x = f["real"]["sph.x"][()]
    assert x.ndim == 2 and x.shape[0] > 0 and np.isfinite(x).all(), "bad positions"
    assert len(f["text"]["run.scene"][()]) > 0
    print(f["number"]["run.t"][0])
PY
}
restart=()
for round in 1 2 3 4 5; do
  "$dvisph" run "$scene" --out "$out" --quiet "${set_args[@]}" "${restart[@]}" >/dev/null 2>&1 &
  pid=$!
  sleep "$(awk -v s=$RANDOM 'BEGIN { print 1.0 + (s % 1000) / 1000 }')"
  kill -9 $pid; wait $pid 2>/dev/null
  [ -f "$out/checkpoint.h5" ] || { echo "FAIL: round $round: no checkpoint.h5"; exit 1; }
  t=$(checkpoint_time "$out/checkpoint.h5") || { echo "FAIL: round $round: checkpoint.h5 unreadable"; exit 1; }
  echo "ok: round $round: killed; checkpoint.h5 whole at t = $t s"
  restart=(--restart "$out/checkpoint.h5")
done
end=$(awk -v t="$t" 'BEGIN { print t + 0.01 }')
"$dvisph" run "$scene" --out "$out" --quiet --set geometry.spacing=0.005 --set end_time="$end" \
  "${restart[@]}" >/dev/null || { echo "FAIL: the run did not continue from the checkpoint"; exit 1; }
grep -q "\"restarted_from_step\": [1-9]" "$out/summary.json" || { echo "FAIL: summary.json: not a restart"; exit 1; }
echo "ok: continued from t = $t s to $end s"
