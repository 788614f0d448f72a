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

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = [  # scene, acceptance (text), figures from summary.json metrics
    ("hydrostatic_2d", "P within 1 % of rho g (H - y) below the top two layers; "
     "max density error < 1 % over 5 000 steps; no particle lost",
     ["pressure_max_error_over_rho_g_H", "pressure_rms_error_over_rho_g_H",
      "pressure_max_pointwise_relative_error", "max_density_error"]),
    ("hydrostatic_3d", "P within 1 % of rho g (H - y) below the top two layers; no particle lost",
     ["pressure_max_error_over_rho_g_H", "pressure_rms_error_over_rho_g_H",
      "pressure_max_pointwise_relative_error", "max_density_error"]),
    ("dam_break_2d", "front RMS deviation from Martin & Moyce, T in [1, 3]: goal 5 %, limit 10 %",
     ["front_rms_deviation_T1_3", "front_best_lag_T", "front_rms_deviation_T1_3_after_lag",
      "max_density_error"]),
    ("dam_break_3d", "front RMS deviation from Martin & Moyce, T in [1, 3]: goal 5 %, limit 10 %",
     ["front_rms_deviation_T1_3", "front_best_lag_T", "front_rms_deviation_T1_3_after_lag",
      "max_density_error"]),
]


NOTES = """`front_best_lag_T` is the shift in T of the simulated front that fits Martin &
Moyce best and `..._after_lag` the deviation left after it: the simulated fronts have
the measured shape and lead the data by about 0.2-0.3 in T (10-15 ms at a = 5 cm),
which is the size of the delay usually put down to the gate opening in the experiment.
The deviation grows with resolution (2D a/dx = 20: 12.3 %, 40: 15.0 %): the finer
front converges to a faster one, not to the data.
The density error is the largest over submerged particles (P >= 100 Pa, surface
particles left out) and the whole run, with gamma = 0.1 (the default since the
density-invariance term is weighted by how full the support is; docs/isph.md). With
gamma = 0.001 the 2D tank gave 1.09 % (still above 1 %) and the dam breaks 8-12 %.
The hydrostatic `pressure_max_pointwise_relative_error` is |P - rho g (H - y)| /
(rho g (H - y)) at its worst below the top two layers, with H the nominal water height;
it sits in the third layer, where rho g (H - y) is 60-80 Pa and a settling of the
column by a few tenths of a millimetre shifts P by 1-2 Pa.

"""


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--only", nargs="*", help="scene names to run (default: all)")
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    args = ap.parse_args()
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads), OMP_PROC_BIND="false")
    rows = []
    for name, acceptance, keys in CASES:
        out = os.path.join(ROOT, "out", "validation", name)
        if not args.only or name in args.only:
            subprocess.run([os.path.join(ROOT, "build", "dvisph"), "run",
                            os.path.join(ROOT, "scenes", name + ".yaml"), "--out", out, "--quiet"],
                           check=True, env=env)
            kind = "front" if name.startswith("dam") else "pressure"
            subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "plot_run.py"), out,
                            "-o", os.path.join(ROOT, "docs", f"{name}_{kind}.png")], check=True)
        if not os.path.exists(os.path.join(out, "summary.json")):
            continue
        s = json.load(open(os.path.join(out, "summary.json")))
        figures = ", ".join(f"{k} = {s['metrics'][k]:.4g}" for k in keys if k in s["metrics"])
        rows.append(f"| {name} | {s['particles']['fluid']} | {s['steps']} | {s['end_time']:.3g} s | "
                    f"{s['wall_seconds']:.0f} s ({s['backend']}, {s['threads']} threads) | "
                    f"{s['cg_iterations_mean']:.0f} / {s['cg_iterations_max']} | {figures} | {acceptance} |")
    with open(os.path.join(ROOT, "docs", "validation.md"), "w") as f:
        f.write("# Validation of the single-phase ISPH\n\n")
        f.write(f"Made by `scripts/validate.py` on {datetime.date.today()} "
                f"({platform.node()}, {platform.machine()}, {os.cpu_count()} cores); "
                "plots by `scripts/plot_run.py`. Figures are relative "
                "(0.01 = 1 %).\n\n")
        f.write("| scene | fluid particles | steps | simulated | wall time | CG mean / max | "
                "figures | acceptance |\n|---|---|---|---|---|---|---|---|\n")
        f.write("\n".join(rows) + "\n\n")
        f.write(NOTES)
        for name, _, _ in CASES:
            kind = "front" if name.startswith("dam") else "pressure"
            if os.path.exists(os.path.join(ROOT, "docs", f"{name}_{kind}.png")):
                f.write(f"![{name}]({name}_{kind}.png)\n\n")
    print("wrote docs/validation.md")


if __name__ == "__main__":
    main()
