#!/usr/bin/python3
"""Full-resolution validation of the single-phase ISPH: runs the hydrostatic tanks and
the dam breaks, draws the plots into docs/ and writes docs/validation.md.
Usage: scripts/validate.py [--only NAME ...] [--threads N]   (after scripts/build.sh)"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_run  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = [  # scene, acceptance (text), figures from summary.json metrics
    ("hydrostatic_2d", "P within 1 % of rho g (H - y) below the top two layers; "
     "max density error < 1 % over 5 000 steps; no particle lost",
     ["pressure_max_error_over_rho_g_H", "pressure_rms_error_over_rho_g_H",
      "pressure_max_pointwise_relative_error", "max_density_error", "wall_penetration_over_dx"]),
    ("hydrostatic_3d", "P within 1 % of rho g (H - y) below the top two layers; no particle lost",
     ["pressure_max_error_over_rho_g_H", "pressure_rms_error_over_rho_g_H",
      "pressure_max_pointwise_relative_error", "max_density_error", "wall_penetration_over_dx"]),
    ("dam_break_2d", "front RMS deviation from Martin & Moyce, T in [1, 3]: goal 5 %, limit 10 %",
     ["front_rms_deviation_T1_3", "front_best_lag_T", "front_rms_deviation_T1_3_after_lag",
      "max_density_error", "wall_penetration_over_dx"]),
    ("dam_break_3d", "front RMS deviation from Martin & Moyce, T in [1, 3]: goal 5 %, limit 10 %",
     ["front_rms_deviation_T1_3", "front_best_lag_T", "front_rms_deviation_T1_3_after_lag",
      "max_density_error", "wall_penetration_over_dx"]),
]

# The 2D dam-break front under refinement in space and in time (runs named
# front_convergence): is its lead on Martin & Moyce a numerical error?
FRONT_STUDY = [  # label, --set overrides of scenes/dam_break_2d.yaml
    ("a/dx = 20", ["geometry.spacing=0.0025"]),
    ("a/dx = 40 (the scene)", []),
    ("a/dx = 80", ["geometry.spacing=0.000625"]),
    ("a/dx = 40, dt_max = 1e-4 s", ["numerics.dt_max=1e-4"]),
    ("a/dx = 40, CFL 0.1, dt_max = 2e-4 s", ["numerics.cfl=0.1", "numerics.dt_max=2e-4"]),
]

NOTES = """`front_best_lag_T` is the shift in T of the simulated front that fits Martin &
Moyce best and `..._after_lag` the deviation left after it: the simulated fronts have
the measured shape and lead the data by about 0.2-0.3 in T (10-15 ms at a = 5 cm),
which is the size of the delay usually put down to the gate opening in the experiment.
The front study below refines the 2D dam break in space and in time: the deviation
converges with resolution (to about 16 %), not to the data, and moves by less than 0.6
points with a 2.5 times smaller time step, so the lead is not a numerical error of the
solver. The simulated tip is
blunt (a few particles thick, see the snapshots), so the lead is not a thin leading film
either. Peer codes make the same observation: the Lethe CFD examples compare with Martin
& Moyce after adding 0.175 to the simulated T (chaos-polymtl/lethe,
examples/multiphysics/dam-break; "with T + 0.175" applies that shift here), and PySPH,
SPHinXsys and TrixiParticles only plot against the data, without a tolerance.
`wall_penetration_over_dx` is how far the deepest fluid particle centre got inside the
tank's walls over the run, in spacings. With the hydrostatic wall condition alone the 3D
dam break ended with particles 0.92 dx inside the back wall and the floor, 5-10 %
over-dense, and those carried its largest density error (11 %); the wall condition's
step that stops water moving into a wall (docs/isph.md) brought that to the figures
above.
The density error (`max_density_error`) is the largest over the run of |<rho> - rho_ref|
/ rho_ref over fluid particles with P >= 100 Pa and no free-surface particle within their
support, under- and over-density alike, as the paper reads it (since 2026-12-01; the rule
before, invariance weight > 0 and P >= 100 Pa, is `max_density_error_weighted_rule`),
with the density-invariance term weighted by the truncation of the support
(docs/isph.md), gamma = 0.1 in the tanks and 0.5 in the dam breaks (since 2026-12-03;
section "The density-invariance strength" below: 0.5 lowers the dam breaks' largest
density error, its p95 and the front deviation at every CFL and spacing tried, and
doubles the still tanks' pressure error). Before the weight's change (the weight from
div r, gamma = 0.1 everywhere; the same runs at commit 29661b2, density error by the rule
above): hydrostatic 2D 0.770 % (P max / rms 0.574 / 0.139 % of rho g H), 3D 0.524 %
(0.640 / 0.157 %), dam break 2D 7.55 % (p95 2.14 %, front RMS 15.1 %), 3D 7.54 % (p95
3.16 %, front RMS 13.2 %, wall penetration 0.071 dx). With gamma = 0.001 the 2D tank gave
1.09 % and the dam breaks 8-12 % (sessions 1-2). At gamma = 0.1 the dam breaks' largest
density error was 8.7 % (2D) and 8.0 % (3D): in 2D one pair of particles passing through
each other (particles 467 and 628 close to 0.023 dx 14 dx below the free surface around
t = 0.09 s, where the Wendland gradient, which vanishes at r = 0, no longer pushes them
apart), in 3D an interior patch 7.7 % under-dense behind the collapsing column that
gamma = 0.1 corrected too slowly.
The hydrostatic `pressure_max_pointwise_relative_error` is |P - rho g (H - y)| /
(rho g (H - y)) at its worst below the top two layers, with H the nominal water height;
it sits in the third layer, where rho g (H - y) is 60-80 Pa and a settling of the
column by a few tenths of a millimetre shifts P by 1-2 Pa. The layer tables below (last
snapshot, layers counted from the nominal surface) separate scatter from offset. In 2D
the layer means from the third layer down are within 0.3 % and the pointwise figure is
single particles (1-2 Pa of scatter). In 3D (500 steps) the means sit 0.4-0.9 % high in
every layer, which is what a water surface 0.02-0.03 dx above its nominal height gives
(rho g times that offset, divided by the depth): a pointwise 1 % at 2.5 dx depth asks
for the free surface to within 1/40 of a spacing. Measured against rho g H, every
particle below the top two layers is within the pressure_max_error_over_rho_g_H above.

"""


def run(env, scene, out, sets=()):
    subprocess.run([os.path.join(ROOT, "build", "dvisph"), "run",
                    os.path.join(ROOT, "scenes", scene + ".yaml"), "--out", out, "--quiet"]
                   + [a for kv in sets for a in ("--set", kv)], check=True, env=env)


def summary(out):
    path = os.path.join(out, "summary.json")
    return json.load(open(path)) if os.path.exists(path) else None


LETHE_SHIFT = 0.175  # added to the simulated T by the Lethe dam-break examples


def front_deviation(run, shift):
    """RMS relative deviation from Martin & Moyce for T in [1, 3], the simulated front
    taken at T - shift (as the solver's front_rms_deviation_T1_3 with a lag)."""
    s, sc = plot_run.series(run), plot_run.scene_of(run)
    a = sc["metrics"]["column_width"]
    g = abs(sc.get("material", {}).get("gravity", [-9.81])[-1])
    T, Z = plot_run.martin_moyce()
    m = (T >= 1) & (T <= 3)
    z = np.interp(T[m] - shift, s["t"] * np.sqrt(2 * g / a), s["front"] / a)
    return float(np.sqrt(np.mean(((z - Z[m]) / Z[m]) ** 2)))


def hydrostatic_layers(run, layers=6):
    """Rows of the per-layer pressure table of a tank's last snapshot."""
    sc = plot_run.scene_of(run)
    x, p, fluid, _ = plot_run.last_snapshot(run)
    dx, H = sc["geometry"]["spacing"], sc["metrics"]["water_height"]
    rho = sc.get("material", {}).get("density", 1000.0)
    g = abs(sc.get("material", {}).get("gravity", [-9.81])[-1])
    y = x[fluid, -1]
    exact, p = rho * g * (H - y), p[fluid]
    layer = np.floor((H - y) / dx).astype(int)
    rows = []
    for n in range(layers):
        s = layer == n
        if not s.any():
            continue
        rows.append(f"| {n + 1} | {(n + 0.5):.1f} | {s.sum()} | {exact[s].mean():.1f} | "
                    f"{100 * (p[s] - exact[s]).mean() / exact[s].mean():+.2f} % | "
                    f"{100 * np.max(np.abs(p[s] - exact[s]) / exact[s]):.2f} % | "
                    f"{(np.abs(p[s] - exact[s]) > 0.01 * exact[s]).sum()} |")
    return rows


KEPT = "<!-- Below: sections written by hand, with the commands that made their figures; scripts/validate.py keeps them. -->"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--only", nargs="*",
                    help="scene names to run, or front_convergence (default: all)")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    args = ap.parse_args()
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads), OMP_PROC_BIND="false")
    wanted = lambda name: not args.only or name in args.only  # noqa: E731
    rows = []
    for name, acceptance, keys in CASES:
        out = os.path.join(ROOT, "out", "validation", name)
        if wanted(name):
            run(env, name, out)
            kind = "front" if name.startswith("dam") else "pressure"
            subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "plot_run.py"), out,
                            "-o", os.path.join(ROOT, "docs", f"{name}_{kind}.png")], check=True)
        s = summary(out)
        if not s:
            continue
        figures = ", ".join(f"{k} = {s['metrics'][k]:.4g}" for k in keys if k in s["metrics"])
        if name.startswith("dam"):
            figures += f", with T + {LETHE_SHIFT}: {front_deviation(out, LETHE_SHIFT):.4g}"
        rows.append(f"| {name} | {s['particles']['fluid']} | {s['steps']} | {s['end_time']:.3g} s | "
                    f"{s['wall_seconds']:.0f} s ({s['backend']}, {s['threads']} threads) | "
                    f"{s['cg_iterations_mean']:.0f} / {s['cg_iterations_max']} | {figures} | {acceptance} |")
    study, study_runs = [], []
    for label, sets in FRONT_STUDY:
        out = (os.path.join(ROOT, "out", "validation", "dam_break_2d") if not sets else
               os.path.join(ROOT, "out", "validation", "front_convergence",
                            "_".join(k.split(".")[-1] + v for k, v in (kv.split("=") for kv in sets))))
        if sets and wanted("front_convergence"):
            run(env, "dam_break_2d", out, sets + ["output.snapshot_every=0"])
        s = summary(out)
        if not s:
            continue
        m = s["metrics"]
        study_runs.append((out, label))
        study.append(f"| {label} | {s['steps']} | {100 * m['front_rms_deviation_T1_3']:.2f} % | "
                     f"{m['front_best_lag_T']:.3f} | {100 * m['front_rms_deviation_T1_3_after_lag']:.2f} % | "
                     f"{100 * front_deviation(out, LETHE_SHIFT):.2f} % | "
                     f"{100 * m['density_error_p95']:.2f} % | {s['wall_seconds']:.0f} s |")
    if wanted("front_convergence") and study_runs:
        plot_run.plot_front([r for r, _ in study_runs],
                            os.path.join(ROOT, "docs", "dam_break_2d_front_convergence.png"),
                            [label for _, label in study_runs])
    doc = os.path.join(ROOT, "docs", "validation.md")
    # what follows KEPT in the file is written by hand (runs this script does not make)
    kept = open(doc).read().split(KEPT, 1) if os.path.exists(doc) else []
    kept = KEPT + kept[1] if len(kept) == 2 else ""
    with open(doc, "w") as f:
        f.write("# Validation of the single-phase ISPH\n\n")
        f.write(f"Made by `scripts/validate.py` on {datetime.date.today()} "
                f"({platform.node()}, {platform.machine()}, {os.cpu_count()} cores); "
                "plots by `scripts/plot_run.py`. Figures are relative "
                "(0.01 = 1 %).\n\n")
        f.write("| scene | fluid particles | steps | simulated | wall time | CG mean / max | "
                "figures | acceptance |\n|---|---|---|---|---|---|---|---|\n")
        f.write("\n".join(rows) + "\n\n")
        f.write(NOTES)
        if study:
            f.write("## Dam-break front under refinement (2D)\n\n`scripts/validate.py --only "
                    "front_convergence` (after the dam_break_2d run above). Front RMS deviation "
                    "from Martin & Moyce for T in [1, 3], the best shift in T and what is left "
                    "after it, the deviation with 0.175 added to the simulated T as in the Lethe "
                    "examples, and the p95 of the density error.\n\n"
                    "| run | steps | front RMS dev. | best lag (T) | after lag | with T + 0.175 | density p95 | wall |\n"
                    "|---|---|---|---|---|---|---|---|\n" + "\n".join(study) + "\n\n"
                    "![front convergence](dam_break_2d_front_convergence.png)\n\n")
        for name, _, _ in CASES:
            out = os.path.join(ROOT, "out", "validation", name)
            if name.startswith("hydrostatic") and summary(out):
                f.write(f"## {name}: pressure by layer below the nominal surface\n\n"
                        "| layer | depth / dx | particles | rho g (H - y) mean, Pa | mean deviation | "
                        "largest pointwise | particles off by > 1 % |\n|---|---|---|---|---|---|---|\n"
                        + "\n".join(hydrostatic_layers(out)) + "\n\n")
        for name, _, _ in CASES:
            kind = "front" if name.startswith("dam") else "pressure"
            if os.path.exists(os.path.join(ROOT, "docs", f"{name}_{kind}.png")):
                f.write(f"![{name}]({name}_{kind}.png)\n\n")
        f.write(kept)
    print("wrote docs/validation.md")


if __name__ == "__main__":
    main()
