#!/usr/bin/python3
"""Run time against error: runs every case of CASES over its grid of resolutions and CG
tolerances with `dvisph run`, collects summary.json into
benchmarks/results/suite_<label>.json and .csv, and draws error against wall time
(Pareto plots, every label found in benchmarks/results/) into docs/pareto_<case>.png.

The backend is the one build/dvisph was built for (OpenMP, CUDA, ...); --threads sets
OMP_NUM_THREADS, --build points at another build (e.g. a CUDA one). Each run records the
load that other processes put on the machine while it ran (from /proc/stat less the
run's own CPU time); with --max-other-load a run made under more load is repeated.

Usage: benchmarks/suite.py [--grid quick|default|full] [--threads N] [--label NAME]
                           [--only CASE ...] [--build DIR] [--kernels | --kernels-only]
                           [--max-other-load X] [--plot-only]"""
import argparse
import csv
import datetime
import itertools
import json
import math
import os
import platform
import resource
import shlex
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "benchmarks", "results")

G = 9.81
A = 0.05  # m, the dam breaks' column width
T3 = 3 / math.sqrt(2 * G / A)  # s: T = t sqrt(2g/a) = 3, the end of the front comparison

# The errors a case reports: summary.json metrics key, axis label.
FRONT = ("front_rms_deviation_T1_3", "front RMS deviation from Martin & Moyce, T in [1, 3]")
FRONT_SHAPE = ("front_rms_deviation_T1_3_after_lag", "front RMS deviation after the best time lag")
DENSITY = ("density_error_p95", "density error p95 (submerged, P >= 100 Pa)")

# One entry per case. grid: name -> (spacings [m], CG stops); every pair is run. A stop
# is numerics.cg_density_tolerance (the largest density change per step CG may leave,
# docs/isph.md), with the relative tolerance out of the way (RELATIVE); results from
# before 2026-12-02 varied numerics.cg_tolerance instead (`stop_label` tells them apart).
# `set`: scene keys overridden in every run of the case.
CASES = [
    {
        "name": "dam_break_2d",
        "scene": "scenes/dam_break_2d.yaml",
        "set": {"end_time": f"{T3 + 5e-4:.4f}", "output.snapshot_every": "0"},
        "length": A,  # resolutions are labelled a/dx
        "errors": [FRONT, FRONT_SHAPE, DENSITY],
        "grid": {
            "quick": ([0.005], [1e-6]),
            "default": ([0.0025, 0.00125], [1e-5, 1e-6, 1e-7]),
            "full": ([0.005, 0.0025, 0.00125, 0.000625], [1e-5, 1e-6, 1e-7]),
        },
    },
    {
        "name": "dam_break_3d",
        "scene": "scenes/dam_break_3d.yaml",
        "set": {"end_time": f"{T3 + 5e-4:.4f}", "output.snapshot_every": "0"},
        "length": A,
        "errors": [FRONT, FRONT_SHAPE, DENSITY],
        "grid": {
            "quick": ([0.01], [1e-6]),
            "default": [([0.005], [1e-5, 1e-6, 1e-7]), ([0.003], [1e-5, 1e-6])],
            "full": ([0.005, 0.003, 0.0025], [1e-5, 1e-6, 1e-7]),
        },
    },
]


RELATIVE = 1e-12  # numerics.cg_tolerance in the runs: the density stop ends every solve first


def stop_label(r):
    """How a run's CG stopped: 'drho 1e-06' (density stop) or 'rel 1e-08' (older runs)."""
    if "cg_density_tolerance" in r:
        return f"drho {r['cg_density_tolerance']:.0e}"
    return f"rel {r['cg_tolerance']:.0e}"


def grid_points(case, grid):
    """(spacing, tolerance) pairs of a case's grid: one product or a list of products."""
    g = case["grid"][grid]
    products = g if isinstance(g, list) else [g]
    return [p for spacings, tols in products for p in itertools.product(spacings, tols)]


def busy_seconds():
    """CPU seconds the whole machine has been busy (all cores), from /proc/stat."""
    with open("/proc/stat") as f:
        fields = [int(v) for v in f.readline().split()[1:]]
    user, nice, system, idle, iowait, irq, softirq, steal = fields[:8]
    return (user + nice + system + irq + softirq + steal) / os.sysconf("SC_CLK_TCK")


def children_cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_once(cmd, env):
    """Runs cmd; returns (exit code, stderr tail, wall s, load of other processes)."""
    busy0, own0, t0 = busy_seconds(), children_cpu_seconds(), time.monotonic()
    p = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - t0
    other = (busy_seconds() - busy0 - (children_cpu_seconds() - own0)) / max(wall, 1e-9)
    return p.returncode, (p.stderr or "").strip()[-300:], wall, max(other, 0.0)


def run_case(case, spacing, tol, args, env):
    out = os.path.join(args.out, f"{os.path.basename(os.path.normpath(args.build))}_{args.threads}t",
                       case["name"], f"dx{spacing:g}_drho{tol:g}")
    sets = dict(case["set"], **{"geometry.spacing": f"{spacing:g}", "numerics.cg_tolerance": f"{RELATIVE:g}",
                                "numerics.cg_density_tolerance": f"{tol:g}"})
    cmd = [os.path.join(args.build, "dvisph"), "run", os.path.join(ROOT, case["scene"]), "--out", out,
           "--quiet"] + [a for k, v in sets.items() for a in ("--set", f"{k}={v}")]
    for attempt in range(1 + args.retries):
        load_before = os.getloadavg()[0]
        code, err, wall, other = run_once(cmd, env)
        print(f"  {case['name']} dx={spacing:g} drho={tol:g}: exit {code}, {wall:.1f} s, "
              f"other load {other:.2f}", flush=True)
        if code != 0 or args.max_other_load is None or other <= args.max_other_load:
            break
        time.sleep(args.pause)
    row = {
        "case": case["name"], "spacing": spacing,
        "resolution": round(case["length"] / spacing, 2), "cg_tolerance": RELATIVE,
        "cg_density_tolerance": tol, "exit_code": code,
        "load_average_1min_before": round(load_before, 2), "other_load": round(other, 2),
        "attempts": attempt + 1, "date": datetime.date.today().isoformat(),
        "command": f"OMP_NUM_THREADS={env.get('OMP_NUM_THREADS', '')} OMP_PROC_BIND=false "
                   + shlex.join(os.path.relpath(c, ROOT) if c.startswith(ROOT) else c for c in cmd),
    }
    summary_path = os.path.join(out, "summary.json")
    if code != 0:
        row.update(error=err, wall_seconds=round(wall, 2))
        return row
    with open(summary_path) as f:
        s = json.load(f)
    m = s.get("metrics", {})
    row.update(
        backend=s["backend"], threads=s["threads"], dimension=s["dimension"],
        fluid_particles=s["particles"]["fluid"],
        particles=sum(s["particles"].values()), steps=s["steps"], end_time=s["end_time"],
        wall_seconds=s["wall_seconds"], ns_per_particle_step=s["ns_per_particle_step"],
        cg_iterations_mean=s["cg_iterations_mean"], cg_iterations_max=s["cg_iterations_max"],
        pair_interactions_per_second=s.get("pair_interactions_per_second"),
        max_density_error=m.get("max_density_error"),
        memory_bytes_per_particle=s.get("memory_bytes_per_particle"),
        stage_seconds=s.get("stage_seconds", {}))
    for key, _ in case["errors"]:
        row[key] = m.get(key)
    return row


def write_results(rows, label):
    os.makedirs(RESULTS, exist_ok=True)
    base = os.path.join(RESULTS, f"suite_{label}")
    machine = {"node": platform.node(), "machine": platform.machine(), "cpu": cpu_model(),
               "cores": os.cpu_count(), "kernel": platform.release()}
    with open(base + ".json", "w") as f:
        json.dump({"machine": machine, "runs": rows}, f, indent=1)
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys and k != "stage_seconds"]
    stages = sorted({k for r in rows for k in r.get("stage_seconds", {})})
    with open(base + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(keys + [f"stage_seconds.{k}" for k in stages])
        for r in rows:
            w.writerow([r.get(k, "") for k in keys] + [r.get("stage_seconds", {}).get(k, "") for k in stages])
    print(f"wrote {os.path.relpath(base, ROOT)}.json, .csv")


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def pareto_front(points):
    """The points no other point beats in both time and error, by time."""
    front, best = [], math.inf
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def plot(case):
    """Error against wall time for every label with results for this case."""
    labelled = {}
    for name in sorted(os.listdir(RESULTS)):
        if name.startswith("suite_") and name.endswith(".json"):
            with open(os.path.join(RESULTS, name)) as f:
                runs = [r for r in json.load(f)["runs"] if r["case"] == case["name"] and r["exit_code"] == 0]
            if runs:
                labelled[name[len("suite_"):-len(".json")]] = runs
    if not labelled:
        return
    errors = case["errors"]
    fig, axes = plt.subplots(1, len(errors), figsize=(5.2 * len(errors), 4.4))
    markers = {"drho 1e-05": "v", "drho 1e-06": "o", "drho 1e-07": "s",
               "rel 1e-04": "1", "rel 1e-06": "2", "rel 1e-08": "3"}
    for (key, title), ax in zip(errors, axes):
        for c, (label, runs) in enumerate(labelled.items()):
            color = f"C{c}"
            pts = [(r["wall_seconds"], r[key]) for r in runs if r.get(key) is not None and r[key] >= 0]
            named = set()  # a/dx written once per resolution: its points lie together
            for r in runs:
                if r.get(key) is None or r[key] < 0:
                    continue
                ax.plot(r["wall_seconds"], r[key], markers.get(stop_label(r), "x"), color=color, ms=8)
                if r["resolution"] not in named:
                    named.add(r["resolution"])
                    ax.annotate(f"a/dx {r['resolution']:g}", (r["wall_seconds"], r[key]), fontsize=8,
                                xytext=(5, 4), textcoords="offset points", color=color)
            if pts:
                ft, fe = zip(*pareto_front(pts))
                ax.plot(ft, fe, "-", color=color, lw=1, alpha=0.6, label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time [s]")
        ax.set_title(title, fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("error (relative)")
    axes[0].legend(title="backend, threads (line: Pareto front)", fontsize=8, title_fontsize=8)
    fig.suptitle(f"{case['name']}: error against wall time; markers: how CG stopped, "
                 "density stop v 1e-5, o 1e-6, s 1e-7; relative (before 2026-12-02) 1 1e-4, 2 1e-6, "
                 "3 1e-8", fontsize=9)
    fig.tight_layout()
    png = os.path.join(ROOT, "docs", f"pareto_{case['name']}.png")
    fig.savefig(png, dpi=120)
    plt.close(fig)
    print(f"wrote {os.path.relpath(png, ROOT)}")


KERNELS = ["bench_neighbor_search", "bench_pressure_poisson", "bench_dem_contacts"]


def run_kernels(args, env):
    """Runs the kernel benchmarks; their load record goes to results/kernels_<label>.json."""
    log = []
    for prog in KERNELS:
        path = os.path.join(RESULTS, f"{prog[len('bench_'):]}_{args.label}.json")
        # Serial does not depend on the thread count: measured in the 1-thread run only
        cmd = [os.path.join(args.build, "benchmarks", prog), path] + (["--no-serial"] if args.threads > 1 else [])
        load_before = os.getloadavg()[0]
        code, err, wall, other = run_once(cmd, env)
        print(f"  {prog}: exit {code}, {wall:.0f} s, other load {other:.2f}", flush=True)
        if code != 0:
            print(err, file=sys.stderr)
        log.append({"program": prog, "exit_code": code, "wall_seconds": round(wall, 1),
                    "load_average_1min_before": round(load_before, 2), "other_load": round(other, 2),
                    "date": datetime.date.today().isoformat(),
                    "command": f"OMP_NUM_THREADS={env['OMP_NUM_THREADS']} OMP_PROC_BIND=false "
                               + shlex.join(os.path.relpath(c, ROOT) for c in cmd)})
    with open(os.path.join(RESULTS, f"kernels_{args.label}.json"), "w") as f:
        json.dump(log, f, indent=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--grid", choices=["quick", "default", "full"], default="default")
    ap.add_argument("--threads", type=int, default=os.cpu_count(), help="OMP_NUM_THREADS")
    ap.add_argument("--label", help="results name (default: backend and threads of the runs, e.g. openmp2)")
    ap.add_argument("--only", nargs="*", help="case names to run (default: all)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"), help="build directory")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench"), help="run directories")
    ap.add_argument("--kernels", action="store_true", help="also run the kernel benchmarks")
    ap.add_argument("--kernels-only", action="store_true", help="run only the kernel benchmarks")
    ap.add_argument("--plot-only", action="store_true", help="only redraw the plots")
    ap.add_argument("--max-other-load", type=float,
                    help="repeat a run made while other processes loaded the machine more than this")
    ap.add_argument("--retries", type=int, default=2, help="repeats allowed by --max-other-load")
    ap.add_argument("--pause", type=float, default=60, help="seconds to wait before a repeat")
    args = ap.parse_args()
    cases = [c for c in CASES if not args.only or c["name"] in args.only]
    if not args.plot_only:
        env = dict(os.environ, OMP_NUM_THREADS=str(args.threads), OMP_PROC_BIND="false")
        if not args.kernels_only:
            rows = []
            for case in cases:
                for spacing, tol in grid_points(case, args.grid):
                    rows.append(run_case(case, spacing, tol, args, env))
            done = [r for r in rows if r["exit_code"] == 0]
            if args.label is None:
                args.label = f"{done[0]['backend'].lower()}{done[0]['threads']}" if done else "failed"
            for r in rows:
                r["label"] = args.label
            write_results(rows, args.label)
        if args.kernels or args.kernels_only:
            if args.label is None:
                ap.error("--kernels-only needs --label")
            run_kernels(args, env)
    for case in cases:
        plot(case)


if __name__ == "__main__":
    sys.exit(main())
