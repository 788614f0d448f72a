#!/bin/bash
# The paper's claim on its 2D case (CTest glass_beads_methods: the proposed step's density
# error p95 at 0.2 s after the gate at most a third of the conventional one's) over an
# ensemble of runs that differ at round-off only: bead stiffness 1000 (1 + k 1e-12) N/m,
# k = 1..N. The flow is chaotic, so one run is one sample of the ratio.
#   [DVISPH=binary] scripts/glass_beads_ensemble.sh [N, default 6] [work dir, default out/glass_beads_ensemble]
# One thread a run, two runs at a time; about 4 s a pair on a 2-core machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
n=${1:-6}
work=${2:-$root/out/glass_beads_ensemble}
dvisph=${DVISPH:-$root/build/dvisph}  # another build: DVISPH=path
scene=$root/scenes/glass_beads_dam_break_2d.yaml
[ -x "$dvisph" ] || { echo "glass_beads_ensemble: $dvisph not built (scripts/build.sh)" >&2; exit 2; }
mkdir -p "$work"
run() {  # k method -> out dir
  local k=$1 method=$2 extra=()
  [ "$method" = conventional ] && extra=(--set numerics.alpha=0.001 --set numerics.beta=0.001)
  OMP_NUM_THREADS=1 OMP_PROC_BIND=false "$dvisph" run "$scene" --set end_time=0.52 \
    --set solids.stiffness=$(printf '1000.%09d' "$k") "${extra[@]}" --out "$work/k${k}_$method" --quiet >/dev/null
}
for k in $(seq "$n"); do
  run "$k" proposed & run "$k" conventional; wait
done
/usr/bin/python3 - "$work" "$n" <<'PY'
import json, sys
work, n = sys.argv[1], int(sys.argv[2])
p95 = lambda d: json.load(open(f"{work}/{d}/summary.json"))["metrics"]["density_error_at"]["p95"]
print("k  proposed_p95  conventional_p95  ratio")
ratios = []
for k in range(1, n + 1):
    p, c = p95(f"k{k}_proposed"), p95(f"k{k}_conventional")
    ratios.append(c / p)
    print(f"{k}  {100 * p:.2f} %  {100 * c:.2f} %  {c / p:.2f}")
print(f"ratio min {min(ratios):.2f}, max {max(ratios):.2f}; below 3 in {sum(r < 3 for r in ratios)} of {n}")
PY
