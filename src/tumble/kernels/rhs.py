"""The compiled right-hand sides, chosen by an integer kind, and their event functions.

Every right-hand side reads its parameters from one float array, so that one compiled
integrator serves every model: :mod:`tumble.integrate.dop853` specialises itself on the kind
as a compile-time constant, and the dispatch below folds away.

Kinds
-----
``KIND_RIGID_BODY``
    Euler's equations with quaternion kinematics under a sum of built-in torques (the free
    body, the resisting-medium moment (1.2) of Medvedev (1987), the eddy-current moment (1.3)
    of Martynenko (1979), and the torques of the averaging engine). State ``[ω, q]``,
    parameters ``[I1, I2, I3, torque program]``.
``KIND_ORBITING_BODY``
    The same under a program with terms compiled apart: along an orbit (the eddy current in the
    geomagnetic field, the gravity gradient of an elliptic orbit) or calling out (a user's numba
    function), so that only this kind compiles Kepler's equation, the field's synthesis and the
    opaque calls, which would keep the common kind from holding its parameters in registers.
``KIND_ROTATING_FIELD``
    The rotating-field form (1.5) of Martynenko (1979), state ``[z, Γ by rows]``.
``KIND_NONLINEAR_MOMENT``
    Euler's equations (1.1) of Serov (1991) with quaternions, under the moment
    A(a sinθ + b sin2θ) with damping.
``KIND_MEDIUM_AVERAGED``
    The averaged equations of Medvedev (1987): (2.2) for ``[k, ϑ]`` or (2.3) for ``[W, V]``,
    parameters ``[ε, a3, α, β, γ, δ, form]`` (form 0: (2.2), 1: (2.3)).
``KIND_FIELD_AVERAGED``
    The averaged equations of Martynenko (1979) in the vector form, state ``[L_ξ, r]`` with
    r = 2T/L², parameters ``[ε, sin²β, cos²β, I1, I2, I3]`` (sorted moments).
``KIND_NUTATION_AVERAGED``
    Volosov's averaged equations of Serov (1991) in the energy form, state ``[H, R, G, a, b]``
    (:mod:`tumble.kernels.nutation`).
``KIND_NUTATION_ENGINE``
    The same in the general engine's nutation setting, for a moment of the body rate only
    (:func:`tumble.kernels.nutation.nutation_engine`).
``KIND_SPINNER_AVERAGED``
    The general engine's spinner setting for a moment of the body rate only, state
    ``[k, ρ, σ, ϑ]``, parameters ``[κ, rtol, torque program]`` (:mod:`tumble.kernels.spinner`).
``KIND_TRIAXIAL_CLOSED``, ``KIND_TRIAXIAL_PHASE_MEANS``, ``KIND_TRIAXIAL_AVERAGED``
    The general engine's triaxial setting, state ``[L_ξ, r]`` (:mod:`tumble.kernels.triaxial`):
    in closed form, by the exact phase means of built-in terms, or by the product rule for any
    program (a user's numba function).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, cast

import numpy as np
from numba import types
from numba.extending import overload

from tumble._typing import FloatArray
from tumble.kernels import codes
from tumble.kernels.elliptic import elliprd, elliprf
from tumble.kernels.frames import quaternion_rates
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, OVERLOAD, compile_lock, jit
from tumble.kernels.layout import mat_vec, vec3
from tumble.kernels.nutation import (
    nutation_averaged,
    nutation_engine,
    pressure,
    separatrix_distance,
)
from tumble.kernels.params import (
    FIELD_AVERAGED,
    MEDIUM_AVERAGED,
    NONLINEAR_MOMENT,
    RIGID_BODY,
    ROTATING_FIELD,
    TRIAXIAL_AVERAGED,
)
from tumble.kernels.spinner import spinner_averaged
from tumble.kernels.torque import orbit_torque_moment, torque_moment
from tumble.kernels.triaxial import triaxial_averaged, triaxial_closed, triaxial_phase_means

__all__ = [
    "euler_quaternion",
    "evaluate",
    "evaluate_event",
    "evaluate_repeatedly",
    "event",
    "rhs",
    "rigid_body",
    "rotating_field",
    "symmetric_body",
]


_RB, _RF, _NM = RIGID_BODY.at, ROTATING_FIELD.at, NONLINEAR_MOMENT.at
_MA, _FA = MEDIUM_AVERAGED.at, FIELD_AVERAGED.at
_RB_PROGRAM = RIGID_BODY.size
_FA_I2 = FIELD_AVERAGED.at.inertia + 1
_TA_I2 = TRIAXIAL_AVERAGED.at.inertia + 1


@jit(INLINE)
def _euler(
    y: FloatArray, i1: float, i2: float, i3: float, m1: float, m2: float, m3: float,
    out: FloatArray,
) -> None:  # fmt: skip
    """I ω' = (I ω) × ω + M and q' = ½ q ⊗ (0, ω) for y = [ω, q] and the body moment M."""
    w1, w2, w3 = y[0], y[1], y[2]
    out[0] = ((i2 - i3) * w2 * w3 + m1) / i1
    out[1] = ((i3 - i1) * w3 * w1 + m2) / i2
    out[2] = ((i1 - i2) * w1 * w2 + m3) / i3
    quaternion_rates(y, out)


@jit(INLINE)
def _rigid_body(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """Euler's equations with quaternions under the torque program; p = [I1, I2, I3,
    torque program]."""
    torque_moment(p, _RB_PROGRAM, t, y, out)
    i1, i2, i3 = vec3(p, _RB.inertia)
    _euler(y, i1, i2, i3, out[0], out[1], out[2], out)


@jit(INLINE)
def _orbiting_body(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """:func:`_rigid_body` for a program with terms along an orbit."""
    orbit_torque_moment(p, _RB_PROGRAM, t, y, out)
    i1, i2, i3 = vec3(p, _RB.inertia)
    _euler(y, i1, i2, i3, out[0], out[1], out[2], out)


@jit(ENTRY)
def rigid_body(t: float, y: FloatArray, p: FloatArray) -> FloatArray:
    """dy/dt of Euler's equations under any torque program (the terms along an orbit
    included), from Python: the integrator's code."""
    out = np.empty_like(y)
    _orbiting_body(t, y, p, out)
    return out


@jit(ENTRY)
def euler_quaternion(y: FloatArray, inertia: FloatArray, moment: FloatArray) -> FloatArray:
    """dy/dt of Euler's equations with quaternions under a body moment computed elsewhere (a
    Python torque): the same equations as the integrator's."""
    out = np.empty_like(y)
    _euler(y, inertia[0], inertia[1], inertia[2], moment[0], moment[1], moment[2], out)
    return out


@jit(INLINE)
def _rotating_field(y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """Martynenko (1979) eq. (1.5), with the sign of its field term corrected:
    I z′ = I z × z + ε Γᵀ ĥĥ (Γ z − ξ3), Γ′ = Γ ẑ − ξ̂3 Γ; p = [I1, I2, I3, ε, ĥĥ by rows]."""
    i1, i2, i3 = vec3(p, _RF.inertia)
    eps = p[_RF.eps]
    z1, z2, z3 = y[0], y[1], y[2]
    g = y[3:12]
    r1 = g[0] * z1 + g[1] * z2 + g[2] * z3
    r2 = g[3] * z1 + g[4] * z2 + g[5] * z3
    r3 = g[6] * z1 + g[7] * z2 + g[8] * z3 - 1.0
    e1, e2, e3 = mat_vec(p, _RF.hh, r1, r2, r3)
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


@jit(ENTRY)
def rotating_field(y: FloatArray, p: FloatArray) -> FloatArray:
    """dy/dτ of (1.5) from Python: the same code as the integrator's, for real or complex
    states (complex-step Jacobians)."""
    out = np.empty_like(y)
    _rotating_field(y, p, out)
    return out


@jit(INLINE)
def _symmetric_body(
    y: FloatArray, mu: float, a: float, b: float, ed: float, en: float, out: FloatArray
) -> None:
    """Serov (1991) eq. (1.1) in quaternions under M0 = a sinθ + b sin2θ (per A), written
    without Euler angles as (a + 2b cos θ)(e_z × e3), with the damping −ed (p, q, 0) and
    −en (0, 0, r)."""
    w1, w2, w3 = y[0], y[1], y[2]
    q0, q1, q2, q3 = y[3], y[4], y[5], y[6]
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    # e_z in body axes: the third row of the body → inertial matrix.
    ex = 2.0 * (q1 * q3 - q0 * q2) / n2
    ey = 2.0 * (q2 * q3 + q0 * q1) / n2
    ez = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / n2
    m0 = a + 2.0 * b * ez
    out[0] = (1.0 - mu) * w2 * w3 + m0 * ey - ed * w1
    out[1] = (mu - 1.0) * w3 * w1 - m0 * ex - ed * w2
    out[2] = -en * w3
    quaternion_rates(y, out)


@jit(INLINE)
def _nonlinear_moment(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """(1.1) with a, b scaled by the pressure Q(εt)/Q(0); p = [μ, a0, b0, ε, d, ν, pressure
    kind, Q(0), table size n, τ_1..n, Q_1..n]."""
    eps = p[_NM.eps]
    q = pressure(p, eps * t)
    mu, a, b = p[_NM.mu], p[_NM.a] * q, p[_NM.b] * q
    _symmetric_body(y, mu, a, b, eps * p[_NM.d], eps * p[_NM.nu], out)


@jit(ENTRY)
def symmetric_body(
    y: FloatArray, mu: float, a: float, b: float, ed: float, en: float
) -> FloatArray:
    """dy/dt of (1.1) from Python, at given a, b: the same code as the integrator's."""
    out = np.empty_like(y)
    _symmetric_body(y, mu, a, b, ed, en, out)
    return out


@jit(INLINE)
def _medium_averaged(y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """Averaged equations of Medvedev (1987) in τ: (2.2) for y = [k, ϑ] (the a3 term of the
    ϑ-equation as a3 sin ϑ / k, regular at ϑ = π/2), or (2.3) for y = [W, V]; a third
    component is the mean proper rotation φ̄, dφ̄/dτ = −κW/(1+κ) + ε⟨m1 cos φ − m2 sin φ⟩/V
    (the mean of (1.3)'s φ-equation)."""
    eps, a3, al = p[_MA.eps], p[_MA.a3], p[_MA.alpha]
    be, ga, de = p[_MA.beta], p[_MA.gamma], p[_MA.delta]
    if p[_MA.form] == 0.0:
        k, theta = y[0], y[1]
        c, s = math.cos(theta), math.sin(theta)
        ac, as_ = abs(c), abs(s)
        out[0] = eps * (
            a3 * c - k * (al * s * s + be * c * c + k * (ga * s * s * as_ + de * c * c * ac))
        )
        out[1] = -eps * (a3 * s / k + (al - be + k * (ga * as_ - de * ac)) * s * c)
        W, V = k * c, k * s
    else:
        W, V = y[0], y[1]
        out[0] = eps * (a3 - be * W - de * W * abs(W))
        out[1] = -eps * (al * V + ga * V * V)
    if y.shape[0] == 3:
        kappa = p[_MA.kappa]
        out[2] = -kappa * W / (1.0 + kappa) + eps * (p[_MA.phase_b] + p[_MA.phase_s] * V)


@jit(KERNEL)
def _mean_square_rate(i1: float, i2: float, i3: float, r: float) -> float:
    """⟨|z|²⟩/L² of the Euler–Poinsot motion with 2T/L² = r (sorted moments, r inside
    [1/I3, 1/I1]): :func:`tumble.unperturbed.euler_poinsot.mean_square_rate` at L = 1."""
    d1, d2, d3 = max(1.0 - r * i1, 0.0), 1.0 - r * i2, max(r * i3 - 1.0, 0.0)
    tol = codes.DEGENERATE_RTOL * i3
    if i3 - i1 <= 2.0 * tol:  # a sphere
        return 1.0 / (i2 * i2)
    x3 = d2 >= 0.0 if abs(d2) <= codes.SEPARATRIX_RTOL else d2 > 0.0
    m, mc = 0.0, 1.0
    if i2 - i1 <= tol:  # symmetric about x3
        x3 = True
    elif i3 - i2 <= tol:  # symmetric about x1
        x3 = False
    else:
        if x3:
            den = (i3 - i2) * d1
            m, mc = (i2 - i1) * d3 / den, (i3 - i1) * d2 / den
        else:
            den = (i2 - i1) * d3
            m, mc = (i3 - i2) * d1 / den, -(i3 - i1) * d2 / den
        if mc < codes.MC_FLOOR:
            m, mc = 1.0, 0.0
        else:
            m, mc = min(max(m, 0.0), 1.0), min(mc, 1.0)
    if mc == 0.0:  # on the separatrix: both period averages vanish (E/K → 0)
        cn2, dn2 = 0.0, 0.0
    else:
        rf = elliprf(0.0, mc, 1.0)
        rd_over_3rf = elliprd(0.0, mc, 1.0) / (3.0 * rf)
        dn2 = 1.0 - m * rd_over_3rf  # E/K, E = R_F − (m/3) R_D
        cn2 = 1.0 - rd_over_3rf if m <= 0.5 else (dn2 - mc) / m
    w1 = (i2 - i1) * d3 / (i1 * (i3 - i1))
    w3 = (i3 - i2) * d1 / (i3 * (i3 - i1))
    if x3:
        return r / i2 + (w1 * cn2 - w3 * dn2) / i2
    return r / i2 + (w1 * dn2 - w3 * cn2) / i2


@jit(INLINE)
def _field_averaged(y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """The vector form of the averaged equations of Martynenko (1979):
    dL_ξ/dτ = ε(r D L_ξ + sin²β ξ3), dr/dτ = (εA/2)(r² − ⟨z²⟩/L²), D = −diag(a, a, sin²β),
    a = (1 + cos²β)/2, A = 2(1 + cos²β) + (1 − 3cos²β) sin²ρ; NaN beyond a pure rotation
    (r outside [1/I3, 1/I1] by more than the margin), so that the step is rejected."""
    eps, s2, c2 = p[_FA.eps], p[_FA.s2], p[_FA.c2]
    i1, i2, i3 = vec3(p, _FA.inertia)
    lo, hi = 1.0 / i3, 1.0 / i1
    margin = codes.REACHED_MARGIN * hi
    r = y[3]
    if not lo - margin <= r <= hi + margin:
        for j in range(4):
            out[j] = math.nan
        return
    r = min(max(r, lo), hi)
    l1, l2, l3 = y[0], y[1], y[2]
    big = l1 * l1 + l2 * l2 + l3 * l3
    sin2_rho = (l1 * l1 + l2 * l2) / big if big > 0.0 else 0.0
    a = 0.5 * (1.0 + c2)
    out[0] = -eps * r * a * l1
    out[1] = -eps * r * a * l2
    out[2] = eps * (s2 - r * s2 * l3)
    big_a = 2.0 * (1.0 + c2) + (1.0 - 3.0 * c2) * sin2_rho
    out[3] = 0.5 * eps * big_a * (r * r - _mean_square_rate(i1, i2, i3, r))


@jit(INLINE)
def _any_kind(kind: int, t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """:func:`rhs` for a kind known only at run time (NaN for an unknown one, so that the
    integration fails)."""
    if kind == codes.KIND_RIGID_BODY:
        _rigid_body(t, y, p, out)
    elif kind == codes.KIND_ORBITING_BODY:
        _orbiting_body(t, y, p, out)
    elif kind == codes.KIND_ROTATING_FIELD:
        _rotating_field(y, p, out)
    elif kind == codes.KIND_NONLINEAR_MOMENT:
        _nonlinear_moment(t, y, p, out)
    elif kind == codes.KIND_MEDIUM_AVERAGED:
        _medium_averaged(y, p, out)
    elif kind == codes.KIND_FIELD_AVERAGED:
        _field_averaged(y, p, out)
    elif kind == codes.KIND_NUTATION_AVERAGED:
        nutation_averaged(t, y, p, out)
    elif kind == codes.KIND_SPINNER_AVERAGED:
        spinner_averaged(t, y, p, out)
    elif kind == codes.KIND_NUTATION_ENGINE:
        nutation_engine(t, y, p, out)
    elif kind == codes.KIND_TRIAXIAL_AVERAGED:
        triaxial_averaged(t, y, p, out)
    elif kind == codes.KIND_TRIAXIAL_PHASE_MEANS:
        triaxial_phase_means(t, y, p, out)
    elif kind == codes.KIND_TRIAXIAL_CLOSED:
        triaxial_closed(t, y, p, out)
    else:
        for j in range(y.size):
            out[j] = math.nan


def rhs(kind: int, t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """dy/dt of the right-hand side ``kind`` with parameters ``p`` into ``out``.

    In compiled code an overload: where ``kind`` is a compile-time constant (the integrator
    specialised on one kind, :func:`tumble.integrate.dop853.driver._specialised`) it is that
    kind's kernel alone, so that compiling an integrator types and lowers one right-hand side,
    not all of them; otherwise the dispatch on the run-time kind. From Python: that dispatch.
    """
    cast(Any, _any_kind).py_func(kind, t, y, p, out)


def _with_time(kernel: Callable[..., None]) -> Callable[..., None]:
    """A kernel of (y, p, out) as one of (t, y, p, out)."""

    @jit(INLINE)
    def wrapped(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
        kernel(y, p, out)

    return wrapped


_BY_KIND: dict[int, Callable[..., None]] = {
    codes.KIND_RIGID_BODY: _rigid_body,
    codes.KIND_ORBITING_BODY: _orbiting_body,
    codes.KIND_ROTATING_FIELD: _with_time(_rotating_field),
    codes.KIND_NONLINEAR_MOMENT: _nonlinear_moment,
    codes.KIND_MEDIUM_AVERAGED: _with_time(_medium_averaged),
    codes.KIND_FIELD_AVERAGED: _with_time(_field_averaged),
    codes.KIND_NUTATION_AVERAGED: nutation_averaged,
    codes.KIND_SPINNER_AVERAGED: spinner_averaged,
    codes.KIND_NUTATION_ENGINE: nutation_engine,
    codes.KIND_TRIAXIAL_AVERAGED: triaxial_averaged,
    codes.KIND_TRIAXIAL_PHASE_MEANS: triaxial_phase_means,
    codes.KIND_TRIAXIAL_CLOSED: triaxial_closed,
}


@overload(rhs, prefer_literal=True, jit_options=cast(Any, OVERLOAD))
def _rhs_by_kind(kind: Any, t: Any, y: Any, p: Any, out: Any) -> Callable[..., None]:
    if isinstance(kind, types.IntegerLiteral) and kind.literal_value in _BY_KIND:
        one = _BY_KIND[kind.literal_value]

        # (numba compares the parameters, annotations included, with the typing function's)
        def impl(kind: Any, t: Any, y: Any, p: Any, out: Any) -> None:
            one(t, y, p, out)

        return impl

    def dispatch(kind: Any, t: Any, y: Any, p: Any, out: Any) -> None:
        _any_kind(kind, t, y, p, out)

    return dispatch


@jit(INLINE)
def _theta_dot(t: float, y: FloatArray, p: FloatArray) -> float:
    """θ' sinθ = ω·(e_z × e3) of the nonlinear-moment quaternion form: the sign of θ'."""
    q0, q1, q2, q3 = y[3], y[4], y[5], y[6]
    n2 = q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3
    ex = 2.0 * (q1 * q3 - q0 * q2) / n2
    ey = 2.0 * (q2 * q3 + q0 * q1) / n2
    return y[0] * ey - y[1] * ex


@jit(INLINE)
def _field_separatrix(t: float, y: FloatArray, p: FloatArray) -> float:
    """r − 1/I2 of the rotating field's averaged vector form."""
    return y[3] - 1.0 / p[_FA_I2]


@jit(INLINE)
def _nutation_separatrix(t: float, y: FloatArray, p: FloatArray) -> float:
    """The distance of the energy form's state from the separatrix."""
    return separatrix_distance(y)


@jit(INLINE)
def _equator(t: float, y: FloatArray, p: FloatArray) -> float:
    """cos ϑ of a spinner's averaged state [k, ρ, σ, ϑ]."""
    return math.cos(y[3])


@jit(INLINE)
def _triaxial_separatrix(t: float, y: FloatArray, p: FloatArray) -> float:
    """r − 1/I2 of the triaxial engine."""
    return y[3] - 1.0 / p[_TA_I2]


_BY_EVENT: dict[int, Callable[..., float]] = {
    codes.EVENT_THETA_DOT: _theta_dot,
    codes.EVENT_FIELD_SEPARATRIX: _field_separatrix,
    codes.EVENT_NUTATION_SEPARATRIX: _nutation_separatrix,
    codes.EVENT_EQUATOR: _equator,
    codes.EVENT_TRIAXIAL_SEPARATRIX: _triaxial_separatrix,
}


@jit(INLINE)
def _any_event(code: int, t: float, y: FloatArray, p: FloatArray) -> float:
    """:func:`event` for a code known only at run time (1 for ``EVENT_NONE`` or an unknown
    one: no zero)."""
    if code == codes.EVENT_THETA_DOT:
        return _theta_dot(t, y, p)
    if code == codes.EVENT_FIELD_SEPARATRIX:
        return _field_separatrix(t, y, p)
    if code == codes.EVENT_NUTATION_SEPARATRIX:
        return _nutation_separatrix(t, y, p)
    if code == codes.EVENT_EQUATOR:
        return _equator(t, y, p)
    if code == codes.EVENT_TRIAXIAL_SEPARATRIX:
        return _triaxial_separatrix(t, y, p)
    return 1.0


def event(code: int, t: float, y: FloatArray, p: FloatArray) -> float:
    """The event function ``code`` (``EVENT_*``) at (t, y); the integrator locates its sign
    changes.

    In compiled code an overload, as :func:`rhs`: for a code known at compile time (the
    integrator's event function, :func:`tumble.integrate.dop853.functions.event_function`)
    that event's function alone. From Python: the dispatch on the run-time code.
    """
    return float(cast(Any, _any_event).py_func(code, t, y, p))


@overload(event, prefer_literal=True, jit_options=cast(Any, OVERLOAD))
def _event_by_code(code: Any, t: Any, y: Any, p: Any) -> Callable[..., float]:
    if isinstance(code, types.IntegerLiteral) and code.literal_value in _BY_EVENT:
        one = _BY_EVENT[code.literal_value]

        def impl(code: Any, t: Any, y: Any, p: Any) -> float:
            return one(t, y, p)

        return impl

    def dispatch(code: Any, t: Any, y: Any, p: Any) -> float:
        return _any_event(code, t, y, p)

    return dispatch


_EVALUATORS: dict[tuple[str, int], Callable[..., Any]] = {}


def _one_kind(what: str, number: int) -> Callable[..., Any]:
    """The entry ``what`` of :func:`evaluate`, :func:`evaluate_event` or
    :func:`evaluate_repeatedly` for the kind (event code) ``number`` alone, compiled on first
    use and cached on disk.

    ``number`` is a constant of the closure, which numba types as a literal: the dispatch of
    :func:`rhs` (:func:`event`) folds to that kind's kernel, as in the integrator
    (:func:`tumble.integrate.dop853.functions.kind_functions`). An entry taking the kind at run
    time would compile every kind's kernel at its first call (a minute and a half from a cold
    cache) to evaluate one.
    """
    key = (what, number)
    got = _EVALUATORS.get(key)
    if got is not None:
        return got
    if what == "rhs":

        def one(t: float, y: FloatArray, p: FloatArray) -> FloatArray:
            out = np.empty(y.size)
            rhs(number, t, y, p, out)
            return out

    elif what == "event":

        def one(t: float, y: FloatArray, p: FloatArray) -> float:  # type: ignore[misc]
            return event(number, t, y, p)

    else:

        def one(  # type: ignore[misc]
            t: float, y: FloatArray, p: FloatArray, n: int, feedback: float
        ) -> FloatArray:
            state = y.copy()
            out = np.empty(y.size)
            for _ in range(n):
                rhs(number, t, state, p, out)
                state[0] += feedback * out[0]
            return out

    dispatcher = jit(ENTRY)(one)

    def first(*args: Any) -> Any:
        # The first call compiles (another process compiling the same: load it after).
        with compile_lock(f"{what}-{number}"):
            value = dispatcher(*args)
        _EVALUATORS[key] = dispatcher
        return value

    _EVALUATORS[key] = first
    return first


def evaluate_event(code: int, t: float, y: FloatArray, p: FloatArray) -> float:
    """The event function ``code`` at (t, y), from Python: the integrator's own code, compiled
    for that code alone."""
    return float(_one_kind("event", int(code))(float(t), y, p))


def evaluate(kind: int, t: float, y: FloatArray, p: FloatArray) -> FloatArray:
    """dy/dt of the right-hand side ``kind`` at one state, from Python: the integrator's own
    kernel, compiled for that kind alone (NaN for an unknown kind, without compiling the
    dispatch over every kind that compiled code falls back on)."""
    if int(kind) not in _BY_KIND:
        return np.full(np.shape(y)[0], math.nan)
    return cast(FloatArray, _one_kind("rhs", int(kind))(float(t), y, p))


def evaluate_repeatedly(
    kind: int, t: float, y: FloatArray, p: FloatArray, n: int, feedback: float
) -> FloatArray:
    """dy/dt of the right-hand side ``kind`` evaluated ``n`` times in compiled code (the
    benchmark's cost of one evaluation, without the call from Python); the last result.

    Each evaluation adds ``feedback`` times the previous derivative to the state (pass 0.0):
    a dependence the compiler cannot see through, so that it cannot fold the repeated,
    identical evaluations into one. Compiled for that kind alone, as the integrator is.
    """
    if int(kind) not in _BY_KIND:
        return np.full(np.shape(y)[0], math.nan)
    entry = _one_kind("repeat", int(kind))
    return cast(FloatArray, entry(float(t), y, p, int(n), float(feedback)))
