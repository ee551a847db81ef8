"""Compiled integration: DOP853 with dense output and events, and the right-hand sides it
integrates, as numba kernels.

The integrator is the Dormand–Prince 8(5,3) method with its 7th-order continuous extension
(Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5–II.6), with the coefficients, error norm,
step-size controller and initial step of scipy's ``DOP853``. The two therefore take the same
steps, and scipy's solver (with the models' Python right-hand sides) is the reference the
compiled path is tested against (``integrator = "scipy"``).

The right-hand sides are chosen by an integer ``kind`` and read their parameters from one float
array, so that one compiled integrator serves every model and is cached on disk
(``cache=True``): only the first run after installation compiles. They all live in this one
module on purpose: numba checks a cached function against its own source file only, so a
kernel kept in another file could change without the integrator being recompiled.

Kinds
-----
``KIND_RIGID_BODY``
    Euler's equations with quaternion kinematics under a sum of built-in torques (the free
    body, the resisting-medium moment (1.2) of seed 000, the eddy-current moment (1.3) of seed
    002, and the torques of the averaging engine). State ``[ω, q]``.
``KIND_ROTATING_FIELD``
    The rotating-field form (1.5) of seed 002, state ``[z, Γ by rows]``.
``KIND_NONLINEAR_MOMENT``
    Euler's equations (1.1) of seed 003 with quaternions, under the moment of spec/serov.md §9.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop853

from tumble._typing import FloatArray
from tumble.errors import ParameterError
from tumble.torques import (
    TERM_BODY_CONSTANT,
    TERM_EDDY_CURRENT,
    TERM_GRAVITY_GRADIENT,
    TERM_INERTIAL_CONSTANT,
    TERM_LINEAR_DRAG,
    TERM_QUADRATIC_DRAG,
    Torque,
)

__all__ = [
    "EVENT_NONE",
    "EVENT_THETA_DOT",
    "KIND_NONLINEAR_MOMENT",
    "KIND_RIGID_BODY",
    "KIND_ROTATING_FIELD",
    "BatchResult",
    "CompiledSolution",
    "Kernel",
    "evaluate_rhs",
    "rigid_body_kernel",
    "solve",
    "solve_batch",
    "solve_many",
    "torque_program",
]

KIND_RIGID_BODY = 1
KIND_ROTATING_FIELD = 2
KIND_NONLINEAR_MOMENT = 3

EVENT_NONE = 0
EVENT_THETA_DOT = 1
"""Zeros of θ' of the nonlinear-moment quaternion form: the extrema of θ(t)."""

# Status codes of the compiled integrator.
_OK = 0
_STEP_TOO_SMALL = -1
_NOT_FINITE = -2

# Tableau of DOP853 (scipy's copy of Hairer's coefficients), frozen into the compiled code.
_NS = _dop853.N_STAGES  # 12 stages; the 13th evaluation is the FSAL derivative
_NX = _dop853.N_STAGES_EXTENDED  # 16 with the three stages of the dense output
_NP = _dop853.INTERPOLATOR_POWER  # 7 coefficient rows of the interpolant
_A = np.ascontiguousarray(_dop853.A, dtype=np.float64)
_B = np.ascontiguousarray(_dop853.B, dtype=np.float64)
_C = np.ascontiguousarray(_dop853.C, dtype=np.float64)
_E3 = np.ascontiguousarray(_dop853.E3, dtype=np.float64)
_E5 = np.ascontiguousarray(_dop853.E5, dtype=np.float64)
_D = np.ascontiguousarray(_dop853.D, dtype=np.float64)
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0
_ERROR_EXPONENT = -1.0 / 8.0  # the error estimator is of order 7

# Reassociation and contraction (FMA) only: no "nnan"/"ninf", so the checks for non-finite
# states survive optimization.
_FAST = {"contract", "reassoc", "nsz", "arcp"}
# numpy's error model: a division by zero gives inf or NaN (caught as a non-finite state)
# instead of raising from compiled code, and compiles to less code.
_JIT: dict[str, Any] = {"cache": True, "fastmath": _FAST, "nogil": True, "error_model": "numpy"}
# Helpers only compiled code calls: no Python wrapper to build (a large part of the cost of
# compiling a small function).
_INNER: dict[str, Any] = {**_JIT, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}
# The integrator is called from Python only: no C callback wrapper either.
_ENTRY: dict[str, Any] = {**_JIT, "no_cfunc_wrapper": True}
# Kernels allocate nothing: without reference counting, calls to them cost less.
_KERNEL: dict[str, Any] = {**_INNER, "_nrt": False}
# Small kernels LLVM must inline into the integrator's loops (alwaysinline): the right-hand
# side's dispatch on the kind then folds away in a specialisation of `_solve` on one kind.
_INLINE: dict[str, Any] = {**_KERNEL, "forceinline": True}


# ---------------------------------------------------------------------------------------------
# Right-hand sides.


@numba.njit(**_KERNEL)
def _torque(prog: FloatArray, start: int, t: float, y: FloatArray, out: FloatArray) -> None:
    """Body moment of the torque program ``prog[start:]`` at state ``y = [ω, q]`` into out."""
    n_terms = int(prog[start])
    if n_terms == 0:
        out[0] = out[1] = out[2] = 0.0
        return
    w1, w2, w3 = y[0], y[1], y[2]
    norm = math.sqrt(y[3] * y[3] + y[4] * y[4] + y[5] * y[5] + y[6] * y[6])
    q0, q1, q2, q3 = y[3] / norm, y[4] / norm, y[5] / norm, y[6] / norm
    # Body → inertial matrix A of the unit quaternion (tumble.rotations.quat_to_matrix).
    a00 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    a01 = 2.0 * (q1 * q2 - q0 * q3)
    a02 = 2.0 * (q1 * q3 + q0 * q2)
    a10 = 2.0 * (q1 * q2 + q0 * q3)
    a11 = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    a12 = 2.0 * (q2 * q3 - q0 * q1)
    a20 = 2.0 * (q1 * q3 - q0 * q2)
    a21 = 2.0 * (q2 * q3 + q0 * q1)
    a22 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    m1 = m2 = m3 = 0.0
    i = start + 1
    for _ in range(n_terms):
        code = int(prog[i])
        f = prog[i + 1]
        v = i + 2
        if code == TERM_BODY_CONSTANT:
            m1 += f * prog[v]
            m2 += f * prog[v + 1]
            m3 += f * prog[v + 2]
            i = v + 3
        elif code == TERM_LINEAR_DRAG:
            m1 -= f * (prog[v] * w1 + prog[v + 1] * w2 + prog[v + 2] * w3)
            m2 -= f * (prog[v + 3] * w1 + prog[v + 4] * w2 + prog[v + 5] * w3)
            m3 -= f * (prog[v + 6] * w1 + prog[v + 7] * w2 + prog[v + 8] * w3)
            i = v + 9
        elif code == TERM_QUADRATIC_DRAG:
            u1, u2, u3 = w1 * abs(w1), w2 * abs(w2), w3 * abs(w3)
            m1 -= f * (prog[v] * u1 + prog[v + 1] * u2 + prog[v + 2] * u3)
            m2 -= f * (prog[v + 3] * u1 + prog[v + 4] * u2 + prog[v + 5] * u3)
            m3 -= f * (prog[v + 6] * u1 + prog[v + 7] * u2 + prog[v + 8] * u3)
            i = v + 9
        elif code == TERM_INERTIAL_CONSTANT:
            x1, x2, x3 = prog[v], prog[v + 1], prog[v + 2]
            m1 += f * (a00 * x1 + a10 * x2 + a20 * x3)
            m2 += f * (a01 * x1 + a11 * x2 + a21 * x3)
            m3 += f * (a02 * x1 + a12 * x2 + a22 * x3)
            i = v + 3
        elif code == TERM_GRAVITY_GRADIENT:
            i1, i2, i3 = prog[v], prog[v + 1], prog[v + 2]
            n, u0 = prog[v + 3], prog[v + 4]
            cu, su = math.cos(n * t + u0), math.sin(n * t + u0)
            # r̂ = cos u e1 + sin u e2 (inertial), then body components Aᵀ r̂.
            x1 = cu * prog[v + 5] + su * prog[v + 8]
            x2 = cu * prog[v + 6] + su * prog[v + 9]
            x3 = cu * prog[v + 7] + su * prog[v + 10]
            r1 = a00 * x1 + a10 * x2 + a20 * x3
            r2 = a01 * x1 + a11 * x2 + a21 * x3
            r3 = a02 * x1 + a12 * x2 + a22 * x3
            g = 3.0 * n * n * f
            m1 += g * (i3 - i2) * r2 * r3
            m2 += g * (i1 - i3) * r3 * r1
            m3 += g * (i2 - i1) * r1 * r2
            i = v + 14
        elif code == TERM_EDDY_CURRENT:
            M0, rate, beta = prog[v], prog[v + 1], prog[v + 2]
            sb, cb = math.sin(beta), math.cos(beta)
            h1, h2, h3 = sb * math.cos(rate * t), sb * math.sin(rate * t), cb
            # Inertial angular velocity relative to the field, A ω − Ω ξ3.
            x1 = a00 * w1 + a01 * w2 + a02 * w3
            x2 = a10 * w1 + a11 * w2 + a12 * w3
            x3 = a20 * w1 + a21 * w2 + a22 * w3 - rate
            hw = h1 * x1 + h2 * x2 + h3 * x3
            x1, x2, x3 = h1 * hw - x1, h2 * hw - x2, h3 * hw - x3
            g = f * M0
            m1 += g * (a00 * x1 + a10 * x2 + a20 * x3)
            m2 += g * (a01 * x1 + a11 * x2 + a21 * x3)
            m3 += g * (a02 * x1 + a12 * x2 + a22 * x3)
            i = v + 3
        else:
            # An unknown code cannot come from torque_program(); poison the state so the
            # integration fails loudly instead of ignoring the term.
            m1 = m2 = m3 = math.nan
            break
    out[0], out[1], out[2] = m1, m2, m3


@numba.njit(**_INLINE)
def _quaternion_rates(y: FloatArray, out: FloatArray) -> None:
    """dq/dt = ½ q ⊗ (0, ω) into out[3:7] for y = [ω, q]."""
    w1, w2, w3, q0, q1, q2, q3 = y[0], y[1], y[2], y[3], y[4], y[5], y[6]
    out[3] = 0.5 * (-q1 * w1 - q2 * w2 - q3 * w3)
    out[4] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
    out[5] = 0.5 * (q0 * w2 - q1 * w3 + q3 * w1)
    out[6] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)


@numba.njit(**_KERNEL)
def _pressure(p: FloatArray, tau: float) -> float:
    """Q(τ)/Q(0) of the nonlinear-moment parameters (constant, exponential or a table)."""
    kind = int(p[6])
    if kind == 0:
        return 1.0
    if kind == 1:
        return math.exp(tau) / p[7]
    # A table: piecewise-linear between the knots (the run was checked to stay inside).
    n = int(p[8])
    lo, hi = 0, n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[9 + mid] <= tau:
            lo = mid
        else:
            hi = mid
    x0, x1 = p[9 + lo], p[9 + hi]
    v0, v1 = p[9 + n + lo], p[9 + n + hi]
    return (v0 + (v1 - v0) * (tau - x0) / (x1 - x0)) / p[7]


@numba.njit(**_INLINE)
def _rhs(kind: int, t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """dy/dt of the right-hand side ``kind`` with parameters ``p`` into ``out``."""
    if kind == KIND_RIGID_BODY:
        # p = [I1, I2, I3, torque program]
        i1, i2, i3 = p[0], p[1], p[2]
        w1, w2, w3 = y[0], y[1], y[2]
        _torque(p, 3, t, y, out)
        out[0] = ((i2 - i3) * w2 * w3 + out[0]) / i1
        out[1] = ((i3 - i1) * w3 * w1 + out[1]) / i2
        out[2] = ((i1 - i2) * w1 * w2 + out[2]) / i3
        _quaternion_rates(y, out)
    elif kind == KIND_ROTATING_FIELD:
        # p = [I1, I2, I3, ε, ĥĥ by rows]; y = [z, Γ by rows]; (1.5) with erratum 3:
        # I z′ = I z × z + ε Γᵀ ĥĥ (Γ z − ξ3), Γ′ = Γ ẑ − ξ̂3 Γ.
        i1, i2, i3, eps = p[0], p[1], p[2], p[3]
        z1, z2, z3 = y[0], y[1], y[2]
        g = y[3:12]
        r1 = g[0] * z1 + g[1] * z2 + g[2] * z3
        r2 = g[3] * z1 + g[4] * z2 + g[5] * z3
        r3 = g[6] * z1 + g[7] * z2 + g[8] * z3 - 1.0
        e1 = p[4] * r1 + p[5] * r2 + p[6] * r3
        e2 = p[7] * r1 + p[8] * r2 + p[9] * r3
        e3 = p[10] * r1 + p[11] * r2 + p[12] * r3
        out[0] = ((i2 - i3) * z2 * z3 + eps * (g[0] * e1 + g[3] * e2 + g[6] * e3)) / i1
        out[1] = ((i3 - i1) * z3 * z1 + eps * (g[1] * e1 + g[4] * e2 + g[7] * e3)) / i2
        out[2] = ((i1 - i2) * z1 * z2 + eps * (g[2] * e1 + g[5] * e2 + g[8] * e3)) / i3
        # Γ ẑ: row r of Γ times the cross-product matrix of z.
        for r in range(3):
            a, b, c = g[3 * r], g[3 * r + 1], g[3 * r + 2]
            out[3 + 3 * r] = b * z3 - c * z2
            out[4 + 3 * r] = c * z1 - a * z3
            out[5 + 3 * r] = a * z2 - b * z1
        # − ξ̂3 Γ: rows (Γ2, −Γ1, 0).
        for col in range(3):
            out[3 + col] += g[3 + col]
            out[6 + col] -= g[col]
    elif kind == KIND_NONLINEAR_MOMENT:
        # p = [μ, a0, b0, ε, d, ν, pressure kind, Q(0), table size n, τ_1..n, Q_1..n].
        mu, eps = p[0], p[3]
        q = _pressure(p, eps * t)
        a, b = p[1] * q, p[2] * q
        w1, w2, w3 = y[0], y[1], y[2]
        q0, q1, q2, q3 = y[3], y[4], y[5], y[6]
        n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
        # e_z in body axes: the third row of the body → inertial matrix.
        ex = 2.0 * (q1 * q3 - q0 * q2) / n2
        ey = 2.0 * (q2 * q3 + q0 * q1) / n2
        ez = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / n2
        m0 = a + 2.0 * b * ez
        ed, en = eps * p[4], eps * p[5]
        out[0] = (1.0 - mu) * w2 * w3 + m0 * ey - ed * w1
        out[1] = (mu - 1.0) * w3 * w1 - m0 * ex - ed * w2
        out[2] = -en * w3
        _quaternion_rates(y, out)
    else:
        for j in range(y.size):
            out[j] = math.nan


@numba.njit(**_INLINE)
def _event(event: int, t: float, y: FloatArray, p: FloatArray) -> float:
    """The event function ``event`` at (t, y); its sign changes are located."""
    if event == EVENT_THETA_DOT:
        # θ' sinθ = ω·(e_z × e3) (nonlinear-moment quaternion form): the sign of θ'.
        q0, q1, q2, q3 = y[3], y[4], y[5], y[6]
        n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
        ex = 2.0 * (q1 * q3 - q0 * q2) / n2
        ey = 2.0 * (q2 * q3 + q0 * q1) / n2
        return y[0] * ey - y[1] * ex
    return 1.0


# ---------------------------------------------------------------------------------------------
# DOP853.


@numba.njit(**_INNER)
def _initial_step(
    kind: int, p: FloatArray, t0: float, y0: FloatArray, f0: FloatArray, t1: float,
    rtol: float, atol: float,
) -> float:  # fmt: skip
    """Hairer's starting step (scipy's select_initial_step with the estimator's order 7)."""
    # Scalar loops instead of array expressions throughout this module: every numpy
    # function used here is compiled too, and that is most of the first call's cost.
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
    _rhs(kind, t0 + h0, y1, p, f1)
    d2 = 0.0
    for j in range(n):
        scale = atol + abs(y0[j]) * rtol
        d2 += ((f1[j] - f0[j]) / scale) ** 2
    d2 = math.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)  # error estimator of order 7
    return min(100.0 * h0, h1, t1 - t0)


@numba.njit(**_KERNEL)
def _stages(
    kind: int, p: FloatArray, t: float, h: float, y: FloatArray, K: FloatArray,
    tmp: FloatArray, first: int, last: int,
) -> None:  # fmt: skip
    """Stages first … last − 1 of the step from (t, y) of size h into the rows of K."""
    for s in range(first, last):
        for j in range(y.size):
            acc = 0.0
            for k in range(s):
                acc += _A[s, k] * K[k, j]
            tmp[j] = y[j] + h * acc
        _rhs(kind, t + _C[s] * h, tmp, p, K[s])


@numba.njit(**_KERNEL)
def _dense(
    kind: int, p: FloatArray, t: float, h: float, y: FloatArray, y_new: FloatArray,
    K: FloatArray, F: FloatArray, tmp: FloatArray,
) -> None:  # fmt: skip
    """The interpolant's coefficient rows F (7, n) of the step (t, y) → (t + h, y_new); K holds
    the 13 stages of the step and receives the three extra ones."""
    n = y.size
    _stages(kind, p, t, h, y, K, tmp, _NS + 1, _NX)
    for j in range(n):
        dy = y_new[j] - y[j]
        F[0, j] = dy
        F[1, j] = h * K[0, j] - dy
        F[2, j] = 2.0 * dy - h * (K[_NS, j] + K[0, j])
        for r in range(_NP - 3):
            acc = 0.0
            for k in range(_NX):
                acc += _D[r, k] * K[k, j]
            F[3 + r, j] = h * acc


@numba.njit(**_INLINE)
def _interpolate(F: FloatArray, y: FloatArray, x: float, out: FloatArray) -> None:
    """The interpolant at the fraction ``x`` of a step that starts at ``y`` (scipy's
    Dop853DenseOutput)."""
    for j in range(y.size):
        acc = 0.0
        for i in range(_NP):
            acc += F[_NP - 1 - i, j]
            acc *= x if i % 2 == 0 else 1.0 - x
        out[j] = acc + y[j]


@numba.njit(**_INNER)
def _grow(a: FloatArray) -> FloatArray:
    """``a`` with twice the size, its values first."""
    b = np.empty(2 * a.size)
    for i in range(a.size):
        b[i] = a[i]
    return b


@numba.njit(**_INNER)
def _event_root(
    event: int, p: FloatArray, t: float, h: float, y: FloatArray, F: FloatArray,
    xa: float, ga: float, xb: float, gb: float, out: FloatArray,
) -> float:  # fmt: skip
    """Fraction x in [xa, xb] of the step where the event function changes sign (Illinois
    variant of regula falsi on the interpolant, to a few ulps of t)."""
    side = 0
    x = xb
    for _ in range(200):
        x = (xa * gb - xb * ga) / (gb - ga)
        if not xa < x < xb:
            x = 0.5 * (xa + xb)
        _interpolate(F, y, x, out)
        g = _event(event, t + x * h, out, p)
        if g == 0.0:
            return x
        if (g > 0.0) == (gb > 0.0):
            xb, gb = x, g
            if side == 1:
                ga *= 0.5
            side = 1
        else:
            xa, ga = x, g
            if side == -1:
                gb *= 0.5
            side = -1
        if (xb - xa) * abs(h) <= 4.0 * 2.220446049250313e-16 * max(1.0, abs(t)):
            break
    return x


@numba.njit(**_INLINE)
def _copy(src: FloatArray, dst: FloatArray, at: int) -> None:
    """dst[at : at + src.size] = src."""
    for j in range(src.size):
        dst[at + j] = src[j]


@numba.njit(**_ENTRY)
def _solve(
    kind: int, p: FloatArray, y0: FloatArray, t0: float, t1: float, rtol: float, atol: float,
    first_step: float, t_eval: FloatArray, record: bool, dense: bool, event: int,
):  # fmt: skip
    """Integrate from t0 to t1 with DOP853.

    Returns (status, t, y, nfev, h, n_steps, ts, ys, F, y_eval, ev_t, ev_s, ev_y, n_ev): the
    event times, the sign of the event function before each, and the states there. The step
    times ``ts`` and states ``ys`` (and the interpolants ``F`` when ``dense``) are kept when
    ``record``; arrays are flat buffers, cut and reshaped by the caller.
    """
    n = y0.size
    cap = 1024 if record else 1
    ts = np.empty(cap)
    ys = np.empty(cap * n)
    Fs = np.empty((cap if dense else 1) * _NP * n)
    ev_t = np.empty(16)
    ev_s = np.empty(16)
    ev_y = np.empty(16 * n)
    n_ev = 0
    m = t_eval.size
    y_eval = np.empty(m * n)
    for j in range(m * n):
        y_eval[j] = math.nan
    ie = 0
    K = np.empty((_NX, n))
    F = np.empty((_NP, n))
    y = np.empty(n)
    for j in range(n):
        y[j] = y0[j]
    y_new = np.empty(n)
    tmp = np.empty(n)
    t = t0
    ts[0] = t
    for j in range(n):
        ys[j] = y0[j]
    n_steps = 0
    while ie < m and t_eval[ie] <= t0:
        _copy(y0, y_eval, ie * n)
        ie += 1
    _rhs(kind, t, y, p, K[0])
    nfev = 1
    status = _OK
    h = 0.0
    if t1 > t0:
        if first_step > 0.0:
            h_abs = min(first_step, t1 - t0)
        else:
            h_abs = _initial_step(kind, p, t, y, K[0], t1, rtol, atol)
            nfev += 1
    else:
        h_abs = 0.0
    g_old = _event(event, t, y, p) if event != EVENT_NONE else 1.0
    while t < t1:
        # The resolution of t (scipy: 10 ulp); below it the step cannot advance.
        min_step = 10.0 * 2.220446049250313e-16 * max(abs(t), 1e-290)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                status = _STEP_TOO_SMALL
                break
            t_new = t + h_abs
            if t_new > t1:
                t_new = t1
            h = t_new - t
            h_abs = h
            _stages(kind, p, t, h, y, K, tmp, 1, _NS)
            for j in range(n):
                acc = 0.0
                for k in range(_NS):
                    acc += _B[k] * K[k, j]
                y_new[j] = y[j] + h * acc
            _rhs(kind, t + h, y_new, p, K[_NS])
            nfev += _NS
            e5 = 0.0
            e3 = 0.0
            for j in range(n):
                scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
                a5 = 0.0
                a3 = 0.0
                for k in range(_NS + 1):
                    a5 += _E5[k] * K[k, j]
                    a3 += _E3[k] * K[k, j]
                e5 += (a5 / scale) ** 2
                e3 += (a3 / scale) ** 2
            if e5 == 0.0 and e3 == 0.0:
                err = 0.0
            else:
                err = h_abs * e5 / math.sqrt((e5 + 0.01 * e3) * n)
            if err < 1.0:
                if err == 0.0:
                    factor = _MAX_FACTOR
                else:
                    factor = min(_MAX_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            if err != err:  # NaN: a stage left the domain of the right-hand side
                h_abs *= _MIN_FACTOR
            else:
                h_abs *= max(_MIN_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
            rejected = True
        if status != _OK:
            break
        finite = True
        for j in range(n):
            if not math.isfinite(y_new[j]):
                finite = False
        if not finite:
            status = _NOT_FINITE
            break
        # The step t → t_new is accepted.
        if dense or event != EVENT_NONE or (ie < m and t_eval[ie] <= t_new):
            _dense(kind, p, t, h, y, y_new, K, F, tmp)
            nfev += _NX - _NS - 1
        while ie < m and t_eval[ie] <= t_new:
            if t_eval[ie] == t_new:
                _copy(y_new, y_eval, ie * n)
            else:
                _interpolate(F, y, (t_eval[ie] - t) / h, tmp)
                _copy(tmp, y_eval, ie * n)
            ie += 1
        if event != EVENT_NONE:
            # Sign changes on the step, sampled at quarters so that no swing is missed.
            xa, ga = 0.0, g_old
            for quarter in range(1, 5):
                xb = 0.25 * quarter
                if quarter == 4:
                    gb = _event(event, t_new, y_new, p)
                else:
                    _interpolate(F, y, xb, tmp)
                    gb = _event(event, t + xb * h, tmp, p)
                if (ga < 0.0 < gb) or (gb < 0.0 < ga):
                    x = _event_root(event, p, t, h, y, F, xa, ga, xb, gb, tmp)
                    if n_ev == ev_t.size:
                        ev_t = _grow(ev_t)
                        ev_s = _grow(ev_s)
                        ev_y = _grow(ev_y)
                    ev_t[n_ev] = t + x * h
                    ev_s[n_ev] = 1.0 if ga > 0.0 else -1.0
                    _interpolate(F, y, x, tmp)
                    _copy(tmp, ev_y, n_ev * n)
                    n_ev += 1
                if gb != 0.0:
                    xa, ga = xb, gb
            g_old = ga
        if record:
            if n_steps + 1 == ts.size:
                ts = _grow(ts)
                ys = _grow(ys)
            if dense:
                if (n_steps + 1) * _NP * n > Fs.size:
                    Fs = _grow(Fs)
                for r in range(_NP):
                    _copy(F[r], Fs, (n_steps * _NP + r) * n)
            ts[n_steps + 1] = t_new
            _copy(y_new, ys, (n_steps + 1) * n)
        n_steps += 1
        t = t_new
        for j in range(n):
            y[j] = y_new[j]
            K[0, j] = K[_NS, j]
    return status, t, y, nfev, h, n_steps, ts, ys, Fs, y_eval, ev_t, ev_s, ev_y, n_ev


@numba.njit(**_JIT)
def _evaluate(kind: int, t: float, y: FloatArray, p: FloatArray) -> FloatArray:
    out = np.empty(y.size)
    _rhs(kind, t, y, p, out)
    return out


# ---------------------------------------------------------------------------------------------
# Python interface.


@dataclass(frozen=True)
class Kernel:
    """A compiled right-hand side: its kind, its parameter array and its event function.

    Attributes
    ----------
    kind : int
        One of the ``KIND_*`` constants.
    params : ndarray
        The parameters, packed as the kind reads them.
    event : int
        ``EVENT_*`` whose zeros are located during the integration (0: none).
    t_max : float
        Last time the parameters cover (e.g. a pressure table); integrating beyond it is an
        error with ``t_max_message``.
    """

    kind: int
    params: FloatArray
    event: int = EVENT_NONE
    t_max: float = math.inf
    t_max_message: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", np.ascontiguousarray(self.params, dtype=np.float64))

    def check_end(self, t_end: float) -> None:
        """ParameterError if the run needs times beyond ``t_max``."""
        if t_end > self.t_max:
            raise ParameterError(self.t_max_message or f"the run ends after t = {self.t_max:g}")


def torque_program(torque: Torque | None) -> FloatArray | None:
    """A torque as the flat program the compiled kernels evaluate, or None if one of its terms
    is a Python function.

    Layout: ``[number of terms, (code, factor, payload...)...]``, codes and payloads as in
    :mod:`tumble.torques`.
    """
    if torque is None:
        return np.zeros(1)
    terms = torque.compiled_terms()
    if terms is None:
        return None
    flat: list[float] = [float(len(terms))]
    for code, factor, payload in terms:
        flat += [float(code), float(factor), *(float(v) for v in payload)]
    return np.array(flat)


def rigid_body_kernel(inertia: Any, torque: Torque | None) -> Kernel | None:
    """The kernel of Euler's equations with quaternions (tumble.dynamics.rigid_body_rhs) for
    principal moments ``inertia`` [inertia unit] under ``torque``; None if the torque is a
    Python function."""
    program = torque_program(torque)
    if program is None:
        return None
    return Kernel(KIND_RIGID_BODY, np.concatenate([np.asarray(inertia, dtype=float), program]))


def evaluate_rhs(kernel: Kernel, t: float, y: Any) -> FloatArray:
    """dy/dt of a compiled kernel at one state (for tests against the Python forms)."""
    return _evaluate(kernel.kind, float(t), np.ascontiguousarray(y, dtype=np.float64),
                     kernel.params)  # fmt: skip


@dataclass(frozen=True)
class CompiledSolution:
    """Result of :func:`solve`.

    Attributes
    ----------
    status : int
        0 on success; −1 if the step size fell below the resolution of t; −2 if the state
        stopped being finite.
    t : float
        Time reached.
    y : ndarray
        State at ``t``.
    nfev : int
        Right-hand-side evaluations.
    h : float
        Last step size (for restarting).
    ts, ys : ndarray
        Step times and states (when recorded).
    F : ndarray, shape (steps, 7, n)
        Coefficients of the interpolant on each step (when dense).
    y_eval : ndarray
        States at the requested ``t_eval``.
    event_t, event_signs, event_y : ndarray
        Zeros of the event function, its sign just before each, and the states there.
    """

    status: int
    t: float
    y: FloatArray
    nfev: int
    h: float
    ts: FloatArray
    ys: FloatArray
    F: FloatArray
    y_eval: FloatArray
    event_t: FloatArray
    event_signs: FloatArray
    event_y: FloatArray

    @property
    def message(self) -> str:
        """Why the integration stopped early (empty on success)."""
        return {
            _OK: "",
            _STEP_TOO_SMALL: "the step size fell below the resolution of t",
            _NOT_FINITE: "the state stopped being finite",
        }.get(self.status, f"status {self.status}")

    def __call__(self, t: Any) -> FloatArray:
        """Dense output at times ``t`` within the recorded steps, shape (m, n)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.F.shape[0] == 0:
            raise ValueError("this solution was computed without dense output")
        i = np.clip(np.searchsorted(self.ts, t, side="right") - 1, 0, self.F.shape[0] - 1)
        h = self.ts[i + 1] - self.ts[i]
        x = ((t - self.ts[i]) / h)[:, None]
        F = self.F[i]
        acc = np.zeros((t.size, self.ys.shape[1]))
        for k in range(_NP):
            acc += F[:, _NP - 1 - k]
            acc *= x if k % 2 == 0 else 1.0 - x
        return acc + self.ys[i]


def _specialised(kind: int, args: tuple[Any, ...]) -> Any:
    """``_solve`` compiled for the kernel kind ``kind`` as a compile-time constant.

    With the kind a ``Literal[int]``, LLVM folds the right-hand side's dispatch and inlines
    the one kernel into the stage loops (about 1.8× faster than a runtime kind). Each kind's
    specialisation is compiled once and cached on disk like any other signature, and
    :func:`solve_batch` runs the same one.
    """
    signature = (numba.types.literal(kind), *(numba.typeof(a) for a in args))
    return _solve.compile(signature)


def solve(
    kernel: Kernel,
    y0: Any,
    t_end: float,
    *,
    t0: float = 0.0,
    rtol: float,
    atol: float,
    t_eval: Any = None,
    record: bool = True,
    dense: bool = True,
    first_step: float | None = None,
) -> CompiledSolution:
    """Integrate a compiled kernel from ``t0`` to ``t_end`` with DOP853.

    Parameters
    ----------
    kernel : Kernel
        The right-hand side.
    y0 : array_like
        State at ``t0``.
    t_end : float
        Final time [the kernel's time unit].
    rtol, atol : float
        Tolerances of the local error (as scipy's DOP853 interprets them).
    t_eval : array_like, optional
        Ascending times in [t0, t_end] at which to return states (``y_eval``).
    record : bool
        Keep every step's time and state.
    dense : bool
        Keep the interpolant of every step (needs ``record``), for evaluation anywhere.
    first_step : float, optional
        Initial step size; by default Hairer's estimate.

    Returns
    -------
    CompiledSolution
        Check ``status`` (or use :func:`tumble.integrate.integrate`, which raises on failure).
    """
    args = _solve_args(kernel, y0, t0, t_end, rtol, atol, t_eval, record, dense, first_step)
    res = _specialised(kernel.kind, args)(kernel.kind, *args)
    return _solution(res, args[1].size, record, dense)


def _solve_args(
    kernel: Kernel,
    y0: Any,
    t0: float,
    t_end: float,
    rtol: float,
    atol: float,
    t_eval: Any,
    record: bool,
    dense: bool,
    first_step: float | None,
) -> tuple[Any, ...]:
    """The arguments of ``_solve`` after the kind, in its types."""
    te = np.empty(0) if t_eval is None else np.ascontiguousarray(t_eval, dtype=np.float64)
    return (
        kernel.params,
        np.ascontiguousarray(y0, dtype=np.float64),
        float(t0),
        float(t_end),
        float(rtol),
        float(atol),
        0.0 if first_step is None else float(first_step),
        te,
        bool(record),
        bool(dense and record),
        int(kernel.event),
    )


def _solution(res: tuple[Any, ...], n: int, record: bool, dense: bool) -> CompiledSolution:
    """``_solve``'s result tuple as a :class:`CompiledSolution` of an n-dimensional state."""
    status, t, y, nfev, h, n_steps, ts, ys, F, y_eval, ev_t, ev_s, ev_y, n_ev = res
    kept = n_steps + 1 if record else 1
    return CompiledSolution(
        int(status),
        float(t),
        y,
        int(nfev),
        float(h),
        ts[:kept],
        ys[: kept * n].reshape(kept, n),
        F[: n_steps * _NP * n].reshape(n_steps, _NP, n)
        if (record and dense)
        else np.empty((0, _NP, n)),
        y_eval.reshape(-1, n),
        ev_t[:n_ev],
        ev_s[:n_ev],
        ev_y[: n_ev * n].reshape(n_ev, n),
    )


def solve_many(
    kernels: Sequence[Kernel],
    y0: Sequence[Any],
    t_end: Sequence[float],
    *,
    rtol: float,
    atol: float,
    threads: int | None = None,
) -> list[tuple[CompiledSolution, float]]:
    """:func:`solve` of many problems at once, over a thread pool, with dense output.

    The kernels may differ in kind and parameters. Each problem runs through the integrator
    :func:`solve` uses, with the GIL released, so each result equals that of :func:`solve`
    to the bit, whatever the number of threads.

    Parameters
    ----------
    kernels : sequence of Kernel
        The right-hand sides.
    y0 : sequence of array_like
        Initial states at t = 0, one per kernel.
    t_end : sequence of float
        Final times, one per kernel [the kernel's time unit].
    rtol, atol : float
        Tolerances.
    threads : int, optional
        Number of threads (default: :func:`available_threads`).

    Returns
    -------
    list of (CompiledSolution, float)
        Per problem, its solution (check ``status``) and the seconds it took [s].
    """
    if not len(kernels) == len(y0) == len(t_end):
        raise ParameterError(
            f"solve_many needs as many initial states and end times as kernels, got "
            f"{len(kernels)}, {len(y0)} and {len(t_end)}"
        )
    jobs = [
        (k, _solve_args(k, y, 0.0, t, rtol, atol, None, True, True, None))
        for k, y, t in zip(kernels, y0, t_end, strict=True)
    ]
    # Look every kind's specialisation up first: compiling inside the pool would compile
    # the same function in several threads at once.
    entries = {k.kind: _specialised(k.kind, args) for k, args in jobs}
    out: list[Any] = [None] * len(jobs)

    def one(i: int) -> None:
        k, args = jobs[i]
        start = time.perf_counter()
        res = entries[k.kind](k.kind, *args)
        out[i] = (_solution(res, args[1].size, True, True), time.perf_counter() - start)

    workers = max(1, min(_MAX_THREADS if threads is None else int(threads), _MAX_THREADS))
    if workers == 1 or len(jobs) < 2:
        for i in range(len(jobs)):
            one(i)
    else:
        with ThreadPoolExecutor(max_workers=min(workers, len(jobs))) as pool:
            list(pool.map(one, range(len(jobs))))
    return out


@dataclass(frozen=True)
class BatchResult:
    """Result of :func:`solve_batch`: states (N, len(t_eval), n), and per trajectory the
    status (0 = success), the time reached and the right-hand-side evaluations."""

    y: FloatArray
    status: Any
    t: FloatArray
    nfev: Any


def solve_batch(
    kind: int,
    params: Any,
    y0: Any,
    t_end: Any,
    t_eval: Any,
    *,
    rtol: float,
    atol: float,
    threads: int | None = None,
) -> BatchResult:
    """Integrate N trajectories of one kernel kind in parallel over the cores.

    Parameters
    ----------
    kind : int
        ``KIND_*`` of every trajectory.
    params : array_like, shape (N, m)
        One parameter array per trajectory (equal length; pad with zeros).
    y0 : array_like, shape (N, n)
        Initial states at t = 0.
    t_end : float or array_like, shape (N,)
        Final times.
    t_eval : array_like
        Ascending sample times, shared by all trajectories (beyond a trajectory's ``t_end``
        its samples are NaN).
    rtol, atol : float
        Tolerances.
    threads : int, optional
        Number of threads (default: :func:`available_threads`). Each runs whole trajectories
        through the integrator :func:`solve` uses, with the GIL released: the results do not
        depend on the number of threads.

    Returns
    -------
    BatchResult
    """
    P = np.ascontiguousarray(params, dtype=np.float64)
    Y0 = np.ascontiguousarray(y0, dtype=np.float64)
    if P.ndim != 2 or Y0.ndim != 2 or P.shape[0] != Y0.shape[0]:
        raise ParameterError(
            f"solve_batch needs params (N, m) and y0 (N, n) with the same N, "
            f"got {P.shape} and {Y0.shape}"
        )
    T = np.ascontiguousarray(np.broadcast_to(np.asarray(t_end, dtype=float), (Y0.shape[0],)))
    te = np.ascontiguousarray(t_eval, dtype=np.float64)
    N, n = Y0.shape
    y = np.empty((N, te.size, n))
    status = np.empty(N, dtype=np.int64)
    t = np.empty(N)
    nfev = np.empty(N, dtype=np.int64)
    kind = int(kind)

    def args(i: int) -> tuple[Any, ...]:
        return (P[i], Y0[i], 0.0, float(T[i]), float(rtol), float(atol), 0.0, te, False, False,
                EVENT_NONE)  # fmt: skip

    if N == 0:
        return BatchResult(y, status, t, nfev)
    # The same compiled integrator as solve() (no second, parallel compile), looked up once;
    # it releases the GIL, so threads run the trajectories concurrently.
    entry = _specialised(kind, args(0))

    def one(i: int) -> None:
        res = entry(kind, *args(i))
        status[i], t[i], nfev[i] = res[0], res[1], res[3]
        y[i] = res[9].reshape(-1, n)

    workers = max(1, min(_MAX_THREADS if threads is None else int(threads), _MAX_THREADS, N))
    if workers == 1:
        for i in range(N):
            one(i)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(one, range(N)))
    return BatchResult(y, status, t, nfev)


_MAX_THREADS = numba.get_num_threads()  # the cores, or NUMBA_NUM_THREADS


def available_threads() -> int:
    """Threads the batch integrator can use (the cores, or ``NUMBA_NUM_THREADS``)."""
    return _MAX_THREADS
