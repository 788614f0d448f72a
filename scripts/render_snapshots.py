#!/usr/bin/python3
"""Side views (x against the vertical axis) of a run's snapshots: water blue, beads orange,
walls grey (2D only); in 3D the particles are projected along y.
Usage: render_snapshots.py RUN_DIR [-t TIMES] [-o PNG]
TIMES: comma-separated times in s (the nearest snapshot each; default: six spread over
the run)."""
import argparse
import glob
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

KINDS = {0: ("water", "tab:blue"), 1: ("wall", "0.75"), 2: ("gate", "tab:red"), 3: ("beads", "tab:orange")}


def snapshots(run):
    out = []
    for path in sorted(glob.glob(os.path.join(run, "snapshot_*.h5"))):
        with h5py.File(path) as f:
            out.append((f.attrs["time"][0], path))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("run")
    ap.add_argument("-t", "--times")
    ap.add_argument("-o", "--output")
    args = ap.parse_args()
    snaps = snapshots(args.run)
    if args.times:
        wanted = [float(t) for t in args.times.split(",")]
        chosen = [min(snaps, key=lambda s: abs(s[0] - t)) for t in wanted]
    else:
        chosen = [snaps[i] for i in np.linspace(0, len(snaps) - 1, min(6, len(snaps))).astype(int)]
    fig, axes = plt.subplots(len(chosen), 1, figsize=(9, 1.9 * len(chosen)), squeeze=False)
    for ax, (t, path) in zip(axes[:, 0], chosen):
        with h5py.File(path) as f:
            x, kind = f["x"][:], f["kind"][:]
        up = x.shape[1] - 1
        for k, (name, colour) in KINDS.items():
            m = kind == k
            if not m.any() or name == "wall":
                continue
            size = 1.5 if name != "beads" else 2.0
            ax.scatter(x[m, 0], x[m, up], s=size, c=colour, lw=0, label=name,
                       alpha=0.35 if x.shape[1] == 3 and name == "water" else 1)
        walls = kind == 1
        if x.shape[1] == 2:  # in 3D the side walls would cover the view
            ax.scatter(x[walls, 0], x[walls, up], s=0.3, c="0.8", lw=0)
        ax.set_xlim(x[:, 0].min(), x[:, 0].max())  # the tank, walls included
        ax.set_ylim(x[:, up].min(), x[:, up].max())
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:.3f} s", fontsize=9)
        ax.tick_params(labelsize=7)
    axes[0, 0].legend(fontsize=7, loc="upper right", markerscale=4)
    fig.tight_layout()
    png = args.output or os.path.join(args.run, "side_views.png")
    fig.savefig(png, dpi=110)
    print("wrote", png)


if __name__ == "__main__":
    main()
