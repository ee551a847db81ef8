"""One DOP853 step, compiled: its stages, its error norm and the control of its size.

The error norm, the step-size controller and the starting step are scipy's ``DOP853`` ones
(which are Hairer's), so that the compiled integrator takes the same steps as scipy's; only
the averaged equations (a kind declared ``slow``) start with a longer first step.
Scalar loops are used instead of array expressions: every numpy function used in compiled code
is compiled too, and that is most of the first call's cost.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, cast

import numpy as np
from numba import types
from numba.extending import overload

from tumble._typing import FloatArray
from tumble.integrate.dop853.tableau import E3, E5, N_STAGES, N_STAGES_EXTENDED, A, B, C
from tumble.kernels.jit import INLINE, INNER, OVERLOAD, jit
from tumble.kernels.rhs import rhs

__all__ = [
    "attempt_step",
    "error_norm",
    "evaluate",
    "initial_step",
    "stages",
    "step_stages",
]

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0
_ERROR_EXPONENT = -1.0 / 8.0  # the error estimator is of order 7
_EPS = 2.220446049250313e-16  # machine epsilon of float64

STEP_OK = 0
STEP_TOO_SMALL = -1


@jit(INLINE)
def min_step(t: float) -> float:
    """The resolution of t (scipy: 10 ulp); below it a step cannot advance."""
    return 10.0 * _EPS * max(abs(t), 1e-290)


@jit(INNER)
def initial_step(
    rhs_fn: Any, p: FloatArray, t0: float, y0: FloatArray, f0: FloatArray, t1: float,
    rtol: float, atol: float, slow: bool,
) -> float:  # fmt: skip
    """Hairer's starting step (scipy's select_initial_step with the estimator's order 7);
    ``rhs_fn(t, y, p, out)`` is the right-hand side (:data:`~.functions.RHS`).

    With ``slow``, no shorter than Hairer's own first guess h0 = 0.01‖y‖/‖f‖, the time in which
    the state changes by 1 %. His final choice, (0.01/max(‖f‖, ‖f′‖))^(1/8) in the tolerance's
    units, takes every derivative to be of one size: true on the time scale of 1, but a system
    whose rates are of order ε has its k-th derivative of order ε^k, and there it starts at
    1e-5 to 1e-4 of the step the error allows (1e-5 of the slow time at ε = 1e-4, where the
    step allowed is about 0.4), which the controller's tenfold growth a step then takes four
    or five steps to undo.
    """
    n = y0.size
    d0 = d1 = 0.0
    for j in range(n):
        scale = atol + abs(y0[j]) * rtol
        d0 += (y0[j] / scale) ** 2
        d1 += (f0[j] / scale) ** 2
    d0, d1 = math.sqrt(d0 / n), math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, t1 - t0)
    y1 = np.empty(n)
    for j in range(n):
        y1[j] = y0[j] + h0 * f0[j]
    f1 = np.empty(n)
    rhs_fn(t0 + h0, y1, p, f1)
    d2 = 0.0
    for j in range(n):
        scale = atol + abs(y0[j]) * rtol
        d2 += ((f1[j] - f0[j]) / scale) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)  # error estimator of order 7
    h = min(100.0 * h0, h1, t1 - t0)
    return max(h, h0) if slow else h  # h0 ≤ t1 − t0 already


def evaluate(
    source: Any, t: float, y: FloatArray, p: FloatArray, out: FloatArray
) -> None:  # pragma: no cover - compiled only (the overload below)
    """dy/dt into ``out`` from ``source``: a kind (``KIND_*``, a compile-time constant), whose
    right-hand side is then compiled in, or a compiled right-hand side (:data:`~.functions.RHS`),
    which is then called."""
    raise NotImplementedError("compiled code only")


@overload(evaluate, prefer_literal=True, inline="always", jit_options=cast(Any, OVERLOAD))
def _evaluate(source: Any, t: Any, y: Any, p: Any, out: Any) -> Callable[..., None]:
    if isinstance(source, types.FunctionType):

        def called(source: Any, t: Any, y: Any, p: Any, out: Any) -> None:
            source(t, y, p, out)

        return called

    def inlined(source: Any, t: Any, y: Any, p: Any, out: Any) -> None:
        rhs(source, t, y, p, out)

    return inlined


@jit(INLINE)
def stages(
    source: Any, p: FloatArray, t: float, h: float, y: FloatArray, K: FloatArray,
    tmp: FloatArray, first: int, last: int,
) -> None:  # fmt: skip
    """Stages first … last − 1 of the step from (t, y) of size h into the rows of K, of the
    right-hand side ``source`` (:func:`evaluate`)."""
    for s in range(first, last):
        for j in range(y.size):
            acc = 0.0
            for k in range(s):
                acc += A[s, k] * K[k, j]
            tmp[j] = y[j] + h * acc
        evaluate(source, t + C[s] * h, tmp, p, K[s])


@jit(INLINE)
def error_norm(
    h_abs: float, y: FloatArray, y_new: FloatArray, K: FloatArray, rtol: float, atol: float
) -> float:
    """Hairer's combined 5th/3rd-order error estimate of the step, in units of the tolerance
    (NaN if a stage left the domain of the right-hand side)."""
    n = y.size
    e5 = 0.0
    e3 = 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        a5 = 0.0
        a3 = 0.0
        for k in range(N_STAGES + 1):
            a5 += E5[k] * K[k, j]
            a3 += E3[k] * K[k, j]
        e5 += (a5 / scale) ** 2
        e3 += (a3 / scale) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return h_abs * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@jit(INLINE)
def step_stages(
    source: Any, p: FloatArray, t: float, h: float, y: FloatArray, K: FloatArray,
    y_new: FloatArray, tmp: FloatArray, rtol: float, atol: float, extended: bool,
) -> float:  # fmt: skip
    """What a step of size h from (t, y), K[0] = f(t, y), asks of the right-hand side
    ``source`` (a kind or a compiled function, :func:`evaluate`): its stages 1 … 12 into K,
    the new state into ``y_new``, its derivative into K[12], and the step's
    :func:`error_norm` (returned); with ``extended``, the three extra stages of the
    interpolant instead (K[13:16]; returns 0).

    Each kind whose right-hand side is inlined compiles this once (:mod:`~.functions`); the
    stage counts are constants in both branches, so that the compiler unrolls the stages and
    drops the tableau's zeros. The kinds whose right-hand side is called share one.
    """
    if extended:
        stages(source, p, t, h, y, K, tmp, N_STAGES + 1, N_STAGES_EXTENDED)
        return 0.0
    stages(source, p, t, h, y, K, tmp, 1, N_STAGES)
    for j in range(y.size):
        acc = 0.0
        for k in range(N_STAGES):
            acc += B[k] * K[k, j]
        y_new[j] = y[j] + h * acc
    evaluate(source, t + h, y_new, p, K[N_STAGES])
    return error_norm(abs(h), y, y_new, K, rtol, atol)


@jit(INLINE)
def next_size(h_abs: float, err: float, rejected: bool) -> float:
    """The size of the next try after a step of size h_abs with error ``err``: grown (at
    most 10×, not at all right after a rejection) if it was accepted, shrunk if not."""
    if err < 1.0:
        factor = _MAX_FACTOR if err == 0.0 else min(_MAX_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
        if rejected:
            factor = min(1.0, factor)
        return h_abs * factor
    if err != err:  # NaN: a stage left the domain of the right-hand side
        return h_abs * _MIN_FACTOR
    return h_abs * max(_MIN_FACTOR, _SAFETY * err**_ERROR_EXPONENT)


@jit(INLINE)
def attempt_step(
    step_fn: Any, rhs_fn: Any, p: FloatArray, t: float, t1: float, h_abs: float, y: FloatArray,
    K: FloatArray, y_new: FloatArray, tmp: FloatArray, rtol: float, atol: float,
) -> tuple[int, float, float, int]:  # fmt: skip
    """Try steps from (t, y), K[0] = f(t, y), shrinking until one is accepted; ``step_fn``
    is the kind's compiled :func:`step_stages` (:mod:`~.functions`).

    Returns (status, h, the size to try next, evaluations); on success the new state is in
    ``y_new`` and the 13 stages in K. ``rhs_fn`` is the right-hand side, which ``step_fn``
    calls where it does not compile it in.
    """
    nfev = 0
    rejected = False
    lowest = min_step(t)
    h_abs = max(h_abs, lowest)
    while True:
        if not h_abs >= lowest:  # NaN too: an error estimate that is not a number
            return STEP_TOO_SMALL, 0.0, h_abs, nfev
        t_new = min(t + h_abs, t1)
        h = t_new - t
        h_abs = h
        err = step_fn(rhs_fn, p, t, h, y, K, y_new, tmp, rtol, atol, False)
        nfev += N_STAGES
        next_h = next_size(h_abs, err, rejected)
        if err < 1.0:
            return STEP_OK, h, next_h, nfev
        h_abs = next_h
        rejected = True
