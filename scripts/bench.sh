#!/usr/bin/env bash
# Benchmarks for the backend at hand: builds (scripts/build.sh), then runs the scene
# suite (benchmarks/suite.py: run time against error, Pareto plots in docs/) and, with
# --kernels, the kernel benchmarks. Arguments go to suite.py, e.g.
#   scripts/bench.sh --threads 2              # default grid, OpenMP with 2 threads
#   scripts/bench.sh --grid quick --kernels   # a few minutes, plus the kernel benchmarks
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
exec /usr/bin/python3 benchmarks/suite.py "$@"
