"""The gravity-gradient moment on a body in a circular orbit, M = 3n² r̂ × (I r̂) in body axes,
with r̂ = cos u e₁ + sin u e₂ and u = n t + u₀ (:class:`tumble.torques.GravityGradientTorque`;
the standard first-order expansion of the gravity field over the body, e.g. Wertz (ed.),
*Spacecraft Attitude Determination and Control*, §17.2)."""

from __future__ import annotations

import math
from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.frames import to_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts, column_dot, sorted_moments, weighted
from tumble.kernels.terms.base import Term, principal_moments

LAYOUT = Layout(
    "gravity_gradient",
    (
        principal_moments("inertia unit"),
        Field("n", 1, "rad/time", "orbital mean motion", 0.0),
        Field("u0", 1, "rad", "argument of latitude at t = 0"),
        Field("basis", 9, "1", "rows e1 (ascending node), e2, orbit normal (inertial)"),
    ),
)
_AT = LAYOUT.at
_E1, _E2, _NORMAL = _AT.basis, _AT.basis + 3, _AT.basis + 6


@jit(INLINE)
def gradient_moment(g: float, prog: FloatArray, vi: int, r1: float, r2: float, r3: float) -> Vec3:
    """g r × (I r) for the body unit vector r and the principal moments at prog[vi : vi + 3]:
    the gravity-gradient moment of every term that has one, g [moment per inertia unit]
    collecting 3μ/r³ and the term's factor."""
    i1, i2, i3 = vec3(prog, vi)
    return g * (i3 - i2) * r2 * r3, g * (i1 - i3) * r3 * r1, g * (i2 - i1) * r1 * r2


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    n = prog[v + _AT.n]
    cu, su = math.cos(n * t + prog[v + _AT.u0]), math.sin(n * t + prog[v + _AT.u0])
    e1, e2 = vec3(prog, v + _E1), vec3(prog, v + _E2)
    r1, r2, r3 = to_body(
        a, cu * e1[0] + su * e2[0], cu * e1[1] + su * e2[1], cu * e1[2] + su * e2[2]
    )
    return gradient_moment(3.0 * n * n * f, prog, v + _AT.inertia, r1, r2, r3)


@jit(INLINE)
def phase_mean(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """Over the orbit: the moment at ⟨r̂ r̂ᵀ⟩ = ½(e₁e₁ᵀ + e₂e₂ᵀ)."""
    g = 3.0 * prog[v + _AT.n] ** 2 * f
    e1, e2 = vec3(prog, v + _E1), vec3(prog, v + _E2)
    x = gradient_moment(g, prog, v + _AT.inertia, *to_body(a, e1[0], e1[1], e1[2]))
    y = gradient_moment(g, prog, v + _AT.inertia, *to_body(a, e2[0], e2[1], e2[2]))
    return 0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1]), 0.5 * (x[2] + y[2])


@jit(INLINE)
def gravity_closed(
    p: FloatArray, vi: int, c: float, h1: float, h2: float, h3: float, ctx: Context
) -> Parts:
    """The Euler–Poinsot average of −c ĥ × (I ĥ) (moments at p[vi : vi + 3], user order):
    b = (c/2)(3⟨ℓᵀIℓ⟩ − tr I) on the m = 1 input ĥ₃(ĥ₁, ĥ₂) of ĥĥᵀ, nothing along L nor
    in the power (:mod:`tumble.kernels.triaxial_closed`)."""
    sq, F = ctx[3], ctx[8]
    i1, i2, i3 = vec3(p, vi)
    moments = sorted_moments(p, i1, i2, i3)
    b = 0.5 * c * (3.0 * weighted(moments, sq, (1.0, 1.0, 1.0)) - (i1 + i2 + i3))
    u1, u2, u3 = (column_dot(F, 0, h1, h2, h3), column_dot(F, 1, h1, h2, h3),
                  column_dot(F, 2, h1, h2, h3))  # fmt: skip
    return -b * u3 * u2, b * u3 * u1, 0.0, 0.0  # b L̂ × u₃(u₁, u₂)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The circular orbit's term: c = 3n²/2 (⟨r̂r̂ᵀ⟩ = ½(1 − ĥĥᵀ)), a fixed normal."""
    h1, h2, h3 = vec3(p, v + _NORMAL)
    return gravity_closed(p, v + _AT.inertia, 1.5 * p[v + _AT.n] ** 2, h1, h2, h3, ctx)


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    i1, i2, i3 = (float(x) for x in values["inertia"])
    n, u0, basis = values["n"], values["u0"], values["basis"]
    cu, su = hy.cos(n * t + u0), hy.sin(n * t + u0)
    r = frame.to_body([cu * float(basis[0, k]) + su * float(basis[1, k]) for k in range(3)])
    g = 3.0 * n * n * f
    return [g * (i3 - i2) * r[1] * r[2], g * (i1 - i3) * r[2] * r[0], g * (i2 - i1) * r[0] * r[1]]


TERM = Term(
    name="gravity_gradient",
    doc="the gravity gradient of a circular orbit, M = 3n² r̂ × (I r̂)",
    layout=LAYOUT,
    reads=frozenset({"attitude", "time"}),
    moment=moment,
    phase_mean=phase_mean,
    closed=closed,
    forcing_rate=lambda values: float(values["n"]),
    peer=peer,
)

TERMS = (TERM,)
