#!/usr/bin/python3
"""Plots of a run directory (written by `dvisph run`): the surge front against Martin &
Moyce (1952) for dam breaks (and the bead front where there are beads; time from the
gate's removal) and, where the runs wrote density_error_histogram.csv
(metrics.density_error_at), the density error's histograms side by side over 0-50 %
and 0-5 % (as the paper shows them) into <PNG>_density_error.png, and the fronts at
T = 0.5, 1, ..., 4 into <PNG>.csv; pressure against
depth for hydrostatic tanks, energy and bed height for bead runs, the bead front for a
dry collapse.
Usage: plot_run.py RUN_DIR [more RUN_DIRs with the same metrics kind] [-o PNG]"""
import argparse
import csv
import glob
import json
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene_of(run):
    with open(os.path.join(run, "scene.yaml")) as f:
        return yaml.safe_load(f)


def series(run):
    with open(os.path.join(run, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def martin_moyce():
    d = np.loadtxt(os.path.join(ROOT, "data", "martin_moyce_1952.csv"), delimiter=",",
                   comments="#", skiprows=4)
    return d[:, 0], d[:, 1]


def last_snapshot(run):
    """Positions, pressure, fluid mask and time of a run's last snapshot."""
    snaps = sorted(glob.glob(os.path.join(run, "snapshot_*.h5")))
    with h5py.File(snaps[-1]) as f:
        return f["x"][:], f["pressure"][:], f["kind"][:] == 0, f.attrs["time"][0]


def fronts_from_gate(run):
    """T from the gate's removal and Z of the water front (and of the bead front, or
    None) of a dam-break run."""
    s, sc = series(run), scene_of(run)
    a = sc["metrics"]["column_width"]
    g = abs(sc.get("material", {}).get("gravity", [0, -9.81])[-1])
    t0 = sc["geometry"].get("gate", {}).get("remove_at", 0)
    after = s["t"] >= t0
    T = (s["t"][after] - t0) * np.sqrt(2 * g / a)
    beads = s["bead_front"][after] / a if "bead_front" in s else None
    return T, s["front"][after] / a, beads


def write_front_table(runs, path, labels=None):
    """Z of each run's water and bead fronts at T = 0.5, 1, ..., 4 (interpolated in T;
    empty past a run's end) into a CSV, so that fronts can be compared in numbers."""
    Ts = np.arange(0.5, 4.01, 0.5)
    cols, names = [], []
    for n, run in enumerate(runs):
        T, Z, B = fronts_from_gate(run)
        name = labels[n] if labels else scene_of(run).get("name", run)
        for what, z in (("water", Z), ("beads", B)):
            if z is None:
                continue
            cols.append([f"{np.interp(t, T, z):.4f}" if t <= T[-1] else "" for t in Ts])
            names.append(f"{name}: {what}")
    with open(path, "w") as f:
        f.write("# Z = z/a of the fronts at T = t sqrt(2g/a) from the gate (src/connected_front.hpp)\n")
        f.write(",".join(["T"] + [f'"{c}"' for c in names]) + "\n")
        for i, t in enumerate(Ts):
            f.write(",".join([f"{t:g}"] + [c[i] for c in cols]) + "\n")


def plot_front(runs, png, labels=None):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    T, Z = martin_moyce()
    ax.plot(T, Z, "ko", label="Martin & Moyce (1952)")
    for n, run in enumerate(runs):
        sc = scene_of(run)
        a = sc["metrics"]["column_width"]
        path = os.path.join(run, "summary.json")  # none where the run failed: plotted to there
        summary = json.load(open(path)) if os.path.exists(path) else {"metrics": {}}
        rms = summary["metrics"].get("front_rms_deviation_T1_3", float("nan"))
        num = sc.get("numerics", {})
        method = f", alpha {num['alpha']:g} beta {num['beta']:g}" if "alpha" in num and "beta" in num else ""
        name = labels[n] if labels else f"{sc.get('name', run)}: a/dx = {a / sc['geometry']['spacing']:.0f}{method}"
        label = f"{name}, RMS dev. (T 1-3) {100 * rms:.1f} %"
        T, Z, B = fronts_from_gate(run)
        line, = ax.plot(T, Z, "-", label=label)
        if B is not None:
            ax.plot(T, B, "--", color=line.get_color(), label=f"{name}: bead front")
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = z/a")
    ax.set_xlim(0, 4)
    ax.set_ylim(1, 5)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def histogram(run):
    """(lower and upper bin edges, counts, time after the gate) of
    density_error_histogram.csv."""
    with open(os.path.join(run, "density_error_histogram.csv")) as f:
        head = f.readline()
    d = np.loadtxt(os.path.join(run, "density_error_histogram.csv"), delimiter=",", skiprows=2)
    t = float(head.split(" at t = ")[1].split(" s")[0])
    return d[:, 0], d[:, 1], d[:, 2], t


def rebin(lower, upper, count, edges):
    """Counts of fine bins spread over coarser ones by overlap (uniform within a fine bin)."""
    out = np.zeros(len(edges) - 1)
    for lo, up, c in zip(lower, upper, count):
        if c == 0:
            continue
        overlap = np.clip(np.minimum(edges[1:], up) - np.maximum(edges[:-1], lo), 0, None)
        out += c * overlap / (up - lo)
    return out


def plot_density_error(runs, png, labels=None):
    """One column per run: the fraction of counted particles per 1 % (top, 0-50 %) and
    per 0.1 % (bottom, 0-5 %) of |density error|; the file's fine logarithmic bins are
    spread over these by overlap."""
    fig, axes = plt.subplots(2, len(runs), figsize=(4 * len(runs), 6), squeeze=False)
    for n, run in enumerate(runs):
        lower, upper, count, t = histogram(run)
        total = count.sum()
        sc = scene_of(run)
        summary = json.load(open(os.path.join(run, "summary.json")))["metrics"]["density_error_at"]
        name = labels[n] if labels else sc.get("name", run)
        for row, (top, width) in enumerate([(50, 1.0), (5, 0.1)]):
            edges = np.arange(0, top + width / 2, width)
            frac = rebin(100 * lower, 100 * upper, count, edges) / max(total, 1)
            ax = axes[row, n]
            ax.bar(edges[:-1], frac, width=width, align="edge", color="C%d" % n, edgecolor="none")
            ax.set_xlim(0, top)
            ax.set_xlabel("|density error| [%]")
            ax.set_ylabel("fraction of particles")
            ax.grid(alpha=0.3)
            beyond = count[100 * upper > top].sum() / max(total, 1)
            ax.set_title(f"{name}\n{t:.2f} s after the gate: p95 {100 * summary['p95']:.2f} %, "
                         f"max {100 * summary['max']:.1f} %" if row == 0 else
                         f"0-{top} %: {100 * (1 - beyond):.1f} % of {int(total)} particles", fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def plot_pressure(runs, png):
    fig, ax = plt.subplots(figsize=(5, 5))
    for run in runs:
        sc = scene_of(run)
        x, p, fluid, t = last_snapshot(run)
        dim = x.shape[1]
        y = x[fluid, dim - 1]
        rho = sc.get("material", {}).get("density", 1000.0)
        g = abs(sc.get("material", {}).get("gravity", [0] * (dim - 1) + [-9.81])[-1])
        H = sc["metrics"]["water_height"]
        ax.plot(p[fluid] / (rho * g * H), (H - y) / H, ".", ms=2,
                label=f"{sc.get('name', run)} at t = {t:.2f} s")
    ax.plot([0, 1], [0, 1], "k-", lw=1, label="rho g (H - y)")
    ax.set_xlabel("P / (rho g H)")
    ax.set_ylabel("depth (H - y) / H")
    ax.invert_yaxis()
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def plot_beads(runs, png):
    """Energy (kinetic on a log scale) and the heights of the beads against time."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for run in runs:
        s, sc = series(run), scene_of(run)
        name = sc.get("name", run)
        ax1.semilogy(s["t"], np.maximum(s["kinetic_energy"], 1e-16), label=f"{name}: kinetic")
        ax1.semilogy(s["t"], s["total_energy"] - s["total_energy"].min() + 1e-16, "--",
                     label=f"{name}: total - its final value")
        if sc["metrics"]["kind"] == "bead_collapse":
            a = sc["metrics"]["column_width"]
            g = abs(sc.get("material", {}).get("gravity", [0, 0, -9.81])[-1])
            ax2.plot(s["t"] * np.sqrt(2 * g / a), s["front"] / a, label=f"{name}: bead front")
            ax2.set_xlabel("T = t sqrt(2g/a)")
            ax2.set_ylabel("Z = z/a")
        else:
            ax2.plot(s["t"], 100 * s["bed_top"], label=f"{name}: highest bead top")
            summary = json.load(open(os.path.join(run, "summary.json")))["metrics"]
            if "bed_height" in summary:
                ax2.axhline(100 * summary["bed_height"], color="k", lw=1,
                            label=f"bed height {100 * summary['bed_height']:.2f} cm at packing "
                                  f"{summary['packing_fraction_core']:.3f}")
            ax2.set_xlabel("t [s]")
            ax2.set_ylabel("height [cm]")
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("energy [J]")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("-o", "--output", help="PNG file (default: RUN_DIR/<kind>.png)")
    ap.add_argument("--labels", help="legend names separated by ;, one per RUN_DIR (dam breaks)")
    args = ap.parse_args()
    kind = scene_of(args.runs[0]).get("metrics", {}).get("kind", "none")
    if kind == "dam_break":
        png = args.output or os.path.join(args.runs[0], "front.png")
        labels = args.labels.split(";") if args.labels else None
        plot_front(args.runs, png, labels)
        table = os.path.splitext(png)[0] + ".csv"
        write_front_table(args.runs, table, labels)
        print("wrote", table)
        if all(os.path.exists(os.path.join(r, "density_error_histogram.csv")) for r in args.runs):
            hist = os.path.splitext(png)[0] + "_density_error.png"
            plot_density_error(args.runs, hist, labels)
            print("wrote", hist)
    elif kind == "hydrostatic":
        png = args.output or os.path.join(args.runs[0], "pressure.png")
        plot_pressure(args.runs, png)
    elif kind in ("bead_bed", "bead_collapse"):
        png = args.output or os.path.join(args.runs[0], "beads.png")
        plot_beads(args.runs, png)
    else:
        print("no plot for metrics kind", kind)
        return
    print("wrote", png)


if __name__ == "__main__":
    main()
