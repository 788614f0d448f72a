#!/usr/bin/python3
"""The first step of a dam break against potential flow: the horizontal acceleration of
the water's open face, a_x = v/dt after one step from rest, by height, next to that of
the initial pressure of an inviscid column released at once (Laplace's equation for P
in the column, P = 0 on the top and the open face, dP/dn = rho g.n on the floor and the
back wall; cell-centred finite differences, refined until the figures below stop
changing). Run the step first, e.g.
  build/dvisph run scenes/dam_break_2d.yaml --set end_time=1e-9 --set output.snapshot_every=1e-9 --out out/start
Usage: dam_break_start.py RUN_DIR [--cells N]   (N cells across the column, default 200)"""
import argparse
import glob
import os

import h5py
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
import yaml


def column_pressure(a, H, rho, g, n):
    """Cell centres (x, y) and the initial pressure of a column a wide, H high."""
    h = a / n
    ny = int(round(H / h))
    hy = H / ny
    idx = lambda i, j: j * n + i  # noqa: E731
    rows, cols, vals, b = [], [], [], np.zeros(n * ny)
    for j in range(ny):
        for i in range(n):
            k, diag = idx(i, j), 0.0
            for di, dj, h2 in ((1, 0, h * h), (-1, 0, h * h), (0, 1, hy * hy), (0, -1, hy * hy)):
                ii, jj = i + di, j + dj
                if 0 <= ii < n and 0 <= jj < ny:
                    rows.append(k), cols.append(idx(ii, jj)), vals.append(1 / h2)
                    diag -= 1 / h2
                elif ii == n or jj == ny:  # open face or top: P = 0 on the face
                    diag -= 2 / h2
                elif jj == -1:  # floor: dP/dy = -rho g
                    b[k] -= rho * g * hy / h2
                # back wall: dP/dx = 0, the ghost equals the cell
            rows.append(k), cols.append(k), vals.append(diag)
    A = sp.csr_matrix((vals, (rows, cols)), shape=(n * ny, n * ny))
    return (np.arange(n) + 0.5) * h, (np.arange(ny) + 0.5) * hy, spl.spsolve(A, b).reshape(ny, n)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--cells", type=int, default=200)
    args = ap.parse_args()
    sc = yaml.safe_load(open(os.path.join(args.run, "scene.yaml")))
    rho = sc.get("material", {}).get("density", 1000.0)
    g = abs(sc["material"]["gravity"][-1])
    with h5py.File(sorted(glob.glob(os.path.join(args.run, "snapshot_*.h5")))[-1]) as f:
        t, x, v, fluid = f.attrs["time"][0], f["x"][:], f["velocity"][:], f["kind"][:] == 0
    D = x.shape[1]
    dx = sc["geometry"]["spacing"]
    lo = np.array(sc["geometry"]["tank"]["lo"], float)
    # the column as the lattice fills it: whole spacings from the back wall and the floor
    box = sc["geometry"]["fluid"][0]
    a = np.floor((box["hi"][0] - box["lo"][0]) / dx + 1e-9) * dx
    H = np.floor((box["hi"][-1] - box["lo"][-1]) / dx + 1e-9) * dx
    xc, yc, p = column_pressure(a, H, rho, g, args.cells)
    face_x = x[fluid, 0].max()
    face = fluid & (x[:, 0] > face_x - 0.2 * dx)
    layer = np.round((x[:, D - 1] - lo[D - 1]) / dx - 0.5).astype(int)  # lattice layers
    layers = np.unique(layer[face])
    print(f"{sc.get('name', args.run)}: column {100 * a:.1f} x {100 * H:.1f} cm, dx = {1000 * dx:g} mm, "
          f"first step dt = {t:g} s; a_x / g of the open face")
    print("height / H | dvisph (mean over the face's particles at that height) | potential flow")
    for k in layers[:4].tolist() + layers[4::max(1, len(layers) // 6)].tolist():
        at = face & (layer == k)
        y = np.mean(x[at, D - 1]) - lo[D - 1]
        j = np.argmin(np.abs(yc - y))
        pot = -np.interp(face_x - lo[0], xc, np.gradient(p[j], xc)) / rho
        print(f"{y / H:.3f} | {np.mean(v[at, 0]) / t / g:.3f} | {pot / g:.3f}")


if __name__ == "__main__":
    main()
