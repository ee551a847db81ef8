"""The weights of Romberg extrapolation, without numba: the compiled φ-mean of
:mod:`tumble.kernels.spinner` and the Python engine of :mod:`tumble.averaging.quadrature`
share them."""

from __future__ import annotations

import numpy as np

from tumble._typing import FloatArray

__all__ = ["romberg_weights"]


def romberg_weights(levels: int) -> FloatArray:
    """W with R(j, j) = Σ_i W[j, i] T_i: the diagonal of the Romberg table of T_0 … T_{L−1}.

    The recurrence R(j, m) = R(j, m−1) + (R(j, m−1) − R(j−1, m−1))/(4^m − 1), run on weight
    vectors (the rows of W sum to 1). Row j depends on j only, not on ``levels``.
    """
    rows = [np.eye(levels)[0]]
    weights = np.zeros((levels, levels))
    weights[0] = rows[0]
    for j in range(1, levels):
        fresh = [np.eye(levels)[j]]
        for m, coarse in enumerate(rows, start=1):
            fresh.append(fresh[-1] + (fresh[-1] - coarse) / (4.0**m - 1.0))
        weights[j], rows = fresh[-1], fresh
    return weights
