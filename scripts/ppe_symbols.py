#!/usr/bin/python3
"""Lattice facts behind the PPE choices (docs/isph.md, docs/stability.md).

1. How far one density-invariance correction can overshoot on a regular lattice.

On a lattice of spacing dx (volume dx^D, Wendland C2), a Fourier mode k of the pressure
is scaled by the Morris Laplacian L with the symbol l(k) = -sum_m w(m) (1 - cos k.m), and
the divergence of the symmetric gradient D G (what moves the particles and changes their
summation density) by -|s(k)|^2, s(k) = sum_m sin(k.m) grad W(m). A correction with
gamma removes gamma |s|^2 / |l| of a density error of mode k in one step, so it
overshoots where gamma R(k) > 1 and grows where gamma R(k) > 2, R = |s|^2 / |l|. Prints
max R over the Brillouin zone for 2D and 3D and several h/dx.
2. What a flat free surface takes from the support of the layers below it, and how
much the same sums scatter on a jittered lattice (the invariance weight reads div r).
Usage: scripts/ppe_symbols.py"""
import numpy as np

from wendland import W, dW


def lattice(D, h):
    """Offsets (in dx) of the square lattice points around a particle, a spacing beyond
    the support radius 2h, the particle itself included (the middle row)."""
    reach = int(np.ceil(2 * h)) + 1
    axis = np.arange(-reach, reach + 1)
    return np.array(np.meshgrid(*[axis] * D, indexing="ij")).reshape(D, -1).T.astype(float)


for D, hs in ((2, (1.2, 1.3, 1.5, 1.6)), (3, (1.2, 1.5, 1.6))):
    for h in hs:
        m = lattice(D, h)
        r = np.linalg.norm(m, axis=1)
        m, r = m[r > 0], r[r > 0]
        grad = (dW(r, h, D) / r)[:, None] * m
        w = 2 * dW(r, h, D) * r / (r * r + 0.01 * h * h)
        ks = np.linspace(0, np.pi, 41 if D == 2 else 17)[1:]
        K = np.array(np.meshgrid(*[ks] * D, indexing="ij")).reshape(D, -1).T
        km = K @ m.T
        s2 = ((np.sin(km) @ grad) ** 2).sum(1)
        l = -(w[None, :] * (1 - np.cos(km))).sum(1)
        R = s2 / l
        i = np.argmax(R)
        print(f"{D}D h/dx = {h}: max |DG| / |L| = {R[i]:.3f} at k dx / pi = {np.round(K[i] / np.pi, 2)}")

# What a flat free surface takes from a lattice particle's support, `layer` rows below the
# top row: the summation density (Shepard sum), the position divergence div r and the sum
# of Morris weights (the PPE diagonal), as fractions of the interior values; and how much
# these three scatter in the interior of a lattice jittered by +-0.1 dx per axis.
print()
for D in (2, 3):
    h = 1.5
    m = lattice(D, h)

    def sums(p):
        r = np.linalg.norm(p, axis=1)
        div_r = -dW(r, h, D) * r
        lap = np.where(r > 0, -2 * dW(r, h, D) * r / (r * r + 0.01 * h * h), 0)
        return np.array([W(r, h, D).sum(), div_r.sum(), lap.sum()])

    full = sums(m)
    for layer in (0, 1):
        d = 1 - sums(m[m[:, -1] <= layer]) / full
        print(f"{D}D h/dx = {h}, layer {layer} below the surface: deficit of <rho> {100 * d[0]:.2f} %, "
              f"div r {100 * d[1]:.2f} %, Morris diagonal {100 * d[2]:.2f} %")
    rng = np.random.default_rng(1)
    centre = len(m) // 2
    scatter = []
    for _ in range(400):
        p = m + rng.uniform(-0.1, 0.1, m.shape)
        scatter.append(1 - sums(p - p[centre]) / full)
    sd = 100 * np.std(scatter, axis=0)
    print(f"{D}D jitter 0.1 dx, interior scatter (std): <rho> {sd[0]:.2f} %, div r {sd[1]:.2f} %, "
          f"Morris diagonal {sd[2]:.2f} %")

# 3. The truncation t = |sum_j V grad W_ij| / g_face that weights the density-invariance
# term (solvers/isph/roles.hpp): by layer below a flat surface, and how it scatters on a
# jittered lattice (+-0.1 and +-0.25 dx per axis) where the support is full.
print()
for D in (2, 3):
    h = 1.5
    m = lattice(D, h)

    def cut(p):  # |sum_j grad W(x_i - x_j)| for x_i at the origin, x_j = p
        r = np.linalg.norm(p, axis=1)
        g = np.where(r > 0, dW(r, h, D) / np.where(r > 0, r, 1), 0)[:, None] * (-p)
        return np.linalg.norm(g.sum(0))

    face = cut(m[m[:, -1] <= 0])
    layers = [cut(m[m[:, -1] <= layer]) / face for layer in (0, 1, 2)]
    print(f"{D}D h/dx = {h}, truncation by layer below the surface: "
          + ", ".join(f"{t:.3f}" for t in layers))
    rng = np.random.default_rng(1)
    centre = len(m) // 2
    for jitter in (0.1, 0.25):
        t = []
        for _ in range(400):
            p = m + rng.uniform(-jitter, jitter, m.shape)
            t.append(cut(p - p[centre]) / face)
        print(f"{D}D jitter {jitter} dx, full support: truncation median {np.median(t):.3f}, "
              f"p95 {np.percentile(t, 95):.3f}, max {np.max(t):.3f}")
