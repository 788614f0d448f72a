#!/usr/bin/python3
"""Stability stress matrix: runs every cell of every case in CASES with `dvisph run`
and writes docs/stability.md (and out/stability/<case>.json).

A cell is *stable* when the run reaches its end time with no guard firing (no NaN, no
particle out of the domain, CG converged within its cap, no DEM bead overlapping more
than half its radius or skipping contacts) and
  - water: the density error of submerged particles stayed below 10 % (its largest over
    the run; in the cases with beads, the largest over the series rows of its p95,
    because there the max is set by one particle for one or two rows in every cell);
  - beads: the total energy never rose by more than 1e-9 of its initial value between
    series rows (a dissipative system must not gain energy).
Adding a case (e.g. a coupled one later) is one entry in CASES.

Usage: scripts/stability.py [--only CASE ...] [--jobs N] [--table-only]
"""
import argparse
import concurrent.futures
import datetime
import itertools
import json
import os
import platform
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DVISPH = os.path.join(ROOT, "build", "dvisph")
OUT = os.path.join(ROOT, "out", "stability")

WATER_LIMIT = 0.10   # density error of a stable water run
ENERGY_RISE = 1e-9   # relative energy rise of a stable bead run

# A small bead bed: 300 beads in a 2 cm x 2 cm footprint, or released by a gate.
SMALL_BED = {
    "geometry.tank.hi": "[0.02, 0.02, 0.15]",
    "solids.lattice": "[{lo: [0, 0, 0], hi: [0.02, 0.02, 0.12]}]",
    "solids.count": 300,
    "output.series_every": 20,
    "output.snapshot_every": 0,
}
SMALL_COLLAPSE = dict(SMALL_BED, **{
    "geometry.tank.hi": "[0.1, 0.02, 0.15]",
    "geometry.gate": "{x: 0.02, remove_at: 0.0}",
    "metrics.kind": "bead_collapse",
    "metrics.column_width": 0.02,
})

CASES = [
    dict(name="dam_break_2d", kind="water", scene="scenes/dam_break_2d.yaml",
         what="water dam break, a/dx = 20, to T = 3",
         base={"geometry.spacing": 0.0025, "geometry.wall_layers": 6, "end_time": 0.152,
               "output.snapshot_every": 0},
         grid={"numerics.cfl": [0.1, 0.25, 0.5], "numerics.gamma": [0, 0.001, 0.1, 0.5, 1],
               "numerics.h_over_dx": [1.2, 1.5, 1.6], "geometry.jitter": [0, 0.1]}),
    dict(name="dam_break_2d_impact", kind="water", scene="scenes/dam_break_2d.yaml",
         what="water dam break, a/dx = 20, hitting the far wall 0.2 m from the back wall, to T = 8",
         base={"geometry.spacing": 0.0025, "geometry.wall_layers": 6, "geometry.tank.hi": "[0.2, 0.4]",
               "end_time": 0.4, "output.snapshot_every": 0},
         grid={"numerics.cfl": [0.1, 0.25], "numerics.gamma": [0.001, 0.1, 0.5, 1]}),
    dict(name="hydrostatic_2d", kind="water", scene="scenes/hydrostatic_2d.yaml",
         what="still water 10 cm deep, dx = 5 mm, 1 000 steps",
         base={"geometry.spacing": 0.005, "geometry.wall_layers": 6, "end_time": 1.0,
               "output.snapshot_every": 0, "output.series_every": 10},
         grid={"numerics.gamma": [0, 0.001, 0.1, 0.5, 1], "numerics.h_over_dx": [1.2, 1.5, 1.6],
               "geometry.jitter": [0, 0.1]}),
    dict(name="hydrostatic_3d_long", kind="water", scene="scenes/hydrostatic_3d.yaml",
         what="still water in 3D, dx = 6.25 mm (coarse, to afford the length), 20 000 steps",
         base={"geometry.spacing": 0.00625, "end_time": 20.0, "output.snapshot_every": 0,
               "output.series_every": 100},
         grid={"numerics.gamma": [0.1]}),
    dict(name="bead_bed", kind="beads", scene="scenes/bead_bed_settle.yaml",
         what="300 beads settling for 0.05 s",
         base=dict(SMALL_BED, end_time=0.05),
         grid={"solids.stiffness": [1e2, 1e3, 1e4, 1e5], "solids.dt_safety": [0.02, 0.1, 0.2, 0.5],
               "solids.restitution": [0.1, 0.5, 0.9, 0.99]}),
    dict(name="dry_collapse", kind="beads", scene="scenes/bead_bed_settle.yaml",
         what="300 beads released by a gate, 0.05 s",
         base=dict(SMALL_COLLAPSE, end_time=0.05),
         grid={"solids.stiffness": [1e2, 1e3, 1e4, 1e5], "solids.dt_safety": [0.02, 0.1, 0.2, 0.5],
               "solids.restitution": [0.1, 0.9]}),
    dict(name="glass_beads_2d", kind="water", limit="p95", scene="scenes/glass_beads_dam_break_2d.yaml",
         what="the paper's case in 2D (water and glass beads, dx = 3 mm), to 0.25 s after the gate",
         base={"end_time": 0.55, "output.snapshot_every": 0},
         grid={"numerics.cfl": [0.1, 0.25, 0.5], "numerics.alpha": [0, 0.001],
               "numerics.beta": [0.001, 0.5], "solids.density": [2500, 1050]}),
]


# What the matrix showed (2026-11-22), printed under each table; update when re-run.
FINDINGS = {
    "dam_break_2d":
        "2026-12-02 (issue 16): re-run with CG's density stop (numerics.cg_density_tolerance = 1e-6, docs/isph.md) and the finer fluid cells: 80 of 90 cells stable (79 before), CG 44 iterations a step on average over the cells. Median density error over the stable cells of each gamma: 0: 8.6 % (16), 0.001: 8.7 % (16), 0.1: 7.0 % (18), 0.5: 7.5 % (15), 1: 6.7 % (15). The unstable cells are the same kinds: h/dx = 1.2 from a jittered start (12.2 %) and CFL 0.5 with gamma <= 0.001 (10.7-11.2 %). "
        "2026-12-01 (issue 19): re-run with the density-invariance weight read from the support's truncation instead of div r, and with the density error as the paper reads it (P >= 100 Pa, no free-surface particle within the support, under- and over-density alike; docs/isph.md). 79 of 90 cells stable (75 before), no guard fails. Median density error over the stable cells of each gamma: 0: 8.2 % (16), 0.001: 8.7 % (16), 0.1: 6.6 % (17), 0.5: 7.5 % (15), 1: 6.7 % (15). Unstable: h/dx = 1.2 from a jittered start (12.2 %, the jitter's first-step figure, the same in every such cell), and CFL 0.5 with gamma <= 0.1 (10.3-11.2 %). Session 6's figures follow. "
        "Session 6, with the wall condition that stops water moving into a wall (docs/isph.md): "
        "75 of 90 cells stable (62 before it) and no cell fails a guard any more. The h/dx = 1.2, "
        "gamma >= 0.5, CFL 0.1 cells that diverged (described below) now run: the floor "
        "particles pressed into the wall, which carried 25-40 kPa, are stopped at it, and the "
        "reproduction command below now ends at a density error of 6.1 % with the fastest "
        "particle at 1.5 m/s. The unstable cells left are density errors of 10-13.6 %: h/dx = "
        "1.2 from a jittered start (12.2 %, the same in every such cell), h/dx = 1.2 with gamma "
        "= 1 at CFL >= 0.25, and CFL 0.5 with gamma <= 0.1. Median density error over the stable "
        "cells of each gamma: 0: 8.75 % (16), 0.001: 8.7 % (16), 0.1: 6.7 % (16), 0.5: 7.5 % "
        "(14), 1: 6.7 % (13). What follows is the history before it. "
        "Re-run after the fix below (session 3). The first run of this matrix found gamma = 0.1 "
        "and 1 raising the density error to 18-28 % instead of lowering it (0 of 18 cells "
        "stable at gamma = 1, 3 of them crashing). Cause: the density-invariance term read "
        "the low summation density of particles whose support reaches into the air (the "
        "layers under the free surface) as expansion and compressed the water there, every "
        "step. Fix: the term is weighted by how full the support is (position divergence, "
        "docs/isph.md); particles whose support reaches well into the air no longer count in "
        "the density error either. Median density error over the 18 cells of each gamma "
        "(stable cells): gamma = 0: 9.4 % (11), 0.001: 9.0 % (12), 0.1: 7.9 % (15), "
        "0.5: 7.9 % (12), 1: 7.5 % (12); before the fix 0.1 gave 10.9 % (8) and 1 gave 25.2 % "
        "(0). gamma = 0.1 is the default: the most stable cells, no failure. Still weak then: "
        "h/dx = 1.2 with gamma >= 0.5 diverges in 3 of its 12 cells (all at CFL 0.1: CG, a "
        "particle thrown out) and reaches 10-38 % in the others. How the CFL 0.1 cells fail "
        "(`dvisph run scenes/dam_break_2d.yaml --set geometry.spacing=0.0025 --set "
        "geometry.wall_layers=6 --set end_time=0.152 --set output.snapshot_every=0 --set "
        "output.series_every=1 --set numerics.cfl=0.1 --set numerics.gamma=1 --set "
        "numerics.h_over_dx=1.2`, series.csv): until t = 0.080 s dt = 2.5e-4 s and the "
        "fastest particle moves at 1.2 m/s; then floor particles under the collapsing column, "
        "pressed toward the wall (one at y = 0, half a spacing below the lowest "
        "fluid row) by the short support, carry 25-40 kPa (hydrostatic there: 0.5 kPa) and "
        "the fastest speed climbs 6, 13, 34, 190, 82 000 m/s while dt falls 5e-5, 9e-6, "
        "1.6e-6, 4e-9 s; CG then fails at step 948. The density-invariance term asks for a "
        "position correction dx_c that does not shrink with dt, and in this one-velocity "
        "solver the velocity carries it as dx_c / dt; the CFL limit then shrinks dt by "
        "CFL h / dx_c a step, so once dx_c exceeds CFL h (0.12 dx here) dt collapses "
        "geometrically. That is why it strikes at the smallest CFL. Before the speed jumps "
        "the run oscillates with a period of two steps: from step 219 the CG iteration count "
        "alternates between 76-91 and 102-113 while the largest density error climbs from "
        "4 % to 28 % (step 242), as when each step's correction overshoots and the next "
        "reverses it, the velocity that carried it staying in the momentum. The dual-velocity method "
        "(method.md section 4) removes the feedback where it belongs: the correction "
        "(gamma = beta) goes into the transport velocity only, and the time step must then "
        "come from the physical velocity (gamma = alpha), with the transport displacement "
        "per step bounded on its own (a fraction of h), not through a CFL number. "
        "From a jittered start, "
        "gamma >= 0.5 lifts the error from the jitter's 5 % to 6.7-7.9 % in the first step "
        "(the same figure at every CFL) and then lowers it. On a regular lattice one "
        "correction cannot overshoot: the divergence of the symmetric gradient never scales "
        "a mode by more than the Morris Laplacian does (ratio <= 1.004, scripts/ppe_symbols.py); "
        "on disordered particles that bound is lost (the Morris Laplacian is not the "
        "divergence of the symmetric gradient there), so a full one-step correction is "
        "mis-sized at the particle scale. "
        "Next: the gamma part of the solve with the D G operator itself, or a consistent "
        "Laplacian. CFL 0.5 costs 1-5 points of density error at every gamma.",
    "dam_break_2d_impact":
        "2026-12-02 (issue 16), with CG's density stop: 3 of 8 cells stable, as before, CG 22-41 iterations a step (62-77 before); the largest density error 5.7-15.0 % (before 5.7-14.7 %; CFL 0.1, gamma 0.5 rose from 10.9 to 15.0 %, gamma 1 from 8.2 to 9.5 %), water up to 0.26 dx into the wall (before 0.26 dx). "
        "2026-12-01 (issue 19), same changes as above: 3 of 8 cells stable (1 before): the largest density error, set at the impact, is 5.7-14.7 % (before 9.8-21 %), lower in every cell; water gets up to 0.26 dx into the wall (before 0.31 dx). Session 6's text follows. "
        "Added in session 6: no earlier case drove water at a wall. The front reaches the far "
        "wall at t = 0.15 s (T = 3) at about 1.5 m/s. With the hydrostatic wall condition alone "
        "the walls did not stop it: at CFL 0.25 with gamma <= 0.1 a particle passed through all "
        "six wall layers and left the domain (t = 0.28-0.32 s), and in the other cells water "
        "ended 1-8.5 dx inside the wall with a density error of 15-25 %. Cause: the wall rows "
        "continued the fluid pressure with the hydrostatic gradient, a Neumann condition that "
        "knew nothing of water driven at the wall; the tip reached the first wall layer 20 % "
        "over-dense, and once among the wall particles the symmetric gradient pushed it "
        "outward. Fix (docs/isph.md): the wall rows add the step dP/dn = rho0 vn / dt that "
        "brings the water's normal velocity toward the wall to rest. Now every cell runs to the "
        "end and water stays within 0.31 dx of the wall faces; the largest density error, set "
        "at the impact, is 9.8-21 %. At the scene's spacing (a/dx = 40, `dvisph run "
        "scenes/dam_break_2d.yaml --set 'geometry.tank.hi=[0.2, 0.4]' --set end_time=0.4`): "
        "0.17 dx, largest density error 16 %, p95 2.1 % (before: a particle left through the "
        "wall at t = 0.177 s). In 3D (`dvisph run scenes/dam_break_3d.yaml --set end_time=0.32`, "
        "a/dx = 20, the front at the far wall from t = 0.21 s) the run now finishes where a "
        "particle left through a corner at t = 0.238 s, but water gets 0.75 dx into the corner "
        "walls (largest density error 19.5 %, p95 3.8 %). Next: the corners, and the impact's "
        "density error with the dual-velocity step's transport correction.",
    "hydrostatic_2d":
        "2026-12-02 (issue 16), with CG's density stop: 30 of 30 stable; the largest density error over the cells 8.0 % (h/dx = 1.2, jittered). "
        "2026-12-01 (issue 19), same changes: 30 of 30 stable. With the new metric the regular "
        "lattices at h/dx >= 1.5 reach at most 0.24-0.93 % (before 0.2-1.44 %) and the jittered ones "
        "2.4-5.2 % (before also 2.4-5.2 %), the jitter's own error included. Earlier text: "
        "Every cell keeps all particles; every CG converged. The density error is the largest "
        "over the run, which for a jittered start is the jitter itself (about 5 %). Without "
        "jitter at h/dx >= 1.5: 1.37-1.44 % at gamma <= 0.001, 0.65-0.78 % at 0.1, 0.2-0.39 % at "
        "0.5 and 1; h/dx = 1.2 is the worst support (1.1-8.0 %). Session 6's wall condition (the "
        "step that stops water moving into a wall, docs/isph.md) raised the gamma <= 0.1 figures "
        "(before it: 0.93-1.01 % and 0.53-0.54 %; the term only pushes, so velocity noise at the "
        "wall leaves a small push) and made the one unstable cell stable (gamma = 1, h/dx = 1.2, "
        "jitter: 10.7 % before, 5.4 % now). Before the density-invariance fix of session 3: "
        "3.2-3.7 % at gamma = 0.1 and 19-23 % at 1.",
    "hydrostatic_3d_long":
        "2026-12-01 (issue 19): largest density error 0.32 % with the new metric and weight "
        "(before 0.86 %), CG 29 iterations on average (48 at most), 20 000 steps, no particle "
        "lost. Earlier text: 20 000 steps at 8 particles over the depth, gamma = 0.1 (the default since the fix "
        "above): no particle lost, CG 32 iterations on average (48 at most) to the end, "
        "largest density error 0.86 % (p95 0.34 %), pressure within 1.5 % of rho g H (rms "
        "1.1 %; 8 layers resolve the surface layer coarsely); before session 6's wall "
        "condition 0.73 % (p95 0.26 %) and 1.7 %. The first run (gamma = 0.001, "
        "before the fix and the stored PPE matrix) gave 3.4 % and took 2362 s. The "
        "full-resolution tank (dx = 2.5 mm) for 20 000 steps would take about 2.4 h here "
        "(0.43 s a step) and was not run here. 4 096 wall particles for 512 fluid ones. "
        "The full-resolution tank ran on an NVIDIA H100 (2026-11-22, CUDA build, "
        "benchmarks/RESULTS.md; before session 6's wall condition, not re-run since: no GPU "
        "lent): `dvisph run scenes/hydrostatic_3d.yaml --set end_time=20.0 "
        "--set output.snapshot_every=0 --set output.series_every=100`, dx = 2.5 mm, 8 000 "
        "fluid and 18 496 wall particles, 20 000 steps in 168 s: stable, no particle lost, "
        "CG 72 iterations on average (95 at most), largest density error 0.40 % (p95 0.18 %), "
        "pressure within 0.46 % of rho g H (rms 0.22 %; pointwise 1.9 % below the top two "
        "layers). Summary and series: "
        "benchmarks/results/hydrostatic_3d_20000_steps_cuda_h100.json and _series.csv.",
    "bead_bed":
        "Before solids.dt_safety was capped at 0.1 (cells at 0.2 and 0.5 are now rejected as "
        "input): at dt = t_c/2 beads moved more than half the contact skin in a step (the "
        "guard stopped the run), and at t_c/5 a strongly damped bed (e = 0.1) gained 0.2-0.3 % "
        "energy. At dt_safety <= 0.1 every run finishes; near-elastic contacts (e = 0.99) at "
        "k_n = 1e5 N/m show energy rises of 4e-8 to 6e-7 between series rows: the bounded "
        "O(dt^2) energy error of velocity Verlet during contacts, not growth.",
    "dry_collapse":
        "As for the bed (the first 0.05 s of a collapse is mostly the same fall).",
    "glass_beads_2d":
        "2026-12-02 (issue 16), with CG's density stop and the finer fluid cells: 21 of 24 cells stable (22 before); the cell that went over is the conventional step (alpha = beta = 0.001) at CFL 0.1 with 2500 kg/m3 beads, at a p95 of 10.0 %, on the threshold; every proposed cell (beta = 0.5) is stable. "
        "2026-12-02 (issue 15), the scene with h_c = 2.5 d (coupling.smoothing_length 6.75 mm), "
        "d eps/dt in the PPE source and the wall stop step at the water's mobility "
        "(docs/coupling.md). Judged on the p95 over the run: in most cells with beads a single "
        "particle sets the run's max (up to 77 %) for a row or two (front-tip particles on the floor, "
        "25-40 % of their reference density at P 265-444 Pa, whose support is emptied evenly "
        "so that the truncation test does not read them as surface). 22 of 24 stable, no run "
        "ended by a guard. The proposed step (alpha = 0, beta = 0.5) is stable in every cell "
        "(6 of 6; p95 0.2 s after the gate 1.35-2.24 %), the conventional one (alpha = beta = "
        "0.001) in 5 of 6 (p95 6.9-7.6 %; at CFL 0.1 with beads of 1050 kg/m^3 its p95 reaches "
        "10 %), so the proposed step is stable wherever the conventional one is; beta = 0.5: "
        "12 of 12, beta = 0.001: 10 of 12. "
        "Before, with h_c = h = 4.5 mm = 1.67 d (the scene's earlier default): 16 of 24 stable, "
        "proposed 5 of 6 and conventional 4 of 6, and light beads at CFL 0.1 ended 3 runs of "
        "both methods by the DEM guard (a bead at 6-13 m/s). In the proposed cell that failed "
        "(restarted from its last good state one step before), the front's water on the floor, "
        "a layer one or two particles thick among the beads, held P = -6e4 to -7.5e4 Pa with "
        "21 pairs of fluid particles closer than 0.2 dx, and the beads there got |F/m| up to "
        "1500 g: suction in a clumped thin layer, which a light bead feels 2.4 times as "
        "strongly as a glass one. The wider coupling kernel removed these failures, as "
        "method.md section 3 warns (a porosity averaged over fewer than about three bead "
        "diameters is noisy and the coupling unstable). Still earlier (with d eps/dt but the "
        "wall stop step at clear water's strength): 13 of 24, runs' max 53-83 % set by water "
        "inside the walls (up to 4 dx).",
}


def cells(case):
    keys = list(case["grid"])
    for values in itertools.product(*(case["grid"][k] for k in keys)):
        yield dict(zip(keys, values))


def cell_name(case, cell):
    return case["name"] + "__" + "__".join(f"{k.split('.')[-1]}={v}" for k, v in cell.items())


def run_cell(case, cell):
    out = os.path.join(OUT, cell_name(case, cell))
    args = [DVISPH, "run", os.path.join(ROOT, case["scene"]), "--out", out, "--quiet"]
    for k, v in list(case["base"].items()) + list(cell.items()):
        args += ["--set", f"{k}={v}"]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    start = time.time()
    p = subprocess.run(args, capture_output=True, text=True, env=env)
    result = {"cell": cell, "exit": p.returncode, "seconds": round(time.time() - start, 1)}
    summary = os.path.join(out, "summary.json")
    if p.returncode == 0 and os.path.exists(summary):
        s = json.load(open(summary))
        m = s["metrics"]
        result["steps"] = s["steps"]
        if case["kind"] == "water":
            result["density_error"] = m["max_density_error"]
            result["density_error_p95"] = m["density_error_p95"]
            if "density_error_at" in m:
                result["density_error_at_p95"] = m["density_error_at"]["p95"]
            result["cg_mean"] = s["cg_iterations_mean"]
            result["cg_max"] = s["cg_iterations_max"]
            result["wall_penetration"] = m.get("wall_penetration_over_dx")
            judged = "density_error_p95" if case.get("limit") == "p95" else "density_error"
            result["stable"] = result[judged] < WATER_LIMIT
            result["why"] = "" if result["stable"] else (
                "density error p95 >= 10 %" if judged == "density_error_p95" else "density error >= 10 %")
        else:
            rise = m["energy_largest_rise"] / max(m["energy_initial"], 1e-300)
            result["energy_rise"] = rise
            result["stable"] = rise <= ENERGY_RISE
            result["why"] = "" if result["stable"] else "energy rose"
    elif p.returncode == 2:
        result.update(stable=False, why="rejected as input: " + p.stderr.strip().splitlines()[-1][-120:])
    else:
        last = (p.stderr.strip().splitlines() or ["?"])
        why = next((l for l in last if l.startswith("numerical failure")), last[-1])
        result.update(stable=False, why=why[:160])
    return result


def table(case, results):
    keys = list(case["grid"])
    beads = case.get("limit") == "p95"
    cols = keys + ((["density error max / p95 (over the run)", "p95 at 0.2 s"] if beads else ["density error"]) +
                   ["CG mean / max", "wall penetration / dx"] if case["kind"] == "water" else ["energy rise"])
    lines = [f"### {case['name']}: {case['what']}", "",
             f"Scene `{case['scene']}` with " +
             ", ".join(f"`{k}={v}`" for k, v in case["base"].items()) + ".", "",
             "| " + " | ".join(cols + ["steps", "wall s", "stable"]) + " |",
             "|" + "---|" * (len(cols) + 3)]
    stable = 0
    for r in results:
        row = [str(r["cell"][k]) for k in keys]
        if case["kind"] == "water" and beads:
            row += [f"{100 * r['density_error']:.1f} / {100 * r['density_error_p95']:.1f} %"
                    if "density_error" in r else "—",
                    f"{100 * r['density_error_at_p95']:.2f} %" if "density_error_at_p95" in r else "—"]
        elif case["kind"] == "water":
            row += [f"{100 * r['density_error']:.2f} %" if "density_error" in r else "—"]
        if case["kind"] == "water":
            row += [f"{r['cg_mean']:.0f} / {r['cg_max']}" if "cg_mean" in r else "—",
                    f"{r['wall_penetration']:.2f}" if r.get("wall_penetration") is not None else "—"]
        else:
            row += [f"{r['energy_rise']:.1e}" if "energy_rise" in r else "—"]
        row += [str(r.get("steps", "—")), f"{r['seconds']:.0f}",
                "yes" if r["stable"] else "**no**: " + r["why"].replace("|", "/")]
        stable += r["stable"]
        lines.append("| " + " | ".join(row) + " |")
    lines += ["", f"{stable} of {len(results)} cells stable.", ""]
    if case["name"] in FINDINGS:
        lines += [FINDINGS[case["name"]], ""]
    return "\n".join(lines)


def earlier_sections(doc):
    """The case sections of an existing docs/stability.md, by case name."""
    if not os.path.exists(doc):
        return {}
    sections, name = {}, None
    for line in open(doc).read().split("\n"):
        if line.startswith("### "):
            name = line[4:].split(":")[0]
            sections[name] = []
        if name:
            sections[name].append(line)
    return {k: "\n".join(v).rstrip("\n") + "\n" for k, v in sections.items()}


def write_doc():
    parts = [
        "# Stability stress matrix", "",
        f"Made by `scripts/stability.py` on {datetime.date.today()} ({platform.node()}, "
        f"{platform.machine()}, {os.cpu_count()} cores; one OpenMP thread per run). "
        "A cell is stable when the run reaches its end time with no guard firing (NaN, a "
        "particle leaving the domain, CG not converged within its cap, a DEM bead "
        "overlapping more than half its radius or moving more than half the contact skin "
        "in a step) and, for water, the density error stays below "
        f"{100 * WATER_LIMIT:.0f} % (`max_density_error`: the largest over the run of "
        "|<rho> - rho_ref| / rho_ref over fluid particles with P >= 100 Pa and no free-surface "
        "particle within their support, under- and over-density alike, as the paper reads it; "
        "since 2026-12-01, docs/isph.md; in the cases with water and beads the largest over "
        "the series rows of its p95 instead, because there one particle sets the max for a "
        "row or two in every cell); for beads, the total energy never rises "
        f"by more than {ENERGY_RISE:g} of its initial value between series rows. "
        "Wall penetration is how far the deepest fluid particle centre got past the tank's "
        "inner faces over the run (`wall_penetration_over_dx` in summary.json; — where the "
        "run failed or predates the figure). A case run on another day (`--only`) keeps its "
        "table and its findings' dates.", ""]
    doc = os.path.join(ROOT, "docs", "stability.md")
    before = earlier_sections(doc)
    for case in CASES:
        path = os.path.join(OUT, case["name"] + ".json")
        if os.path.exists(path):
            parts.append(table(case, json.load(open(path))))
        elif case["name"] in before:  # run on another day (--only): its table stays
            parts.append(before[case["name"]])
        else:
            parts += [f"### {case['name']}: {case['what']}", "", "not run yet", ""]
    with open(doc, "w") as f:
        f.write("\n".join(parts))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", nargs="*", help="case names (default: all)")
    ap.add_argument("--jobs", type=int, default=1, help="runs at once (one thread each)")
    ap.add_argument("--table-only", action="store_true", help="rewrite docs/stability.md only")
    args = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    if not args.table_only:
        for case in CASES:
            if args.only and case["name"] not in args.only:
                continue
            grid = list(cells(case))
            with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
                results = list(pool.map(lambda c: run_cell(case, c), grid))
            json.dump(results, open(os.path.join(OUT, case["name"] + ".json"), "w"), indent=1)
            print(f"{case['name']}: {sum(r['stable'] for r in results)} of {len(results)} stable",
                  flush=True)
    write_doc()
    print("wrote docs/stability.md")


if __name__ == "__main__":
    main()
