#!/usr/bin/python3
"""Is a lattice of water particles at rest stable under pressure? (docs/isph.md, "Still water")

In the symmetric pressure gradient, grad P_i = sum_j V_j (P_i + P_j) grad W_ij, a locally
uniform pressure P accelerates particle i by -(2 P V / rho) sum_j grad_i W_ij: the particles
move in the pair potential (2 P V / rho) sum_pairs W(r_ij). This script computes the
phonon spectrum of a lattice in that potential, omega^2(k) = eigenvalues of
(2 P V / rho) sum_j (1 - cos k.R_j) Hess W(R_j), over the Brillouin zone, for the lattices
dvisph starts from (square, simple cubic) and others at the same particle volume V = dx^D.
A negative omega^2 is a mode that grows at rate sqrt(-omega^2). It leaves out the
pressure's own response (the PPE holds the volume), so it reads the shear modes.

Usage: scripts/lattice_stability.py  (prints one line per case; a few seconds)
"""
import numpy as np

from wendland import d2W, dW

RHO = 1000.0  # kg/m^3
G = 9.81      # m/s^2


def lattice(name, dx):
    """Primitive vectors (rows) of a lattice with one particle per volume dx^D."""
    if name == "square":
        return np.eye(2) * dx
    if name == "hexagonal":
        a = dx * np.sqrt(2 / np.sqrt(3))
        return np.array([[a, 0], [a / 2, a * np.sqrt(3) / 2]])
    if name == "cubic":
        return np.eye(3) * dx
    if name == "fcc":
        c = 4 ** (1 / 3) * dx
        return np.array([[0, c, c], [c, 0, c], [c, c, 0]]) / 2
    raise ValueError(name)


def most_unstable(basis, h, pressure, nk):
    """(omega^2, k, |cos| of the angle between k and the displacement) of the lowest mode."""
    dim = len(basis)
    neighbours = []
    for cell in np.ndindex(*([13] * dim)):
        c = np.array(cell) - 6
        R = c @ basis
        if c.any() and np.linalg.norm(R) < 2 * h:
            neighbours.append(R)
    hessians = []
    for R in neighbours:
        r = np.linalg.norm(R)
        d1, d2 = dW(r, h, dim), d2W(r, h, dim)
        n = R / r
        hessians.append(d2 * np.outer(n, n) + d1 / r * (np.eye(dim) - np.outer(n, n)))
    scale = 2 * pressure * abs(np.linalg.det(basis)) / RHO
    reciprocal = 2 * np.pi * np.linalg.inv(basis).T
    best = (np.inf, None, None)
    for f in np.array(np.meshgrid(*([np.linspace(0, 1, nk, endpoint=False)] * dim))).reshape(dim, -1).T:
        k = f @ reciprocal
        if not k.any():
            continue
        dyn = sum((1 - np.cos(k @ R)) * H for R, H in zip(neighbours, hessians))
        w2s, modes = np.linalg.eigh(scale * dyn)
        if w2s[0] < best[0]:
            # the same mode's shortest wave vector: k less a reciprocal lattice vector
            shifts = np.array(np.meshgrid(*([[-1, 0, 1]] * dim))).reshape(dim, -1).T @ reciprocal
            k = min((k + G for G in shifts), key=np.linalg.norm)
            best = (w2s[0], k, abs(modes[:, 0] @ k) / np.linalg.norm(k))
    return best


CASES = [  # label, lattice, dx, h/dx, water depth (the pressure at the floor)
    ("2D square, 10 cm deep (still_water.py 2d_floor_only)", "square", 0.0025, 1.5, 0.10),
    ("2D square, 4 cm deep (2d_floor_only_shallow)", "square", 0.0025, 1.5, 0.04),
    ("2D square, 10 cm deep, h = 2 dx (2d_floor_only_h2)", "square", 0.0025, 2.0, 0.10),
    ("2D square, 10 cm deep, h = 1.3 dx", "square", 0.0025, 1.3, 0.10),
    ("2D hexagonal, 10 cm deep", "hexagonal", 0.0025, 1.5, 0.10),
    ("2D hexagonal, 10 cm deep, h = 1.3 dx", "hexagonal", 0.0025, 1.3, 0.10),
    ("3D cubic, 3.9 cm deep (3d_floor_only)", "cubic", 0.003, 1.5, 0.039),
    ("3D fcc, 3.9 cm deep", "fcc", 0.003, 1.5, 0.039),
]


def main():
    for label, name, dx, hr, depth in CASES:
        basis = lattice(name, dx)
        w2, k, along = most_unstable(basis, hr * dx, RHO * G * depth, nk=32 if len(basis) == 2 else 12)
        if w2 < 0:
            kind = "shear" if along < 0.1 else "compression" if along > 0.9 else "mixed"
            print(f"{label:54s} grows at {np.sqrt(-w2):5.1f} /s, wavelength {2 * np.pi / np.linalg.norm(k) / dx:4.1f} dx, {kind}")
        else:
            print(f"{label:54s} stable (lowest omega^2 {w2:.3g} /s^2)")


if __name__ == "__main__":
    main()
