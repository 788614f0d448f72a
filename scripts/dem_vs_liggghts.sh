#!/bin/bash
# The bead-bed settle, dvisph against LIGGGHTS 3.8, back to back on this machine:
# ../shared/peers/README.md's matched input (the same 7 921 beads, start positions, law,
# damping, dt and 28 029 steps). One core each, then two (2 OpenMP threads; 2 MPI
# ranks), then one core again. Prints wall times, load averages and both beds.
#   scripts/dem_vs_liggghts.sh [work dir, default out/dem_vs_liggghts]
# Needs build/dvisph (scripts/build.sh), Debian's liggghts and mpirun (apt-get install
# liggghts), python3-h5py. Takes about 5 minutes on a 2-core machine.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
peers=$root/../shared/peers/liggghts
work=${1:-$root/out/dem_vs_liggghts}
dvisph=$root/build/dvisph
for tool in liggghts mpirun; do
  command -v $tool >/dev/null || { echo "dem_vs_liggghts: $tool not found (apt-get install liggghts)" >&2; exit 2; }
done
[ -x "$dvisph" ] || { echo "dem_vs_liggghts: $dvisph not built (scripts/build.sh)" >&2; exit 2; }
mkdir -p "$work" && cd "$work"
scene=$root/scenes/bead_bed_settle.yaml
"$dvisph" run "$scene" --out init --set end_time=0.0002 --quiet >/dev/null
/usr/bin/python3 "$peers/make_data.py" init/snapshot_00000.h5 beads_init.data >/dev/null
dt=$(/usr/bin/python3 -c "import json; print(repr(json.load(open('init/summary.json'))['dem']['dt']))")
steps=28029
lig=(-in "$peers/in.bed_settle_matched" -var steps $steps -var dt 1.4270984256875527e-05 -var data beads_init.data)
: > times.txt
timed() {  # name, command...: wall seconds and the 1-minute load average before
  local name=$1; shift
  local load=$(cut -d' ' -f1 /proc/loadavg) start=$(date +%s.%N)
  "$@" > "$name.log" 2>&1
  echo "$name $(echo "$(date +%s.%N) - $start" | bc) load_before $load" | tee -a times.txt
}
timed dvisph_1t env OMP_NUM_THREADS=1 OMP_PROC_BIND=false "$dvisph" run "$scene" --out dvisph_1t --quiet
mkdir -p lig_1; timed liggghts_1 liggghts "${lig[@]}" -var px 1 -var out lig_1
timed dvisph_2t env OMP_NUM_THREADS=2 OMP_PROC_BIND=false "$dvisph" run "$scene" --out dvisph_2t --quiet
mkdir -p lig_2; timed liggghts_2 mpirun --allow-run-as-root -np 2 liggghts "${lig[@]}" -var px 2 -var out lig_2
timed dvisph_1t_again env OMP_NUM_THREADS=1 OMP_PROC_BIND=false "$dvisph" run "$scene" --out dvisph_1t_again --quiet
mkdir -p lig_1_again; timed liggghts_1_again liggghts "${lig[@]}" -var px 1 -var out lig_1_again
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg); dvisph DEM dt in the scene: $dt s"
/usr/bin/python3 "$peers/analyze_bed.py" dvisph_1t=dvisph_1t/checkpoint.h5 dvisph_2t=dvisph_2t/checkpoint.h5 \
  lig_1=lig_1/final.dump lig_2=lig_2/final.dump
