#!/usr/bin/env bash
# The main job: builds dvisph (installing what is missing) and runs a scene, then
# plots it. Usage: scripts/run.sh [SCENE] [dvisph run options...]
# Default scene: the best validated one that exists (water dam break, 2D).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/dam_break_2d.yaml}
shift || true
bash scripts/build.sh >/dev/null
name=$(basename "$scene" .yaml)
out=out/$name
export OMP_PROC_BIND=${OMP_PROC_BIND:-false}
build/dvisph run "$scene" --out "$out" "$@"
/usr/bin/python3 scripts/plot_run.py "$out"
