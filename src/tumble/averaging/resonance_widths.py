"""How far the phases of a fast system are from a resonance, in units of its width.

For the standard form of :mod:`tumble.averaging.second_order` (slow x, fast phases φ on a
d-torus with frequencies ν(x)), a harmonic k of the slow rates resonates where k·ν = 0. The
mean drift carries the solution through such a resonance and the harmonic itself drives the
combination k·φ like a pendulum; within a few widths of it the averaged equations of order 2
and their generator no longer hold. :func:`resonance_table` measures the distance of every
harmonic present, :func:`nearest_resonance` picks the nearest.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.fourier import _waves
from tumble.averaging.generator import RESONANT_FLOOR

__all__ = ["RESONANCE_WIDTHS", "nearest_resonance", "resonance_distance", "resonance_table"]


RESONANCE_WIDTHS = 3.0
"""A mean state closer than this many widths to a resonance is refused by a run of order 2
(and handed to the full equations by a hybrid one): there the generator, of the size
|f̂_k|/|k·ν| ≳ √ε/RESONANCE_WIDTHS, no longer makes a small correction."""


def resonance_table(
    f: FloatArray, nu: FloatArray, nu_jacobian: FloatArray, drift: FloatArray
) -> dict[tuple[int, ...], float]:
    """The signed distance of each harmonic of the slow rates from its resonance, in units of
    its width.

    The combination θ = k·φ of a harmonic k of the slow rates (coefficient f̂_k) turns at
    k·ν, which changes at the rate (k·∂ν/∂x)·(F₁ + f̂_k e^{iθ}): the mean drift carries the
    solution through the resonance k·ν = 0, and the harmonic itself drives θ like a pendulum.
    Both give the resonance the width w_k = √(|(k·∂ν/∂x)·F₁| + |(k·∂ν/∂x)·f̂_k|) in k·ν:
    within a few widths the phase no longer turns many times while k·ν changes (the
    adiabatic condition |k·ν|² ≫ |d(k·ν)/dt| fails), the solution passes with an O(√ε) jump
    or is captured, and the generator's terms f̂_k/(k·ν) stop being small.

    Parameters
    ----------
    f : ndarray, shape (m, *grid)
        The slow rates on the grid.
    nu : ndarray, shape (d,)
        ν.
    nu_jacobian : ndarray, shape (d, m)
        ∂ν/∂x.
    drift : ndarray, shape (m,)
        F₁.

    Returns
    -------
    dict
        k·ν/w_k for each harmonic k above ``RESONANT_FLOOR`` of the largest that can resonate
        (k·∂ν/∂x ≠ 0), one of each pair ±k (the one whose first non-zero entry is positive).
        Its sign tells on which side of the resonance the state is, so that a step of an
        integrator that jumps a whole band is seen by the sign's change.
    """
    shape = f.shape[1:]
    d = len(shape)
    if d == 1:
        return _one_phase_table(f, float(nu[0]), nu_jacobian[0], drift)
    coef = np.fft.fftn(f, axes=tuple(range(1, d + 1))) / math.prod(shape)
    waves = _waves(shape)
    k_nu = sum(w * n for w, n in zip(waves, nu, strict=True))
    # k·∂ν/∂x, shape (m, *grid)
    k_jac = sum(w[None] * np.reshape(row, (-1, *([1] * d)))
                for w, row in zip(waves, nu_jacobian, strict=True))  # fmt: skip
    width2 = np.abs(np.tensordot(drift, k_jac, axes=(0, 0)))
    width2 = width2 + np.abs(np.sum(k_jac * coef, axis=0))
    size = np.abs(coef).max(axis=0)
    present = size > RESONANT_FLOOR * float(size.max())
    present &= width2 > 0.0
    table: dict[tuple[int, ...], float] = {}
    full = [np.broadcast_to(w, shape) for w in waves]
    for at in zip(*np.nonzero(present), strict=True):
        k = tuple(int(w[at]) for w in full)
        leading = next((c for c in k if c != 0), 0)
        if leading > 0:  # k = 0 has no width; of ±k the one leading with a positive entry
            table[k] = float(k_nu[at] / math.sqrt(float(width2[at])))
    return table


def _one_phase_table(
    f: FloatArray, nu: float, nu_gradient: FloatArray, drift: FloatArray
) -> dict[tuple[int, ...], float]:
    """:func:`resonance_table` on a one-phase grid, from the real transform's half k ≥ 0 (the
    coefficient of −k is the conjugate of k's): the same harmonics 0 < k < n/2, the same
    distances."""
    n = f.shape[1]
    coef = np.fft.rfft(f, axis=1) / n
    k = np.arange(coef.shape[1], dtype=float)
    k_jac = np.outer(nu_gradient, k)  # k ∂ν/∂x, (m, harmonics)
    width2 = np.abs(drift @ k_jac) + np.abs(np.sum(k_jac * coef, axis=0))
    size = np.abs(coef).max(axis=0)
    present = (size > RESONANT_FLOOR * float(size.max())) & (width2 > 0.0) & (k > 0) & (2 * k < n)
    return {(int(h),): float(h * nu / math.sqrt(float(width2[h])))
            for h in np.flatnonzero(present)}  # fmt: skip


def resonance_distance(
    f: FloatArray, nu: FloatArray, nu_jacobian: FloatArray, drift: FloatArray
) -> tuple[float, tuple[int, ...]]:
    """How far the phases are from their nearest resonance, in units of its width: the least
    |k·ν|/w_k of :func:`resonance_table`, and that k.

    Returns
    -------
    distance : float
        inf where no harmonic present can resonate (k·∂ν/∂x = 0 for all of them).
    harmonic : tuple of int
        The nearest resonance's k.
    """
    return nearest_resonance(resonance_table(f, nu, nu_jacobian, drift))


def nearest_resonance(table: dict[tuple[int, ...], float]) -> tuple[float, tuple[int, ...]]:
    """The least |distance| of a :func:`resonance_table` and its harmonic (inf, () if
    empty)."""
    if not table:
        return math.inf, ()
    k = min(table, key=lambda h: abs(table[h]))
    return abs(table[k]), k
