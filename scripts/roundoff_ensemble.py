#!/usr/bin/python3
"""Runs of one scene that differ at round-off only, to see how much of a figure is chaos.

Member k (1..N) multiplies the numbers of one scene key by (1 + k eps) (decimal
arithmetic, so the same text as writing the digits by hand; eps = 1e-12 by default).
Each variant is a name, optionally @binary (another build), and extra key=value
overrides; every variant runs every member, one thread a run, two runs at a time.
Prints each member's metrics; per variant, the mean, standard deviation, min, median and
max; with two variants, the two-sided Mann-Whitney p of each metric (normal approximation
with tie and continuity corrections, scipy's asymptotic method; rough below about 8 runs
a side): whether the two could be draws from one distribution. --report tabulates the outputs already in the work
directory without running anything.

  # the paper's 2D claim (CTest glass_beads_methods: conventional p95 / proposed p95 >= 3)
  scripts/roundoff_ensemble.py scenes/glass_beads_dam_break_2d.yaml -n 24 \\
      --perturb solids.stiffness --set end_time=0.52 \\
      --variant proposed --variant conventional numerics.alpha=0.001 numerics.beta=0.001 \\
      --metric metrics.density_error_at.p95 --ratio conventional/proposed
  # a still tank, this build against another one
  scripts/roundoff_ensemble.py scenes/hydrostatic_2d.yaml -n 8 --perturb material.gravity \\
      --variant now --variant before@/path/to/old/build/dvisph \\
      --metric metrics.max_density_error --metric metrics.pressure_rms_error_over_rho_g_H
"""
import argparse
import concurrent.futures
import json
import math
import os
import statistics
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import yaml

root = Path(__file__).resolve().parent.parent


def perturbed(value, factor):
    scale = lambda x: x if x == 0 else str(Decimal(str(x)) * factor)
    if isinstance(value, list):
        return "[" + ", ".join(str(scale(x)) for x in value) + "]"
    return str(scale(value))


def mann_whitney_p(a, b):
    pooled = sorted(a + b)
    rank = {}
    for x in set(pooled):  # mean rank of ties
        first = pooled.index(x)
        rank[x] = first + (pooled.count(x) + 1) / 2
    n1, n2, n = len(a), len(b), len(a) + len(b)
    u = sum(rank[x] for x in a) - n1 * (n1 + 1) / 2
    ties = sum(c ** 3 - c for c in (pooled.count(x) for x in set(pooled)))
    sigma = math.sqrt(n1 * n2 / 12 * ((n + 1) - ties / (n * (n - 1))))
    if sigma == 0:
        return 1.0
    z = (abs(u - n1 * n2 / 2) - 0.5) / sigma
    return min(1.0, math.erfc(max(z, 0) / math.sqrt(2)))


def lookup(tree, dotted):
    for part in dotted.split("."):
        tree = tree[part]
    return tree


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("-n", type=int, default=6, help="members (default 6)")
    ap.add_argument("--perturb", required=True, help="scene key whose numbers are scaled by 1 + k eps")
    ap.add_argument("--eps", default="1e-12")
    ap.add_argument("--variant", nargs="+", action="append", required=True,
                    metavar="NAME[@BINARY] [KEY=VALUE ...]")
    ap.add_argument("--set", action="append", default=[], help="key=value for every run")
    ap.add_argument("--metric", action="append", required=True, help="dotted path in summary.json")
    ap.add_argument("--ratio", help="A/B: also the ratio of the first metric, variant A over B")
    ap.add_argument("--work", help="output directory (default out/ensemble_<scene name>)")
    ap.add_argument("--report", action="store_true", help="only tabulate the work directory's outputs")
    args = ap.parse_args()

    scene = yaml.safe_load(open(args.scene))
    base = lookup(scene, args.perturb)
    work = Path(args.work or root / "out" / f"ensemble_{scene['name']}")
    variants = []
    for v in args.variant:
        name, _, binary = v[0].partition("@")
        binary = Path(binary or os.environ.get("DVISPH", root / "build" / "dvisph"))
        if not args.report and not os.access(binary, os.X_OK):
            sys.exit(f"roundoff_ensemble: {binary} is not an executable (scripts/build.sh)")
        variants.append((name, binary, v[1:]))

    def run(k, variant):
        name, binary, sets = variant
        value = perturbed(base, 1 + k * Decimal(args.eps))
        out = work / f"k{k}_{name}"
        cmd = [str(binary), "run", args.scene, "--quiet", "--out", str(out),
               "--set", f"{args.perturb}={value}"]
        for s in args.set + sets:
            cmd += ["--set", s]
        env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
        if not args.report:
            subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
        summary = json.load(open(out / "summary.json"))
        return [lookup(summary, m) for m in args.metric]

    jobs = [(k, v) for k in range(1, args.n + 1) for v in variants]
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        values = dict(zip(((k, v[0]) for k, v in jobs), pool.map(lambda j: run(*j), jobs)))

    names = [v[0] for v in variants]
    print("k  " + "  ".join(f"{n}:{m.split('.')[-1]}" for n in names for m in args.metric))
    for k in range(1, args.n + 1):
        print(f"{k}  " + "  ".join(f"{x:.6g}" for n in names for x in values[k, n]))
    for n in names:
        for i, m in enumerate(args.metric):
            xs = [values[k, n][i] for k in range(1, args.n + 1)]
            sd = statistics.stdev(xs) if len(xs) > 1 else 0
            print(f"{n} {m}: mean {statistics.mean(xs):.6g} sd {sd:.2g}  min {min(xs):.6g}  "
                  f"median {statistics.median(xs):.6g}  max {max(xs):.6g}")
    if len(names) == 2:
        for i, m in enumerate(args.metric):
            a, b = ([values[k, n][i] for k in range(1, args.n + 1)] for n in names)
            print(f"{names[0]} against {names[1]}, {m}: Mann-Whitney p {mann_whitney_p(a, b):.2f}")
    if args.ratio:
        a, b = args.ratio.split("/")
        rs = [values[k, a][0] / values[k, b][0] for k in range(1, args.n + 1)]
        print(f"{a}/{b} {args.metric[0]}: min {min(rs):.3g}  median {statistics.median(rs):.3g}  "
              f"max {max(rs):.3g}; " + " ".join(f"{r:.2f}" for r in rs))


if __name__ == "__main__":
    main()
