#!/usr/bin/env bash
# The paper's case end to end (method.md §5, docs/validation.md): the water-glass-bead
# dam break with the proposed step (alpha = 0, beta = 0.5), the conventional one
# (alpha = beta = 0.001) and clear water of the same geometry (the scene without its
# beads), then the fronts of all three on one figure, their density-error histograms
# side by side and side views of the proposed run.
# Usage: scripts/paper_case.sh [2d|3d] [dvisph run options, for all three runs...]
# Output: out/glass_beads_<2d|3d>/{proposed,conventional,clear_water}/, fronts.png,
# fronts_density_error.png, views.png. Builds first, installing what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
dim=${1:-2d}
shift || true
case $dim in
  2d | 3d) ;;
  *) echo "usage: scripts/paper_case.sh [2d|3d] [dvisph run options...]; got '$dim'" >&2; exit 2 ;;
esac
scene=scenes/glass_beads_dam_break_$dim.yaml
out=out/glass_beads_$dim
bash scripts/build.sh >/dev/null
mkdir -p "$out"
export OMP_PROC_BIND=${OMP_PROC_BIND:-false}
build/dvisph run "$scene" --out "$out/proposed" "$@"
build/dvisph run "$scene" --out "$out/conventional" --set numerics.alpha=0.001 \
  --set numerics.beta=0.001 "$@"
/usr/bin/python3 - "$scene" "$out/clear_water.yaml" <<'PY'
import sys, yaml
scene = yaml.safe_load(open(sys.argv[1]))
for key in ("solids", "coupling"):
    scene.pop(key)
scene["name"] += "_clear_water"
yaml.safe_dump(scene, open(sys.argv[2], "w"), sort_keys=False)
PY
build/dvisph run "$out/clear_water.yaml" --out "$out/clear_water" "$@"
/usr/bin/python3 scripts/plot_run.py "$out/proposed" "$out/conventional" "$out/clear_water" \
  --labels "proposed (alpha 0, beta 0.5);conventional (alpha = beta = 0.001);clear water, proposed" \
  -o "$out/fronts.png"
/usr/bin/python3 scripts/render_snapshots.py "$out/proposed" -o "$out/views.png"
