"""The compiled kernels transcribed into heyoka.py's Taylor-method expressions: the benchmark's
independent peer.

Written apart from :mod:`tumble.kernels`, from the same equations: heyoka's reference runs
agree with the compiled ones only if the two transcriptions agree, which a slow test checks at
random states. heyoka.py is optional (the ``bench`` extra); without it every function here
says so by returning None.
"""

from __future__ import annotations

import itertools
import math
import time
from typing import Any

import numpy as np

from tumble import kernels
from tumble._typing import FloatArray
from tumble.errors import IntegrationError, ParameterError
from tumble.kernels import Kernel, terms

__all__ = ["at_equal_error", "available", "heyoka_system", "propagate", "without_quadratic_drag"]

System = list[tuple[Any, Any]]


def available() -> Any:
    """The heyoka module, or None if it is not installed."""
    try:
        import heyoka
    except ImportError:
        return None
    return heyoka


def _quaternion_rates(w: list[Any], q: list[Any]) -> list[Any]:
    w1, w2, w3 = w
    q0, q1, q2, q3 = q
    return [
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 - q1 * w3 + q3 * w1),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
    ]


def _rigid_body(hy: Any, p: list[float]) -> System | None:
    """Euler's equations with quaternions under the torque program p[3:]."""
    w = list(hy.make_vars("w1", "w2", "w3"))
    q = list(hy.make_vars("q0", "q1", "q2", "q3"))
    i1, i2, i3 = p[:3]
    m = _torque(hy, p, 3, hy.time, w, q)
    if m is None:
        return None
    w1, w2, w3 = w
    wdot = [
        ((i2 - i3) * w2 * w3 + m[0]) / i1,
        ((i3 - i1) * w3 * w1 + m[1]) / i2,
        ((i1 - i2) * w1 * w2 + m[2]) / i3,
    ]
    return list(zip([*w, *q], [*wdot, *_quaternion_rates(w, q)], strict=True))


def _nonlinear_moment(hy: Any, p: list[float]) -> System | None:
    """Serov's (1.1) with quaternions; None for a pressure table (no Taylor form here)."""
    w = list(hy.make_vars("w1", "w2", "w3"))
    q = list(hy.make_vars("q0", "q1", "q2", "q3"))
    t = hy.time
    mu, a0, b0, eps, d, nu, code, q_0 = p[:8]
    if code == 0:
        a, b = a0, b0
    elif code == 1:
        a, b = a0 * hy.exp(eps * t) / q_0, b0 * hy.exp(eps * t) / q_0
    else:
        return None  # a pressure table: piecewise linear in t
    w1, w2, w3 = w
    q0, q1, q2, q3 = q
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    ex = 2.0 * (q1 * q3 - q0 * q2) / n2
    ey = 2.0 * (q2 * q3 + q0 * q1) / n2
    ez = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / n2
    m0 = a + 2.0 * b * ez
    wdot = [
        (1.0 - mu) * w2 * w3 + m0 * ey - eps * d * w1,
        (mu - 1.0) * w3 * w1 - m0 * ex - eps * d * w2,
        -eps * nu * w3,
    ]
    return list(zip([*w, *q], [*wdot, *_quaternion_rates(w, q)], strict=True))


def _rotating_field(hy: Any, p: list[float]) -> System:
    """Martynenko's (1.5): I z′ = I z × z + ε Γᵀ ĥĥ (Γ z − ξ3), Γ′ = Γ ẑ − ξ̂3 Γ."""
    i1, i2, i3, eps = p[:4]
    hh = p[4:13]
    z = hy.make_vars("z1", "z2", "z3")
    g = hy.make_vars(*(f"g{r}{c}" for r in range(3) for c in range(3)))
    r = [g[3 * i] * z[0] + g[3 * i + 1] * z[1] + g[3 * i + 2] * z[2] for i in range(3)]
    r[2] = r[2] - 1.0
    e = [hh[3 * i] * r[0] + hh[3 * i + 1] * r[1] + hh[3 * i + 2] * r[2] for i in range(3)]
    gte = [g[c] * e[0] + g[3 + c] * e[1] + g[6 + c] * e[2] for c in range(3)]
    zdot = [
        ((i2 - i3) * z[1] * z[2] + eps * gte[0]) / i1,
        ((i3 - i1) * z[2] * z[0] + eps * gte[1]) / i2,
        ((i1 - i2) * z[0] * z[1] + eps * gte[2]) / i3,
    ]
    gdot = []
    for row in range(3):
        a, b, c = g[3 * row], g[3 * row + 1], g[3 * row + 2]
        gz = [b * z[2] - c * z[1], c * z[0] - a * z[2], a * z[1] - b * z[0]]
        # − ξ̂3 Γ: rows (Γ2, −Γ1, 0)
        shift = (
            [g[3 + k] for k in range(3)]
            if row == 0
            else ([-g[k] for k in range(3)] if row == 1 else [0.0, 0.0, 0.0])
        )
        gdot += [gz[k] + shift[k] for k in range(3)]
    return list(zip([*z, *g], [*zdot, *gdot], strict=True))


def heyoka_system(kernel: Kernel) -> System | None:
    """The right-hand side of a compiled kernel as heyoka.py expressions, or None when a part
    has no heyoka form (a pressure table, the quadratic drag) or heyoka is not installed.

    The quadratic drag's w|w| has no Taylor form (it is not analytic at w = 0).

    Returns
    -------
    list of (variable, expression)
        The system for ``heyoka.taylor_adaptive``.
    """
    hy = available()
    if hy is None:
        return None
    p = [float(v) for v in kernel.params]
    if kernel.kind == kernels.KIND_RIGID_BODY:
        return _rigid_body(hy, p)
    if kernel.kind == kernels.KIND_NONLINEAR_MOMENT:
        return _nonlinear_moment(hy, p)
    if kernel.kind == kernels.KIND_ROTATING_FIELD:
        return _rotating_field(hy, p)
    return None


class _Frame:
    """The attitude of the quaternion q (heyoka expressions, normalised here) as maps of
    3-lists between inertial and body components."""

    def __init__(self, hy: Any, q: list[Any]) -> None:
        norm = hy.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
        q0, q1, q2, q3 = (c / norm for c in q)
        self.A = [
            [1.0 - 2.0 * (q2 * q2 + q3 * q3), 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2)],
            [2.0 * (q1 * q2 + q0 * q3), 1.0 - 2.0 * (q1 * q1 + q3 * q3), 2.0 * (q2 * q3 - q0 * q1)],
            [2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), 1.0 - 2.0 * (q1 * q1 + q2 * q2)],
        ]

    def to_body(self, x: list[Any]) -> list[Any]:
        A = self.A
        return [A[0][c] * x[0] + A[1][c] * x[1] + A[2][c] * x[2] for c in range(3)]

    def to_inertial(self, x: list[Any]) -> list[Any]:
        A = self.A
        return [A[r][0] * x[0] + A[r][1] * x[1] + A[r][2] * x[2] for r in range(3)]


def _torque(
    hy: Any, prog: list[float], start: int, t: Any, w: list[Any], q: list[Any]
) -> list[Any] | None:
    """The torque program of :attr:`tumble.torques.Torque.program` as heyoka expressions, each
    term by its own transcription (``Term.peer``); None if a term has no Taylor form (the
    quadratic drag)."""
    m: list[Any] = [0.0, 0.0, 0.0]
    program = np.asarray(prog, dtype=float)
    if int(program[start]) == 0:
        return m
    frame = _Frame(hy, q)
    for term, f, payload in terms.walk(program, start):
        if term.peer is None:
            raise ParameterError(f"the heyoka peer has no transcription of the term {term.name!r}")
        add = term.peer(term.values(payload), f, t, w, frame, hy)
        if add is None:
            return None
        m = [m[k] + add[k] for k in range(3)]
    return m


def propagate(system: System, y0: FloatArray, t_end: float, tol: float) -> tuple[float, Any]:
    """heyoka's integrator at ``tol``, built once: (its build time [s], a function that
    propagates from ``y0`` to ``t_end`` and returns the final state)."""
    hy = available()
    start = time.perf_counter()
    ta = hy.taylor_adaptive(system, list(y0), tol=tol)
    build = time.perf_counter() - start

    def once() -> Any:
        ta.time = 0.0
        ta.state[:] = y0
        outcome = ta.propagate_until(t_end)[0]
        if outcome != hy.taylor_outcome.time_limit:
            raise IntegrationError(f"heyoka stopped with {outcome} at t = {ta.time:g}")
        return ta.state.copy()

    return build, once


def at_equal_error(ladder: list[dict], error: float) -> tuple[float, bool]:
    """heyoka's time at ``error``: log-log interpolation between the two rungs that bracket
    it; the nearest rung's time (and False) when none do."""
    pts = sorted((r["error"], r["time_s"]) for r in ladder if r["error"] > 0.0)
    for (e_lo, t_lo), (e_hi, t_hi) in itertools.pairwise(pts):
        if e_lo <= error <= e_hi:
            if e_hi == e_lo:
                return t_lo, True
            x = (math.log(error) - math.log(e_lo)) / (math.log(e_hi) - math.log(e_lo))
            return math.exp(math.log(t_lo) + x * (math.log(t_hi) - math.log(t_lo))), True
    nearest = min(pts, key=lambda et: abs(math.log(et[0]) - math.log(error)))
    return nearest[1], False


def without_quadratic_drag(kernel: Kernel) -> Kernel | None:
    """A rigid-body kernel with its quadratic-drag terms removed (the smooth part heyoka can
    integrate); None if it has none or is of another kind."""
    if kernel.kind != kernels.KIND_RIGID_BODY:
        return None
    p = kernel.params
    kept = [
        (terms.code(term.name), f, tuple(payload))
        for term, f, payload in terms.walk(p, 3)
        if term.name != "quadratic_drag"
    ]
    if len(kept) == int(p[3]):
        return None
    return Kernel(kernel.kind, np.concatenate([p[:3], terms.flatten(kept)]))
