"""Torque programs, compiled: the moment of a sum of registered terms at a state.

A :class:`tumble.torques.Torque` whose terms are all compiled flattens into a *program*
(:mod:`tumble.kernels.terms`: ``[number of terms, (code, factor, size, payload...)...]``). Each
term returns its body moment for the body rate ω and the body → inertial matrix ``a`` (formed
once for all terms), through the dispatch the registry generates. The integrator's
right-hand sides call :func:`torque_moment` at one state (:func:`orbit_torque_moment` where the
program has terms along an orbit); Python calls the same terms through :func:`moments` (batches
of states) and :func:`inertial_moments` (an averaging grid: every attitude at every time).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.frames import attitude_matrix, quaternion_matrix, to_inertial
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.layout import Mat3, Vec3
from tumble.kernels.terms import (
    HEAD_SIZE,
    HEADER,
    engine_moment_of,
    moment_of,
    next_term,
    orbit_moment_of,
)

__all__ = [
    "inertial_moments",
    "moments",
    "orbit_torque_moment",
    "program_of",
    "torque_moment",
]

_HEAD = HEADER.at


def program_of(term: Callable[..., Vec3]) -> Callable[..., Vec3]:
    """The body moment of a program whose terms ``term(code, f, prog, v, t, w1, w2, w3, a)``
    evaluates (a dispatch of :mod:`tumble.kernels.terms`)."""

    @jit(INLINE)
    def program(
        prog: FloatArray, start: int, t: float, w1: float, w2: float, w3: float, a: Mat3
    ) -> Vec3:
        m1 = m2 = m3 = 0.0
        i = start + 1
        for _ in range(int(prog[start])):
            d1, d2, d3 = term(
                int(prog[i + _HEAD.code]), prog[i + _HEAD.factor], prog, i + HEAD_SIZE, t,
                w1, w2, w3, a,
            )  # fmt: skip
            m1 += d1
            m2 += d2
            m3 += d3
            i = next_term(prog, i)
        return m1, m2, m3

    return cast(Callable[..., Vec3], program)


fixed_program = program_of(moment_of)
"""Body moment of the program ``prog[start:]`` at body rate ω and attitude matrix a (a term
compiled apart, along an orbit or calling out, is NaN)."""
engine_program = program_of(engine_moment_of)
"""The same with a user's callback (the averaging engines' general quadrature)."""
orbit_program = program_of(orbit_moment_of)
"""The same for any program, the terms along an orbit included."""


@jit(KERNEL)
def torque_moment(prog: FloatArray, start: int, t: float, y: FloatArray, out: FloatArray) -> None:
    """Body moment of the torque program ``prog[start:]`` at state ``y = [ω, q]`` into
    out[0:3]; a term compiled apart gives NaN (:func:`orbit_torque_moment` has them)."""
    m1 = m2 = m3 = 0.0
    if prog[start] > 0:
        m1, m2, m3 = fixed_program(prog, start, t, y[0], y[1], y[2], attitude_matrix(y))
    out[0], out[1], out[2] = m1, m2, m3


@jit(KERNEL)
def orbit_torque_moment(
    prog: FloatArray, start: int, t: float, y: FloatArray, out: FloatArray
) -> None:
    """:func:`torque_moment` for any program, the terms compiled apart included (along an
    orbit, calling out): compiled apart, so that the other right-hand sides neither compile
    Kepler's equation and the geomagnetic field nor carry an opaque call."""
    m1 = m2 = m3 = 0.0
    if prog[start] > 0:
        m1, m2, m3 = orbit_program(prog, start, t, y[0], y[1], y[2], attitude_matrix(y))
    out[0], out[1], out[2] = m1, m2, m3


@jit(ENTRY)
def moments(prog: FloatArray, t: FloatArray, q: FloatArray, w: FloatArray) -> FloatArray:
    """Body moments of a program at the states (t[k], q[k], w[k]), shapes (n,), (n, 4),
    (n, 3) → (n, 3); an argument of length 1 is used for every k."""
    n = max(t.size, q.shape[0], w.shape[0])
    out = np.empty((n, 3))
    for k in range(n):
        kt = k if t.size > 1 else 0
        kq = k if q.shape[0] > 1 else 0
        kw = k if w.shape[0] > 1 else 0
        a = quaternion_matrix(q[kq, 0], q[kq, 1], q[kq, 2], q[kq, 3])
        out[k, 0], out[k, 1], out[k, 2] = orbit_program(
            prog, 0, t[kt], w[kw, 0], w[kw, 1], w[kw, 2], a
        )
    return out


@jit(ENTRY)
def inertial_moments(prog: FloatArray, t: FloatArray, A: FloatArray, w: FloatArray) -> FloatArray:
    """Inertial components A M of a program's moment for every attitude at every time:
    attitudes A (n, 3, 3) with body rates w (n, 3), times t (m,) → (n, m, 3)."""
    out = np.empty((A.shape[0], t.size, 3))
    for k in range(A.shape[0]):
        a = (
            A[k, 0, 0], A[k, 0, 1], A[k, 0, 2],
            A[k, 1, 0], A[k, 1, 1], A[k, 1, 2],
            A[k, 2, 0], A[k, 2, 1], A[k, 2, 2],
        )  # fmt: skip
        for j in range(t.size):
            m1, m2, m3 = orbit_program(prog, 0, t[j], w[k, 0], w[k, 1], w[k, 2], a)
            out[k, j, 0], out[k, j, 1], out[k, j, 2] = to_inertial(a, m1, m2, m3)
    return out
