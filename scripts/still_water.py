#!/usr/bin/python3
"""Still water: how fast does water at rest move, and where does the motion come from?

Runs the still tanks below with `dvisph run`, reads the fluid velocity of every snapshot
and writes, per case and time, the rms and the largest fluid speed
(out/still_water/still_water.csv) and a plot of both against time
(docs/still_water.png). The cases separate the sources (docs/isph.md, "Still water"):
walls reaching above the water (the top corners), side walls, the floor alone (x
periodic), the smoothing length, and 3D.

Usage: scripts/still_water.py [--only CASE ...] [--jobs N]
"""
import argparse
import concurrent.futures
import csv
import glob
import os
import subprocess

import h5py
import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DVISPH = os.path.join(ROOT, "build", "dvisph")
OUT = os.path.join(ROOT, "out", "still_water")

TANK_2D = "scenes/hydrostatic_2d.yaml"  # 0.1 x 0.1 m of water, dx = 2.5 mm, h = 1.5 dx
LOW_WALLS = {"geometry.tank.hi": "[0.1, 0.1]"}  # walls end at the water's surface

# The water of scenes/bed_hydrostatic.yaml without its beads (2.7 x 2.7 x 3.9 cm, dx = 3 mm)
TANK_3D = {"numerics.settle_until": 0, "metrics.kind": "hydrostatic"}
WITHOUT = ("solids", "coupling")  # top-level blocks a case's scene drops

CASES = [
    dict(name="2d_tank", scene=TANK_2D, what="2D tank, walls above the water", sets={}),
    dict(name="2d_low_walls", scene=TANK_2D, what="2D tank, walls end at the surface",
         sets=LOW_WALLS),
    dict(name="2d_floor_only", scene=TANK_2D, what="2D, x periodic (floor only)",
         sets=dict(LOW_WALLS, **{"geometry.tank.periodic": "x"})),
    dict(name="2d_floor_only_shallow", scene=TANK_2D, what="2D, x periodic, 4 cm deep",
         sets={"geometry.tank.hi": "[0.1, 0.04]", "geometry.tank.periodic": "x",
               "geometry.fluid": "[{lo: [0, 0], hi: [0.1, 0.04]}]", "metrics.water_height": 0.04}),
    dict(name="2d_floor_only_h2", scene=TANK_2D, what="2D, x periodic, h = 2 dx",
         sets=dict(LOW_WALLS, **{"geometry.tank.periodic": "x", "numerics.h_over_dx": 2.0,
                                 "geometry.wall_layers": 6})),
    dict(name="2d_damped_2s", scene=TANK_2D, what="2D tank, damped start to 2 s (tau 0.03 s)",
         sets={"numerics.settle_until": 2, "numerics.settle_time": 0.03}),
    dict(name="3d_tank", scene="scenes/bed_hydrostatic.yaml", what="3D tank (bed_hydrostatic's water)",
         sets=TANK_3D, drop=WITHOUT),
    dict(name="3d_floor_only", scene="scenes/bed_hydrostatic.yaml", what="3D, x and y periodic",
         sets=dict(TANK_3D, **{"geometry.tank.periodic": "xy"}), drop=WITHOUT),
]

END_TIME = 3.0   # s
EVERY = 0.1      # s between snapshots


def scene_without(path, blocks, dest):
    """The scene at `path` with its top-level `blocks` left out, written to `dest`."""
    scene = {k: v for k, v in yaml.safe_load(open(path)).items() if k not in blocks}
    with open(dest, "w") as f:
        yaml.safe_dump(scene, f, sort_keys=False)
    return dest


def run(case):
    out = os.path.join(OUT, case["name"])
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(ROOT, case["scene"])
    if case.get("drop"):
        scene = scene_without(scene, case["drop"], os.path.join(OUT, case["name"] + ".yaml"))
    sets = dict(case["sets"], end_time=END_TIME, **{"output.snapshot_every": EVERY})
    cmd = [DVISPH, "run", scene, "--out", out]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    rows = []
    for f in sorted(glob.glob(os.path.join(out, "snapshot_*.h5"))):
        with h5py.File(f, "r") as h:
            fluid = h["kind"][:] == 0
            speed = np.linalg.norm(h["velocity"][:][fluid], axis=1)
            t = float(np.atleast_1d(h.attrs["time"])[0])
        rows.append((t, float(np.sqrt(np.mean(speed ** 2))), float(speed.max())))
    return case, rows


def growth_rate(rows):
    """The e-folding rate [1/s] of the rms speed from its quiet minimum (below 3e-5 m/s)
    to its first snapshot above 1 mm/s; None if the run never was quiet or never grew."""
    above = [k for k, r in enumerate(rows) if r[1] > 1e-3]
    if not above:
        return None
    quiet = [k for k in range(above[0]) if rows[k][1] < 3e-5 and rows[k][0] > 0]
    if not quiet:
        return None
    k0 = min(quiet, key=lambda k: rows[k][1])
    k1 = above[0]
    return np.log(rows[k1][1] / rows[k0][1]) / (rows[k1][0] - rows[k0][0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", nargs="*", help="case names")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    cases = [c for c in CASES if not args.only or c["name"] in args.only]
    os.makedirs(OUT, exist_ok=True)
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(run, cases))

    with open(os.path.join(OUT, "still_water.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "t", "rms_speed", "max_speed"])
        for case, rows in results:
            for t, rms, mx in rows:
                w.writerow([case["name"], f"{t:.4g}", f"{rms:.6g}", f"{mx:.6g}"])
    print(f"{'case':22s} {'rms / max at 0.3 s':>20s} {'at 1 s':>16s} {'at 3 s':>16s} [mm/s]  growth [1/s]")
    for case, rows in results:
        def at(t):
            r = min(rows, key=lambda r: abs(r[0] - t))
            return f"{1e3 * r[1]:6.2f} / {1e3 * r[2]:6.2f}"
        rate = growth_rate(rows)
        print(f"{case['name']:22s} {at(0.3):>20s} {at(1.0):>16s} {at(3.0):>16s}  "
              + (f"{rate:8.1f}" if rate else "       -"))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5), sharex=True)
    for case, rows in results:
        t = [r[0] for r in rows]
        ax[0].semilogy(t, [max(r[1], 1e-8) for r in rows], label=case["what"])
        ax[1].semilogy(t, [max(r[2], 1e-8) for r in rows], label=case["what"])
    for a, what in zip(ax, ["rms", "largest"]):
        a.axhline(1e-3, color="k", lw=0.8, ls="--")
        a.set_xlabel("t [s]")
        a.set_ylabel(f"{what} fluid speed [m/s]")
        a.grid(True, which="both", alpha=0.3)
    ax[1].text(0.02, 1.15e-3, "1 mm/s (issue 14's bound)", fontsize=8)
    ax[0].legend(fontsize=7)
    fig.suptitle("Water at rest (scripts/still_water.py)")
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "still_water.png"), dpi=110)


if __name__ == "__main__":
    main()
