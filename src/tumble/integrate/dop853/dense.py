"""The 7th-order continuous extension of a DOP853 step, compiled (scipy's
``Dop853DenseOutput``; Hairer, Nørsett & Wanner, §II.6)."""

from __future__ import annotations

from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.integrate.dop853.tableau import N_INTERPOLANT, N_STAGES, N_STAGES_EXTENDED, D
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit

__all__ = ["dense_coefficients", "evaluate_dense", "interpolate"]


@jit(KERNEL)
def dense_coefficients(
    step_fn: Any, rhs_fn: Any, p: FloatArray, t: float, h: float, y: FloatArray, y_new: FloatArray,
    K: FloatArray, F: FloatArray, tmp: FloatArray,
) -> None:  # fmt: skip
    """The interpolant's coefficient rows F (7, n) of the step (t, y) → (t + h, y_new); K holds
    the 13 stages of the step and receives the three extra ones (from ``step_fn``, the
    kind's compiled :func:`~.steps.step_stages`, given its right-hand side ``rhs_fn``)."""
    n = y.size
    step_fn(rhs_fn, p, t, h, y, K, y_new, tmp, 0.0, 0.0, True)
    for j in range(n):
        dy = y_new[j] - y[j]
        F[0, j] = dy
        F[1, j] = h * K[0, j] - dy
        F[2, j] = 2.0 * dy - h * (K[N_STAGES, j] + K[0, j])
        for r in range(N_INTERPOLANT - 3):
            acc = 0.0
            for k in range(N_STAGES_EXTENDED):
                acc += D[r, k] * K[k, j]
            F[3 + r, j] = h * acc


@jit(INLINE)
def interpolate(F: FloatArray, y: FloatArray, x: float, out: FloatArray) -> None:
    """The interpolant at the fraction ``x`` of a step that starts at ``y``."""
    for j in range(y.size):
        acc = 0.0
        for i in range(N_INTERPOLANT):
            acc += F[N_INTERPOLANT - 1 - i, j]
            acc *= x if i % 2 == 0 else 1.0 - x
        out[j] = acc + y[j]


@jit(ENTRY)
def evaluate_dense(ts: FloatArray, ys: FloatArray, F: FloatArray, t: FloatArray) -> FloatArray:
    """The dense output of recorded steps (times ``ts``, states ``ys``, interpolants ``F``) at
    the times ``t``, shape (m, n); a time outside the steps takes the nearest step's
    interpolant (extrapolated)."""
    m, n, last = t.size, ys.shape[1], F.shape[0] - 1
    out = np.empty((m, n))
    for q in range(m):
        i = min(max(np.searchsorted(ts, t[q], side="right") - 1, 0), last)
        interpolate(F[i], ys[i], (t[q] - ts[i]) / (ts[i + 1] - ts[i]), out[q])
    return out
