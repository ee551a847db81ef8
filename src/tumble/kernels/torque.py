"""The built-in torques, compiled: the one definition of each torque's physics.

A :class:`tumble.torques.Torque` whose terms are all built in flattens into a *program*
``[number of terms, (code, factor, payload...)...]`` (:attr:`tumble.torques.Torque.program`),
with the codes and payloads below. Each term returns its body moment for the body rate ω and
the body → inertial matrix ``a`` (formed once for all terms). The integrator's right-hand
sides call :func:`torque_moment` at one state (:func:`orbit_torque_moment` where the program
has terms along an orbit); Python calls the same terms through
:func:`moments` (batches of states) and :func:`inertial_moments` (an averaging grid: every
attitude at every time).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.codes import (
    TERM_BODY_CONSTANT,
    TERM_EDDY_CURRENT,
    TERM_FIELD_MOMENTS,
    TERM_GRAVITY_GRADIENT,
    TERM_GRAVITY_MOMENTS,
    TERM_INERTIAL_CONSTANT,
    TERM_LINEAR_DRAG,
    TERM_ORBIT_EDDY,
    TERM_ORBIT_EDDY_HARMONIC,
    TERM_ORBIT_GRAVITY,
    TERM_PAYLOAD,
    TERM_QUADRATIC_DRAG,
    TERM_USER,
)
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.space import ORBIT_SIZE, field_at, harmonic_field, harmonic_size, orbit_at
from tumble.kernels.user import call_user

__all__ = [
    "attitude_matrix",
    "inertial_moments",
    "moments",
    "next_term",
    "orbit_torque_moment",
    "quaternion_rates",
    "torque_moment",
]


Vec3 = tuple[float, float, float]
Mat3 = tuple[float, float, float, float, float, float, float, float, float]


@jit(INLINE)
def _quaternion_matrix(q0: float, q1: float, q2: float, q3: float) -> Mat3:
    """Body → inertial matrix (row by row) of a quaternion, normalised first
    (:func:`tumble.rotations.quat_to_matrix`)."""
    norm = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    q0, q1, q2, q3 = q0 / norm, q1 / norm, q2 / norm, q3 / norm
    return (
        1.0 - 2.0 * (q2 * q2 + q3 * q3), 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2),
        2.0 * (q1 * q2 + q0 * q3), 1.0 - 2.0 * (q1 * q1 + q3 * q3), 2.0 * (q2 * q3 - q0 * q1),
        2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), 1.0 - 2.0 * (q1 * q1 + q2 * q2),
    )  # fmt: skip


@jit(INLINE)
def attitude_matrix(y: FloatArray) -> Mat3:
    """Body → inertial matrix (row by row) of the quaternion y[3:7] of a state ``[ω, q]``."""
    return _quaternion_matrix(y[3], y[4], y[5], y[6])


@jit(INLINE)
def _to_body(a: Mat3, x1: float, x2: float, x3: float) -> Vec3:
    """Aᵀ x: inertial components to body ones."""
    return (
        a[0] * x1 + a[3] * x2 + a[6] * x3,
        a[1] * x1 + a[4] * x2 + a[7] * x3,
        a[2] * x1 + a[5] * x2 + a[8] * x3,
    )


@jit(INLINE)
def _matrix_times(prog: FloatArray, v: int, x1: float, x2: float, x3: float) -> Vec3:
    """M x for the 3×3 matrix stored by rows at prog[v : v + 9]."""
    return (
        prog[v] * x1 + prog[v + 1] * x2 + prog[v + 2] * x3,
        prog[v + 3] * x1 + prog[v + 4] * x2 + prog[v + 5] * x3,
        prog[v + 6] * x1 + prog[v + 7] * x2 + prog[v + 8] * x3,
    )


@jit(INLINE)
def _gravity_gradient(f: float, prog: FloatArray, v: int, t: float, a: Mat3) -> Vec3:
    """f·3n² r × (I r) = f·3n² ((I3 − I2) r2 r3, …) for the unit radius vector r in body
    axes; payload [I1, I2, I3, n, u0, e1, e2, normal] with r̂ = cos u e1 + sin u e2,
    u = n t + u0."""
    i1, i2, i3 = prog[v], prog[v + 1], prog[v + 2]
    n, u0 = prog[v + 3], prog[v + 4]
    cu, su = math.cos(n * t + u0), math.sin(n * t + u0)
    r1, r2, r3 = _to_body(
        a,
        cu * prog[v + 5] + su * prog[v + 8],
        cu * prog[v + 6] + su * prog[v + 9],
        cu * prog[v + 7] + su * prog[v + 10],
    )
    g = 3.0 * n * n * f
    return g * (i3 - i2) * r2 * r3, g * (i1 - i3) * r3 * r1, g * (i2 - i1) * r1 * r2


@jit(INLINE)
def _eddy_current(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f·M0 (ĥ(ĥ·x) − x) in body axes, x = A ω − Ω ξ3 the angular velocity relative to the
    field ĥ(t) = (sinβ cos Ωt, sinβ sin Ωt, cosβ); payload [M0, Ω, β]. Martynenko (1979),
    eq. (1.3)."""
    M0, rate, beta = prog[v], prog[v + 1], prog[v + 2]
    sb, cb = math.sin(beta), math.cos(beta)
    h1, h2, h3 = sb * math.cos(rate * t), sb * math.sin(rate * t), cb
    x1 = a[0] * w1 + a[1] * w2 + a[2] * w3
    x2 = a[3] * w1 + a[4] * w2 + a[5] * w3
    x3 = a[6] * w1 + a[7] * w2 + a[8] * w3 - rate
    hw = h1 * x1 + h2 * x2 + h3 * x3
    m1, m2, m3 = _to_body(a, h1 * hw - x1, h2 * hw - x2, h3 * hw - x3)
    g = f * M0
    return g * m1, g * m2, g * m3


@jit(INLINE)
def _induced(
    prog: FloatArray, v: int, x1: float, x2: float, x3: float, b1: float, b2: float, b3: float
) -> Vec3:
    """(M x) × b for the magnetic tensor M stored by rows at prog[v : v + 9]."""
    m1, m2, m3 = _matrix_times(prog, v, x1, x2, x3)
    return m2 * b3 - m3 * b2, m3 * b1 - m1 * b3, m1 * b2 - m2 * b1


@jit(INLINE)
def _orbit_eddy(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f·(M x) × B in body axes: the eddy-current moment of a conductor of magnetic tensor M
    whose induced dipole is M x, x = −dB/dt seen in the body = ω × B − Aᵀ dB/dt (B and its
    inertial rate from :func:`tumble.kernels.space.field_at`); payload [orbit, field, M]."""
    bi, ci = field_at(prog, v, prog, v + ORBIT_SIZE, t)
    return _eddy_moment(f, prog, v + ORBIT_SIZE + 5, bi, ci, w1, w2, w3, a)


@jit(INLINE)
def _eddy_moment(
    f: float, prog: FloatArray, vm: int, bi: Vec3, ci: Vec3, w1: float, w2: float, w3: float,
    a: Mat3,
) -> Vec3:  # fmt: skip
    """f·(M x) × b for the inertial field bi and its rate ci, x = ω × b − Aᵀ ci (body axes),
    M by rows at prog[vm : vm + 9]."""
    b1, b2, b3 = _to_body(a, bi[0], bi[1], bi[2])
    c1, c2, c3 = _to_body(a, ci[0], ci[1], ci[2])
    x1, x2, x3 = w2 * b3 - w3 * b2 - c1, w3 * b1 - w1 * b3 - c2, w1 * b2 - w2 * b1 - c3
    m1, m2, m3 = _induced(prog, vm, x1, x2, x3, b1, b2, b3)
    return f * m1, f * m2, f * m3


@jit(KERNEL)
def _orbit_eddy_harmonic(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """:func:`_orbit_eddy` in a harmonic field (the IGRF,
    :func:`tumble.kernels.space.harmonic_field`); payload [orbit, M, field]."""
    r, vel = orbit_at(prog, v, t)
    vf = v + ORBIT_SIZE + 9
    bi, ci = harmonic_field(prog, vf, prog[vf + 1] + prog[vf + 2] * t, r, vel)
    return _eddy_moment(f, prog, v + ORBIT_SIZE, bi, ci, w1, w2, w3, a)


@jit(INLINE)
def _orbit_gravity(f: float, prog: FloatArray, v: int, t: float, a: Mat3) -> Vec3:
    """f·3μ/r³ r̂ × (I r̂) in body axes at the orbit's position at time t; payload
    [orbit, I1, I2, I3]."""
    r, _ = orbit_at(prog, v, t)
    size2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    r1, r2, r3 = _to_body(a, r[0], r[1], r[2])
    g = 3.0 * prog[v + 9] * f / (size2 * size2 * math.sqrt(size2))  # 3μ/r³ over r²
    i1, i2, i3 = prog[v + ORBIT_SIZE], prog[v + ORBIT_SIZE + 1], prog[v + ORBIT_SIZE + 2]
    return g * (i3 - i2) * r2 * r3, g * (i1 - i3) * r3 * r1, g * (i2 - i1) * r1 * r2


@jit(INLINE)
def _field_moments(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """The eddy-current moment f·(M x) × B averaged over the orbit and the Earth's rotation
    (:mod:`tumble.space.moments`): with S = ⟨B Bᵀ⟩ and ⟨Ḃ Bᵀ⟩ = [δ]× (its mean is
    antisymmetric) in body axes, C = [ω]× S − [δ]× and N = M C, the moment is
    (N23 − N32, N31 − N13, N12 − N21). S and δ turn about ξ3 with the node, Ω̇ t; payload
    [M (by rows), S (inertial, by rows), δ (inertial), Ω̇]."""
    c, s = math.cos(prog[v + 21] * t), math.sin(prog[v + 21] * t)
    # The columns of A' = Rz(Ω̇t)ᵀ A, so that Aᵀ Rz S Rzᵀ A = A'ᵀ S A'.
    u0 = (c * a[0] + s * a[3], -s * a[0] + c * a[3], a[6])
    u1 = (c * a[1] + s * a[4], -s * a[1] + c * a[4], a[7])
    u2 = (c * a[2] + s * a[5], -s * a[2] + c * a[5], a[8])
    p0 = _matrix_times(prog, v + 9, u0[0], u0[1], u0[2])
    p1 = _matrix_times(prog, v + 9, u1[0], u1[1], u1[2])
    p2 = _matrix_times(prog, v + 9, u2[0], u2[1], u2[2])
    s00, s11, s22 = _dot(u0, p0), _dot(u1, p1), _dot(u2, p2)
    s01, s02, s12 = _dot(u0, p1), _dot(u0, p2), _dot(u1, p2)
    e = (prog[v + 18], prog[v + 19], prog[v + 20])
    d0, d1, d2 = _dot(u0, e), _dot(u1, e), _dot(u2, e)
    # C = [ω]× S − [δ]×, by rows.
    c00, c01, c02 = w2 * s02 - w3 * s01, w2 * s12 - w3 * s11 + d2, w2 * s22 - w3 * s12 - d1
    c10, c11, c12 = w3 * s00 - w1 * s02 - d2, w3 * s01 - w1 * s12, w3 * s02 - w1 * s22 + d0
    c20, c21, c22 = w1 * s01 - w2 * s00 + d1, w1 * s11 - w2 * s01 - d0, w1 * s12 - w2 * s02
    m = prog
    n01 = m[v] * c01 + m[v + 1] * c11 + m[v + 2] * c21
    n02 = m[v] * c02 + m[v + 1] * c12 + m[v + 2] * c22
    n10 = m[v + 3] * c00 + m[v + 4] * c10 + m[v + 5] * c20
    n12 = m[v + 3] * c02 + m[v + 4] * c12 + m[v + 5] * c22
    n20 = m[v + 6] * c00 + m[v + 7] * c10 + m[v + 8] * c20
    n21 = m[v + 6] * c01 + m[v + 7] * c11 + m[v + 8] * c21
    return f * (n12 - n21), f * (n20 - n02), f * (n01 - n10)


@jit(INLINE)
def _dot(x: Vec3, y: Vec3) -> float:
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]


@jit(INLINE)
def _gravity_moments(f: float, prog: FloatArray, v: int, t: float, a: Mat3) -> Vec3:
    """The gravity gradient averaged over the orbit, −f·c ĥ × (I ĥ) in body axes with
    c = 3μ/(2a³(1 − e²)^{3/2}) (⟨3μ r̂ r̂ᵀ/r³⟩ = c (1 − ĥ ĥᵀ)) and the orbit normal ĥ turned
    about ξ3 by Ω̇ t; payload [I1, I2, I3, c, ĥ(0), Ω̇]."""
    cn, sn = math.cos(prog[v + 7] * t), math.sin(prog[v + 7] * t)
    h1 = cn * prog[v + 4] - sn * prog[v + 5]
    h2 = sn * prog[v + 4] + cn * prog[v + 5]
    b1, b2, b3 = _to_body(a, h1, h2, prog[v + 6])
    i1, i2, i3 = prog[v], prog[v + 1], prog[v + 2]
    g = -f * prog[v + 3]
    return g * (i3 - i2) * b2 * b3, g * (i1 - i3) * b3 * b1, g * (i2 - i1) * b1 * b2


@jit(INLINE)
def _matrix_quaternion(a: Mat3) -> tuple[float, float, float, float]:
    """A unit quaternion (sign arbitrary) of the rotation matrix a (by rows), by the largest of
    its four squared components (Shepperd's method: no cancellation)."""
    tr = a[0] + a[4] + a[8]
    if tr >= a[0] and tr >= a[4] and tr >= a[8]:
        s = 2.0 * math.sqrt(1.0 + tr)
        return 0.25 * s, (a[7] - a[5]) / s, (a[2] - a[6]) / s, (a[3] - a[1]) / s
    if a[0] >= a[4] and a[0] >= a[8]:
        s = 2.0 * math.sqrt(1.0 + a[0] - a[4] - a[8])
        return (a[7] - a[5]) / s, 0.25 * s, (a[1] + a[3]) / s, (a[2] + a[6]) / s
    if a[4] >= a[8]:
        s = 2.0 * math.sqrt(1.0 - a[0] + a[4] - a[8])
        return (a[2] - a[6]) / s, (a[1] + a[3]) / s, 0.25 * s, (a[5] + a[7]) / s
    s = 2.0 * math.sqrt(1.0 - a[0] - a[4] + a[8])
    return (a[3] - a[1]) / s, (a[2] + a[6]) / s, (a[5] + a[7]) / s, 0.25 * s


@jit(INLINE)
def _user(f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float,
          a: Mat3) -> Vec3:  # fmt: skip
    """f times the moment of a user's compiled function (:mod:`tumble.kernels.user`); payload
    [address, n, n parameters]."""
    q0, q1, q2, q3 = _matrix_quaternion(a)
    m1, m2, m3 = call_user(int(prog[v]), t, q0, q1, q2, q3, w1, w2, w3, prog, v + 2,
                           int(prog[v + 1]))  # fmt: skip
    return f * m1, f * m2, f * m3


@jit(INLINE)
def _term(
    code: int, f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float,
    a: Mat3,
) -> Vec3:  # fmt: skip
    """Body moment of one term times its factor f; NaN for an unknown code, which cannot come
    from a Torque's program: the caller then fails loudly instead of ignoring the term.

    The terms along an orbit (Kepler's equation, the field's synthesis) are
    :func:`_orbit_term`'s: only the orbiting body's right-hand side compiles them."""
    if code == TERM_BODY_CONSTANT:
        return f * prog[v], f * prog[v + 1], f * prog[v + 2]
    if code == TERM_LINEAR_DRAG:
        m1, m2, m3 = _matrix_times(prog, v, w1, w2, w3)
        return -(f * m1), -(f * m2), -(f * m3)
    if code == TERM_QUADRATIC_DRAG:
        m1, m2, m3 = _matrix_times(prog, v, w1 * abs(w1), w2 * abs(w2), w3 * abs(w3))
        return -(f * m1), -(f * m2), -(f * m3)
    if code == TERM_INERTIAL_CONSTANT:
        m1, m2, m3 = _to_body(a, prog[v], prog[v + 1], prog[v + 2])
        return f * m1, f * m2, f * m3
    if code == TERM_GRAVITY_GRADIENT:
        return _gravity_gradient(f, prog, v, t, a)
    if code == TERM_EDDY_CURRENT:
        return _eddy_current(f, prog, v, t, w1, w2, w3, a)
    if code == TERM_USER:
        return _user(f, prog, v, t, w1, w2, w3, a)
    if code == TERM_FIELD_MOMENTS:
        return _field_moments(f, prog, v, t, w1, w2, w3, a)
    if code == TERM_GRAVITY_MOMENTS:
        return _gravity_moments(f, prog, v, t, a)
    return math.nan, math.nan, math.nan


@jit(INLINE)
def _orbit_term(
    code: int, f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float,
    a: Mat3,
) -> Vec3:  # fmt: skip
    """:func:`_term`, and the terms along an orbit (:data:`~tumble.kernels.codes.ORBIT_TERMS`)."""
    if code == TERM_ORBIT_EDDY:
        return _orbit_eddy(f, prog, v, t, w1, w2, w3, a)
    if code == TERM_ORBIT_GRAVITY:
        return _orbit_gravity(f, prog, v, t, a)
    if code == TERM_ORBIT_EDDY_HARMONIC:
        return _orbit_eddy_harmonic(f, prog, v, t, w1, w2, w3, a)
    return _term(code, f, prog, v, t, w1, w2, w3, a)


# The program's stride by term code, as a tuple numba freezes into the compiled code.
_SIZES = tuple(TERM_PAYLOAD.get(code, 0) for code in range(max(TERM_PAYLOAD) + 1))


@jit(INLINE)
def next_term(prog: FloatArray, i: int) -> int:
    """Index of the term after the one at ``prog[i]`` (its code), or −1 for an unknown code
    (the caller stops there: the term's moment is NaN)."""
    code = int(prog[i])
    if not 0 <= code < len(_SIZES) or _SIZES[code] == 0:
        return -1
    end = i + 2 + _SIZES[code]
    if code == TERM_USER:
        end += int(prog[i + 3])
    elif code == TERM_ORBIT_EDDY_HARMONIC:
        end += harmonic_size(int(prog[end]))
    return end


def _program_of(term: Callable[..., Vec3]) -> Callable[..., Vec3]:
    """The body moment of a program whose terms ``term`` evaluates."""

    @jit(INLINE)
    def program(
        prog: FloatArray, start: int, t: float, w1: float, w2: float, w3: float, a: Mat3
    ) -> Vec3:
        m1 = m2 = m3 = 0.0
        i = start + 1
        for _ in range(int(prog[start])):
            code = int(prog[i])
            d1, d2, d3 = term(code, prog[i + 1], prog, i + 2, t, w1, w2, w3, a)
            m1 += d1
            m2 += d2
            m3 += d3
            i = next_term(prog, i)
            if i < 0:
                break
        return m1, m2, m3

    return cast(Callable[..., Vec3], program)


_program = _program_of(_term)
"""Body moment of the program ``prog[start:]`` at body rate ω and attitude matrix a (no term
along an orbit: those are NaN)."""
_orbit_program = _program_of(_orbit_term)
"""The same for any program, the terms along an orbit included."""


@jit(KERNEL)
def torque_moment(prog: FloatArray, start: int, t: float, y: FloatArray, out: FloatArray) -> None:
    """Body moment of the torque program ``prog[start:]`` at state ``y = [ω, q]`` into
    out[0:3]; a term along an orbit gives NaN (:func:`orbit_torque_moment` has them)."""
    m1 = m2 = m3 = 0.0
    if prog[start] > 0:
        m1, m2, m3 = _program(prog, start, t, y[0], y[1], y[2], attitude_matrix(y))
    out[0], out[1], out[2] = m1, m2, m3


@jit(KERNEL)
def orbit_torque_moment(
    prog: FloatArray, start: int, t: float, y: FloatArray, out: FloatArray
) -> None:
    """:func:`torque_moment` for any program, the terms along an orbit included: compiled
    apart, so that the other right-hand sides do not compile Kepler's equation and the
    geomagnetic field."""
    m1 = m2 = m3 = 0.0
    if prog[start] > 0:
        m1, m2, m3 = _orbit_program(prog, start, t, y[0], y[1], y[2], attitude_matrix(y))
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
        a = _quaternion_matrix(q[kq, 0], q[kq, 1], q[kq, 2], q[kq, 3])
        out[k, 0], out[k, 1], out[k, 2] = _orbit_program(
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
            m1, m2, m3 = _orbit_program(prog, 0, t[j], w[k, 0], w[k, 1], w[k, 2], a)
            out[k, j, 0] = a[0] * m1 + a[1] * m2 + a[2] * m3
            out[k, j, 1] = a[3] * m1 + a[4] * m2 + a[5] * m3
            out[k, j, 2] = a[6] * m1 + a[7] * m2 + a[8] * m3
    return out


@jit(INLINE)
def quaternion_rates(y: FloatArray, out: FloatArray) -> None:
    """dq/dt = ½ q ⊗ (0, ω) into out[3:7] for y = [ω, q]."""
    w1, w2, w3, q0, q1, q2, q3 = y[0], y[1], y[2], y[3], y[4], y[5], y[6]
    out[3] = 0.5 * (-q1 * w1 - q2 * w2 - q3 * w3)
    out[4] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
    out[5] = 0.5 * (q0 * w2 - q1 * w3 + q3 * w1)
    out[6] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)
