"""The Wendland C2 kernel of kernels/wendland_c2.hpp (support 2h) for the scripts:
W, dW/dr and d2W/dr2 at distances r (numbers or arrays), dimension D = 2 or 3."""
import numpy as np


def _sigma(h, D):
    return (7 / (4 * np.pi) if D == 2 else 21 / (16 * np.pi)) / h ** D


def W(r, h, D):
    q = r / h
    return np.where(q < 2, _sigma(h, D) * (1 - q / 2) ** 4 * (2 * q + 1), 0)


def dW(r, h, D):
    q = r / h
    return np.where(q < 2, _sigma(h, D) * (-5 * q * (1 - q / 2) ** 3) / h, 0)


def d2W(r, h, D):
    q = r / h
    t = 1 - q / 2
    return np.where(q < 2, _sigma(h, D) * (-5 * t ** 3 + 7.5 * q * t ** 2) / h ** 2, 0)
