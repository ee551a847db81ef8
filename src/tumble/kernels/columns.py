"""The columns of an averaged run in the vector form ``[L_ξ1, L_ξ2, L_ξ3, r]``, r = 2T/L²,
compiled: one pass over the samples that holds no lock, so that the runs of an ensemble build
their columns on every core at once.

The reference is numpy: :func:`tumble.unperturbed.modulus_squared_of_ratio` for k² (the same
regimes, the same separatrix band and floor of the complementary modulus) and the rotating
field's σ taken within π of its initial value; a test holds them to round-off.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.codes import MC_FLOOR, SEPARATRIX_RTOL
from tumble.kernels.jit import ENTRY, INLINE, jit

__all__ = ["VECTOR_COLUMNS", "vector_columns"]

VECTOR_COLUMNS = ("L", "rho", "sigma", "T", "k2")
"""The columns of :func:`vector_columns`, in its order."""


@jit(INLINE)
def _within_pi(x: float, centre: float) -> float:
    """``x`` moved by whole turns to within π of ``centre``: centre + (mod(x − centre + π, 2π)
    − π), with Python's and numpy's modulo (the sign of the divisor)."""
    return centre + ((x - centre + math.pi) % (2.0 * math.pi) - math.pi)


@jit(INLINE)
def _modulus_squared(i1: float, i2: float, i3: float, r: float) -> float:
    """k² of the regime in which r = 2T/L² lies (sorted moments I1 < I2 < I3): 1 in the
    separatrix band or below the floor of the complementary modulus."""
    d1 = max(1.0 - r * i1, 0.0)
    d2 = 1.0 - r * i2
    d3 = max(r * i3 - 1.0, 0.0)
    if d2 > 0.0:  # about the axis of largest inertia
        den = (i3 - i2) * d1
        m = (i2 - i1) * d3 / den
    else:
        den = (i2 - i1) * d3
        m = (i3 - i2) * d1 / den
    mc = (i3 - i1) * abs(d2) / den
    if abs(d2) <= SEPARATRIX_RTOL or not mc >= MC_FLOOR:
        return 1.0
    if m != m:
        return m
    return min(max(m, 0.0), 1.0)


@jit(ENTRY)
def vector_columns(
    Y: FloatArray, i1: float, i2: float, i3: float, symmetric: bool, sigma0: float
) -> FloatArray:
    """L, ρ, σ, T and k² (:data:`VECTOR_COLUMNS`) of each row ``[L_ξ1, L_ξ2, L_ξ3, r]`` of
    ``Y``, shape (n, 5).

    Parameters
    ----------
    Y : ndarray, shape (n, 4)
        Averaged states: the angular momentum in inertial axes and r = 2T/L².
    i1, i2, i3 : float
        Principal moments, sorted.
    symmetric : bool
        Two equal moments (or three): k² carries no information, 0.
    sigma0 : float
        The initial azimuth of L [rad]: σ of a row on the ξ3 axis, and the centre within π of
        which every σ is taken (the averaged equations keep σ constant).
    """
    n = Y.shape[0]
    out = np.empty((n, 5))
    for i in range(n):
        l1, l2, l3, r = Y[i, 0], Y[i, 1], Y[i, 2], Y[i, 3]
        L = math.sqrt(l1 * l1 + l2 * l2 + l3 * l3)
        perp = math.hypot(l1, l2)
        out[i, 0] = L
        out[i, 1] = math.atan2(perp, l3)
        out[i, 2] = _within_pi(math.atan2(l2, l1), sigma0) if perp > 0.0 else sigma0
        out[i, 3] = 0.5 * r * L * L
        out[i, 4] = 0.0 if symmetric else _modulus_squared(i1, i2, i3, r)
    return out
