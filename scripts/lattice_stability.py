#!/usr/bin/python3
"""Is a lattice of water particles at rest stable under pressure? (docs/isph.md, "Still water")

In the symmetric pressure gradient, grad P_i = sum_j V_j (P_i + P_j) grad W_ij, a locally
uniform pressure P accelerates particle i by -(2 P V / rho) sum_j grad_i W_ij: the particles
move in the pair potential Phi = (2 P V / rho) sum_pairs W(r_ij). This script computes the
phonon spectrum of the square (2D) or simple cubic (3D) lattice in that potential,
omega^2(k) = eigenvalues of (2 P V / rho) sum_j (1 - cos k.R_j) Hess W(R_j), over the
Brillouin zone. A negative omega^2 is a mode that grows at rate sqrt(-omega^2). It leaves
out the pressure's own response (the PPE holds the volume), so it reads the shear modes.

Usage: scripts/lattice_stability.py  (prints one line per case; a few seconds)
"""
import numpy as np

RHO = 1000.0  # kg/m^3
G = 9.81      # m/s^2


def wendland_c2_derivatives(r, h, dim):
    """dW/dr and d2W/dr2 of the Wendland C2 kernel, support 2h (kernels/wendland_c2.hpp)."""
    q = r / h
    if q >= 2:
        return 0.0, 0.0
    sigma = (7 / (4 * np.pi) if dim == 2 else 21 / (16 * np.pi)) / h ** dim
    t = 1 - q / 2
    return sigma * (-5 * q * t ** 3) / h, sigma * (-5 * t ** 3 + 7.5 * q * t ** 2) / h ** 2


def most_unstable(dx, h_over_dx, dim, pressure, nk=24):
    """(omega^2, k dx / pi, |cos| of the angle between k and the displacement) of the
    lowest mode over the zone."""
    h = h_over_dx * dx
    cells = [np.array(c) for c in np.ndindex(*([9] * dim))]
    neighbours = [(c - 4) * dx for c in cells if (c - 4).any() and np.linalg.norm(c - 4) * dx < 2 * h]
    hessians = []
    for R in neighbours:
        r = np.linalg.norm(R)
        d1, d2 = wendland_c2_derivatives(r, h, dim)
        n = R / r
        hessians.append(d2 * np.outer(n, n) + d1 / r * (np.eye(dim) - np.outer(n, n)))
    scale = 2 * pressure * dx ** dim / RHO
    ks = np.linspace(0, np.pi / dx, nk)
    best = (np.inf, None, None)
    for k in np.array(np.meshgrid(*([ks] * dim))).reshape(dim, -1).T:
        if not k.any():
            continue
        dyn = sum((1 - np.cos(k @ R)) * H for R, H in zip(neighbours, hessians))
        w2s, modes = np.linalg.eigh(scale * dyn)
        if w2s[0] < best[0]:
            best = (w2s[0], k * dx / np.pi, abs(modes[:, 0] @ k) / np.linalg.norm(k))
    return best


CASES = [  # label, dimension, dx, h/dx, water depth (the pressure at the floor)
    ("2D, 10 cm deep (scripts/still_water.py 2d_floor_only)", 2, 0.0025, 1.5, 0.10),
    ("2D, 4 cm deep (2d_floor_only_shallow)", 2, 0.0025, 1.5, 0.04),
    ("2D, 10 cm deep, h = 2 dx (2d_floor_only_h2)", 2, 0.0025, 2.0, 0.10),
    ("2D, 10 cm deep, h = 1.3 dx", 2, 0.0025, 1.3, 0.10),
    ("3D, 3.9 cm deep (3d_floor_only)", 3, 0.003, 1.5, 0.039),
]


def main():
    for label, dim, dx, hr, depth in CASES:
        w2, k, along = most_unstable(dx, hr, dim, RHO * G * depth, nk=24 if dim == 2 else 12)
        if w2 < 0:
            kind = "shear" if along < 0.1 else "compression" if along > 0.9 else "mixed"
            print(f"{label:52s} grows at {np.sqrt(-w2):5.1f} /s, k dx/pi = {np.round(k, 2)}, {kind}")
        else:
            print(f"{label:52s} stable (lowest omega^2 {w2:.3g} /s^2)")


if __name__ == "__main__":
    main()
