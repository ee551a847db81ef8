"""The moment of sunlight on a faceted body: absorption, specular and diffuse reflection and the
instantaneous thermal re-emission of every facet lit by the Sun (the YORP moment), with the
Earth's shadow.

A facet of area A, outward normal n and centre r (body axes, from the centre of mass), lit from
the body direction s of the Sun at ĉ = n·s > 0 under the pressure P, feels
f = −P ĉ [ks s + (kp ĉ + kd) n] with ks = A (1 − ρs), kp = 2 A ρs, kd = ⅔ A (ρd + α κ)
(:mod:`tumble.space.radiation`, which states the model and its sources); the moment is
Σ r × f. Two terms:

* ``solar_radiation``: along the orbit: the Sun's direction and distance at the epoch plus t
  (:func:`tumble.kernels.sun.sun_at`), seen from the body's place on the orbit, the pressure
  Φ/c (1 AU/d)² and the visible fraction of the Sun (cylindrical or conical shadow): the full
  equations;
* ``solar_radiation_mean``: the same averaged over the orbit at a fixed attitude, with the
  illumination max(0, ĉ) expanded to second order in Fourier series (Benson and Scheeres,
  *J. Guid. Control Dyn.* 44(4), 2021): the cubic polynomial P (C⁰ + C¹ s + C² s s + C³ s s s)
  of the Sun's body direction (:func:`tumble.space.radiation.expanded_coefficients`), the Sun
  seen from the Earth, weighted by the fraction of the orbit in sunlight (the cylindrical
  shadow's, :func:`tumble.kernels.sun.eclipse_fraction`): what the averaged equations average
  over the Euler–Poinsot motion, in closed form (:func:`closed`).

**The closed form.** With A = F Rz(χ) G (F's third column L̂, G's rows e₁, e₂, ℓ in the body),
the Sun's body direction is s = Gᵀ Rz(χ)ᵀ s_L, s_L = Fᵀ ŝ, and the moment in the L-frame is
Rz(χ) G M(s): both are trigonometric polynomials of degree ≤ 4 in χ (the moment cubic in s,
one more rotation outside), which the trapezoidal rule on five angles averages exactly, with
any e₁, e₂ (a turn of them about ℓ is a shift of χ). The χ-means are polynomials of degree
≤ 4 in ℓ, and so is the power ω·M (ω = L I⁻¹ ℓ). Over the polhode ℓ = (A_c cn u, A_s sn u,
A_d dn u): the four signs of (cn, sn) (u → −u, 2K − u, 2K + u) leave it unchanged, and the
mean of the sign-averaged polynomial is an even part, a polynomial of degree ≤ 2 in x = sn²,
plus dn times one of degree ≤ 1, the two told apart by the sign of dn. The even part's mean is
its values at x = 0, ½, 1 weighted by the means of the Lagrange polynomials (from ⟨x⟩, ⟨x²⟩),
the odd part's its value at x = ½ times ⟨dn⟩ (as ⟨dn (1 − 2x)⟩ = 0). Sixteen directions ℓ of
five angles each: eighty evaluations of the cubic, exact to round-off for the expanded
illumination, whatever the number of facets.

The orbiting body's scenario switches it on with ``[torques] solar_radiation = "conical"`` or
``"cylindrical"`` (the shadow of the full equations) and its ``[surface]`` table of facets.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import ParameterError
from tumble.kernels.astro import AU, SOLAR_FLUX, SPEED_OF_LIGHT
from tumble.kernels.elliptic import agm, jacobi_quarter
from tumble.kernels.frames import to_body
from tumble.kernels.jit import INLINE, KERNEL, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, mat3
from tumble.kernels.lframe import Context, Parts, column_dot
from tumble.kernels.params import TRIAXIAL_AVERAGED
from tumble.kernels.space import ORBIT, orbit_at, perifocal
from tumble.kernels.sun import conical_shadow, cylindrical_shadow, eclipse_fraction, sun_at
from tumble.kernels.terms.base import ORBIT_FIELD, OrbitContext, OrbitKey, Term

__all__ = [
    "FACET",
    "ILLUMINATION",
    "ILLUMINATIONS",
    "LAYOUT",
    "MEAN_LAYOUT",
    "SHADOWS",
    "TERMS",
    "build",
    "coefficients",
    "cubic",
    "exact_illumination",
    "expanded_average",
    "expanded_tensors",
    "lit_average",
    "lit_facets",
    "monomials",
    "principal",
]

SHADOWS = {"none": 0.0, "cylindrical": 1.0, "conical": 2.0}
"""The shadow of the full equations and its code in the payload."""
ILLUMINATIONS = ("exact", "expanded")
"""The illumination of the averaged equations: max(0, ĉ) itself, or its Fourier series to
second order (module notes)."""

_SUN = (
    Field("jd0", 1, "d", "Julian date at t = 0"),
    Field("days", 1, "d/time", "days per unit of model time", 0.0),
    Field("pressure", 1, "N/m²·T0²/I0", "the radiation pressure at 1 AU in the model's units", 0.0),
)
LAYOUT = Layout(
    "solar_radiation",
    (
        ORBIT_FIELD,
        *_SUN,
        Field("shadow", 1, "1", "0: none; 1: cylindrical; 2: conical", 0.0, 2.0),
        Field("count", 1, "1", "number of facets", 0.0),
    ),
    tail="facets",  # FACET per facet
)
FACET = Layout(
    "facet",
    (
        Field("normal", 3, "1", "outward unit normal n, principal axes"),
        Field("centre", 3, "m", "centre r, from the centre of mass, principal axes"),
        Field("ks", 1, "m²", "A (1 − ρs)", 0.0),
        Field("kp", 1, "m²", "2 A ρs", 0.0),
        Field("kd", 1, "m²", "⅔ A (ρd + α κ)"),
        Field("arm", 3, "m", "r × n"),
    ),
)
"""A facet's entry in the full term's tail."""
_TERMS_PER_AXIS = 20  # the monomials of degree ≤ 3 in three variables
MEAN_LAYOUT = Layout(
    "solar_radiation_mean",
    (
        ORBIT_FIELD,
        *_SUN,
        Field("shadow", 1, "1", "0: none; 1: the cylindrical shadow's eclipse fraction", 0.0, 1.0),
        Field(
            "coefficients", 3 * _TERMS_PER_AXIS, "m³", "the cubic M(s)/P by axis, on monomials()"
        ),
        Field("exact", 1, "1", "0: the expanded illumination; 1: the exact one", 0.0, 1.0),
        Field("count", 1, "1", "number of facets", 0.0),
    ),
    tail="facets",  # FACET per facet, as the full term's
)
_AT, _MEAN, _F, _O = LAYOUT.at, MEAN_LAYOUT.at, FACET.at, ORBIT.at
_FACETS = LAYOUT.size
_MEAN_FACETS = MEAN_LAYOUT.size
_FACET = FACET.size
_Q = TRIAXIAL_AVERAGED.at.sorting


def monomials() -> tuple[tuple[int, ...], ...]:
    """The exponents (of s1, s2, s3) of the 20 monomials the mean term's coefficients multiply,
    in the order of :func:`cubic`."""
    return (
        (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1),
        (2, 0, 0), (0, 2, 0), (0, 0, 2), (1, 1, 0), (1, 0, 1), (0, 1, 1),
        (3, 0, 0), (0, 3, 0), (0, 0, 3), (2, 1, 0), (2, 0, 1), (1, 2, 0), (0, 2, 1), (1, 0, 2),
        (0, 1, 2), (1, 1, 1),
    )  # fmt: skip


@jit(INLINE)
def _axis(c: FloatArray, k: int, s1: float, s2: float, s3: float, q: Vec3, r: Vec3) -> float:
    """One axis of the cubic: Σ c[k + j] × monomial j, with q = (s1², s2², s3²) and
    r = (s1 s2, s1 s3, s2 s3)."""
    return (
        c[k] + c[k + 1] * s1 + c[k + 2] * s2 + c[k + 3] * s3
        + c[k + 4] * q[0] + c[k + 5] * q[1] + c[k + 6] * q[2]
        + c[k + 7] * r[0] + c[k + 8] * r[1] + c[k + 9] * r[2]
        + s1 * (c[k + 10] * q[0] + c[k + 13] * r[0] + c[k + 14] * r[1] + c[k + 15] * q[1]
                + c[k + 17] * q[2] + c[k + 19] * r[2])
        + s2 * (c[k + 11] * q[1] + c[k + 16] * r[2] + c[k + 18] * q[2])
        + s3 * c[k + 12] * q[2]
    )  # fmt: skip


@jit(INLINE)
def cubic(c: FloatArray, k: int, s1: float, s2: float, s3: float) -> Vec3:
    """M(s)/P: the three axes' cubics at c[k:] (:func:`monomials`)."""
    q = (s1 * s1, s2 * s2, s3 * s3)
    r = (s1 * s2, s1 * s3, s2 * s3)
    return (
        _axis(c, k, s1, s2, s3, q, r),
        _axis(c, k + _TERMS_PER_AXIS, s1, s2, s3, q, r),
        _axis(c, k + 2 * _TERMS_PER_AXIS, s1, s2, s3, q, r),
    )


@jit(INLINE)
def lit_facets(
    prog: FloatArray, k: int, count: int, p: float, b1: float, b2: float, b3: float
) -> Vec3:
    """Σ r × f over the ``count`` facets at prog[k:] (:data:`FACET`) lit from the body direction
    b under the pressure p: f = −p ĉ [ks b + (kp ĉ + kd) n] where ĉ = n·b > 0."""
    m1 = m2 = m3 = 0.0
    for _ in range(count):
        n1, n2, n3 = prog[k + _F.normal], prog[k + _F.normal + 1], prog[k + _F.normal + 2]
        c = n1 * b1 + n2 * b2 + n3 * b3
        if c > 0.0:
            along_n = prog[k + _F.kp] * c + prog[k + _F.kd]
            g1 = -p * c * (prog[k + _F.ks] * b1 + along_n * n1)
            g2 = -p * c * (prog[k + _F.ks] * b2 + along_n * n2)
            g3 = -p * c * (prog[k + _F.ks] * b3 + along_n * n3)
            x1, x2, x3 = prog[k + _F.centre], prog[k + _F.centre + 1], prog[k + _F.centre + 2]
            m1 += x2 * g3 - x3 * g2
            m2 += x3 * g1 - x1 * g3
            m3 += x1 * g2 - x2 * g1
        k += _FACET
    return m1, m2, m3


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f Σ r × f_facet at the body's place on the orbit (module notes)."""
    r, _ = orbit_at(prog, v + _AT.orbit, t)
    s1, s2, s3, distance = sun_at(prog[v + _AT.jd0] + prog[v + _AT.days] * t)
    shadow = prog[v + _AT.shadow]
    light = 1.0
    if shadow == 1.0:
        light = cylindrical_shadow(r[0], r[1], r[2], s1, s2, s3)
    elif shadow == 2.0:
        light = conical_shadow(r[0], r[1], r[2], s1, s2, s3, distance)
    if light == 0.0:
        return 0.0, 0.0, 0.0
    d1, d2, d3 = distance * s1 - r[0], distance * s2 - r[1], distance * s3 - r[2]  # to the Sun
    d = math.sqrt(d1 * d1 + d2 * d2 + d3 * d3)
    p = f * prog[v + _AT.pressure] * (AU / d) ** 2 * light
    b1, b2, b3 = to_body(a, d1 / d, d2 / d, d3 / d)
    return lit_facets(prog, v + _FACETS, int(prog[v + _AT.count]), p, b1, b2, b3)


@jit(INLINE)
def _sun_mean(prog: FloatArray, v: int, t: float) -> tuple[float, float, float, float]:
    """(ŝ, scale): the Sun's direction from the Earth at t and the orbit-averaged pressure
    P (1 AU/d)² (1 − the eclipse fraction)."""
    s1, s2, s3, distance = sun_at(prog[v + _MEAN.jd0] + prog[v + _MEAN.days] * t)
    scale = prog[v + _MEAN.pressure] * (AU / distance) ** 2
    if prog[v + _MEAN.shadow] == 1.0:
        o = v + _MEAN.orbit
        raan = prog[o + _O.raan] + prog[o + _O.raan_rate] * t
        argp = prog[o + _O.argp] + prog[o + _O.argp_rate] * t
        P, Q, W = perifocal(raan, argp, prog[o + _O.i])
        sp = P[0] * s1 + P[1] * s2 + P[2] * s3
        sq = Q[0] * s1 + Q[1] * s2 + Q[2] * s3
        sn = W[0] * s1 + W[1] * s2 + W[2] * s3
        scale *= 1.0 - eclipse_fraction(prog[o + _O.a], prog[o + _O.e], sp, sq, sn)
    return s1, s2, s3, scale


@jit(INLINE)
def mean_moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f P(t) (1 − eclipse fraction) M(Aᵀ ŝ(t))/P with the expanded or the exact
    illumination."""
    s1, s2, s3, scale = _sun_mean(prog, v, t)
    b1, b2, b3 = to_body(a, s1, s2, s3)
    if prog[v + _MEAN.exact] == 1.0:
        count = int(prog[v + _MEAN.count])
        return lit_facets(prog, v + _MEAN_FACETS, count, f * scale, b1, b2, b3)
    m1, m2, m3 = cubic(prog, v + _MEAN.coefficients, b1, b2, b3)
    g = f * scale
    return g * m1, g * m2, g * m3


_CHI = 5  # precession angles: exact for the degree ≤ 4 in χ (module notes)
_COS = tuple(math.cos(2.0 * math.pi * k / _CHI) for k in range(_CHI))
_SIN = tuple(math.sin(2.0 * math.pi * k / _CHI) for k in range(_CHI))


@jit(INLINE)
def _user(p: FloatArray, x1: float, x2: float, x3: float) -> Vec3:
    """Qᵀ x: sorted axes to the user's (Q by rows at the kind's ``sorting``)."""
    q = mat3(p, _Q)
    return (
        q[0] * x1 + q[3] * x2 + q[6] * x3,
        q[1] * x1 + q[4] * x2 + q[7] * x3,
        q[2] * x1 + q[5] * x2 + q[8] * x3,
    )


@jit(INLINE)
def _across(l1: float, l2: float, l3: float) -> tuple[Vec3, Vec3]:
    """Unit vectors e1, e2 ⊥ ℓ with (e1, e2, ℓ) right-handed: e1 from the body axis least
    along ℓ, e2 = ℓ × e1."""
    if abs(l1) <= abs(l2) and abs(l1) <= abs(l3):
        e1 = (0.0, l3, -l2)  # x̂ × ℓ
    elif abs(l2) <= abs(l3):
        e1 = (-l3, 0.0, l1)
    else:
        e1 = (l2, -l1, 0.0)
    size = math.sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])
    e1 = (e1[0] / size, e1[1] / size, e1[2] / size)
    return e1, (l2 * e1[2] - l3 * e1[1], l3 * e1[0] - l1 * e1[2], l1 * e1[1] - l2 * e1[0])


@jit(KERNEL)
def _about_l(
    p: FloatArray, k: int, l_sorted: Vec3, L: float, inv: Vec3, sl: Vec3
) -> tuple[float, float, float, float]:
    """The χ-means of the L-frame moment Rz(χ) G M(s)/P and of the power ω·M/P at the body
    direction ℓ (sorted axes) of L, the Sun at s_L in the L-frame, the cubic at p[k:]."""
    l1, l2, l3 = _user(p, l_sorted[0], l_sorted[1], l_sorted[2])
    o1, o2, o3 = _user(
        p, L * inv[0] * l_sorted[0], L * inv[1] * l_sorted[1], L * inv[2] * l_sorted[2]
    )
    e1, e2 = _across(l1, l2, l3)
    t1 = t2 = t3 = power = 0.0
    for j in range(_CHI):
        c, s = _COS[j], _SIN[j]
        u1, u2 = c * sl[0] + s * sl[1], -s * sl[0] + c * sl[1]  # Rz(χ)ᵀ s_L
        b1 = u1 * e1[0] + u2 * e2[0] + sl[2] * l1
        b2 = u1 * e1[1] + u2 * e2[1] + sl[2] * l2
        b3 = u1 * e1[2] + u2 * e2[2] + sl[2] * l3
        m1, m2, m3 = cubic(p, k, b1, b2, b3)
        g1 = e1[0] * m1 + e1[1] * m2 + e1[2] * m3
        g2 = e2[0] * m1 + e2[1] * m2 + e2[2] * m3
        t1 += c * g1 - s * g2
        t2 += s * g1 + c * g2
        t3 += l1 * m1 + l2 * m2 + l3 * m3
        power += o1 * m1 + o2 * m2 + o3 * m3
    return t1 / _CHI, t2 / _CHI, t3 / _CHI, power / _CHI


@jit(INLINE)
def _arc_means(a: float, b: float) -> tuple[float, float, float, float, float]:
    """(H0, H1, H2, K0, K1): the means over γ of g cos kγ (k = 0, 1, 2) and g² cos kγ (k = 0, 1)
    for the illumination g = max(0, a + b cos γ), b ≥ 0, lit on |γ| < γ0 = arccos(−a/b):
    H_k = (1/π) ∫₀^γ0 (a + b cos γ) cos kγ dγ and likewise K_k with the square."""
    if a + b <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0
    if a >= b:  # lit all round: γ0 = π
        return a, 0.5 * b, 0.0, a * a + 0.5 * b * b, a * b
    c0 = -a / b
    g0 = math.acos(c0)
    s1 = math.sqrt(max(1.0 - c0 * c0, 0.0))
    s2 = 2.0 * s1 * c0  # sin 2γ0
    s13 = s1 + s1 * (3.0 - 4.0 * s1 * s1) / 3.0  # sin γ0 + sin 3γ0/3
    q = a * a + 0.5 * b * b
    return (
        (a * g0 + b * s1) * _INV_PI,
        (a * s1 + b * (0.5 * g0 + 0.25 * s2)) * _INV_PI,
        0.5 * (a * s2 + b * s13) * _INV_PI,
        (q * g0 + 2.0 * a * b * s1 + 0.25 * b * b * s2) * _INV_PI,
        (q * s1 + a * b * (g0 + 0.5 * s2) + 0.25 * b * b * s13) * _INV_PI,
    )


_INV_PI = 1.0 / math.pi


@jit(INLINE)
def _cross(x: Vec3, y: Vec3) -> Vec3:
    return x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]


@jit(INLINE)
def _plus(x: Vec3, c: float, y: Vec3) -> Vec3:
    """x + c y."""
    return x[0] + c * y[0], x[1] + c * y[1], x[2] + c * y[2]


@jit(KERNEL)
def _lit_about_l(
    p: FloatArray, k: int, count: int, l_sorted: Vec3, L: float, inv: Vec3, sl: Vec3
) -> tuple[float, float, float, float]:
    """The χ-means, exact, of the L-frame moment Rz(χ) G M(s)/P and of the power ω·M/P of the
    ``count`` facets at p[k:] at the body direction ℓ (sorted axes) of L, the Sun at s_L in
    the L-frame (module notes: the lit arcs)."""
    l1, l2, l3 = _user(p, l_sorted[0], l_sorted[1], l_sorted[2])
    ell = (l1, l2, l3)
    om = _user(p, L * inv[0] * l_sorted[0], L * inv[1] * l_sorted[1], L * inv[2] * l_sorted[2])
    e1, e2 = _across(l1, l2, l3)
    across = math.sqrt(sl[0] * sl[0] + sl[1] * sl[1])
    along = sl[2]
    ca, sa = (sl[0] / across, sl[1] / across) if across > 0.0 else (1.0, 0.0)
    # ⟨M⟩ = −[X0 × ℓ + X1 × e1 + X2 × e2 + B0] and ⟨M e^{−iβ}⟩ = re + i im with
    # re = −[Y × ℓ + U1 × e1 + U2 × e2 + B1], im = Z × ℓ + U2 × e1 − V × e2 + B2: the sums
    # over the facets of their centres (and arms r × n) weighted as below (module notes).
    x0 = x1 = x2 = b0 = y = u1 = u2 = z = b1 = b2 = vv = (0.0, 0.0, 0.0)
    for _ in range(count):
        n = (p[k + _F.normal], p[k + _F.normal + 1], p[k + _F.normal + 2])
        n1 = n[0] * e1[0] + n[1] * e1[1] + n[2] * e1[2]
        n2 = n[0] * e2[0] + n[1] * e2[1] + n[2] * e2[2]
        size = math.sqrt(n1 * n1 + n2 * n2)
        h0, h1, h2, k0, k1 = _arc_means(along * (n[0] * l1 + n[1] * l2 + n[2] * l3), across * size)
        if h0 == 0.0:
            k += _FACET
            continue
        r = (p[k + _F.centre], p[k + _F.centre + 1], p[k + _F.centre + 2])
        arm = (p[k + _F.arm], p[k + _F.arm + 1], p[k + _F.arm + 2])
        ks, kp, kd = p[k + _F.ks], p[k + _F.kp], p[k + _F.kd]
        k += _FACET
        if size > 0.0:
            across_n = 1.0 / size
            cb, sb = n1 * across_n, n2 * across_n  # e^{iβ0}
        else:
            cb, sb = 1.0, 0.0
        c2, s2 = cb * cb - sb * sb, 2.0 * cb * sb
        w0 = kp * k0 + kd * h0
        w1 = kp * k1 + kd * h1
        half = 0.5 * ks * across
        g0, g1, g2 = ks * along * h0, ks * across * h1, ks * along * h1
        x0 = _plus(x0, g0, r)
        x1 = _plus(x1, g1 * cb, r)
        x2 = _plus(x2, g1 * sb, r)
        b0 = _plus(b0, w0, arm)
        y = _plus(y, g2 * cb, r)
        z = _plus(z, g2 * sb, r)
        b1 = _plus(b1, w1 * cb, arm)
        b2 = _plus(b2, w1 * sb, arm)
        u1 = _plus(u1, half * (h0 + h2 * c2), r)
        u2 = _plus(u2, half * h2 * s2, r)
        vv = _plus(vv, half * (h2 * c2 - h0), r)
    c1, c2_, c3 = _cross(x0, ell), _cross(x1, e1), _cross(x2, e2)
    mean = (
        -(c1[0] + c2_[0] + c3[0] + b0[0]),
        -(c1[1] + c2_[1] + c3[1] + b0[1]),
        -(c1[2] + c2_[2] + c3[2] + b0[2]),
    )
    d1, d2, d3 = _cross(y, ell), _cross(u1, e1), _cross(u2, e2)
    re = (
        -(d1[0] + d2[0] + d3[0] + b1[0]),
        -(d1[1] + d2[1] + d3[1] + b1[1]),
        -(d1[2] + d2[2] + d3[2] + b1[2]),
    )
    f1, f2, f3 = _cross(z, ell), _cross(u2, e1), _cross(vv, e2)
    im = (
        f1[0] + f2[0] - f3[0] + b2[0],
        f1[1] + f2[1] - f3[1] + b2[1],
        f1[2] + f2[2] - f3[2] + b2[2],
    )
    # T⊥ = e^{iα} w·⟨M e^{−iβ}⟩ (module notes), T∥ = ℓ·⟨M⟩, the power ω·⟨M⟩.
    wr = (
        e1[0] * re[0]
        + e1[1] * re[1]
        + e1[2] * re[2]
        - (e2[0] * im[0] + e2[1] * im[1] + e2[2] * im[2])
    )
    wi = (
        e1[0] * im[0]
        + e1[1] * im[1]
        + e1[2] * im[2]
        + e2[0] * re[0]
        + e2[1] * re[1]
        + e2[2] * re[2]
    )
    return (
        ca * wr - sa * wi,
        sa * wr + ca * wi,
        l1 * mean[0] + l2 * mean[1] + l3 * mean[2],
        om[0] * mean[0] + om[1] * mean[1] + om[2] * mean[2],
    )


_PURE = 1e-6  # polhode amplitudes below which ℓ is the encircled axis (an error ~1e-12)
_POLHODE_NODES = 8  # intervals of the quarter period [0, K] up to K(m = 0.9) (module notes)
_K_STEP = 2.5780921133481733  # K(m = 0.9): beyond it, 8 more intervals for each such step of K
_MAX_NODES = 64


@jit(INLINE)
def _on_polhode(
    a: int, ac: float, as_: float, ad: float, cn: float, sn: float, dn: float, i_c: int,
    i_s: int, sd: float,
) -> Vec3:  # fmt: skip
    """ℓ in the sorted axes at (cn, sn, dn) with the signs of cn and sn flipped by i_c, i_s and
    dn's times sd: (A_c cn, A_s sn, A_d dn) about the third axis (a = 2), reversed about the
    first."""
    c_ = (1.0 - 2.0 * i_c) * ac * cn
    s_ = (1.0 - 2.0 * i_s) * as_ * sn
    d_ = sd * ad * dn
    return (c_, s_, d_) if a == 2 else (d_, s_, c_)


@jit(INLINE)
def _plus4(
    x: tuple[float, float, float, float], w: float, y: tuple[float, float, float, float]
) -> tuple[float, float, float, float]:
    """x + w y."""
    return x[0] + w * y[0], x[1] + w * y[1], x[2] + w * y[2], x[3] + w * y[3]


@jit(KERNEL)
def _exact_closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The Euler–Poinsot average of the exact illumination (:func:`lit_average`)."""
    s1, s2, s3, scale = _sun_mean(p, v, t)
    parts = lit_average(p, v + _MEAN_FACETS, int(p[v + _MEAN.count]), s1, s2, s3, ctx)
    return scale * parts[0], scale * parts[1], scale * parts[2], scale * parts[3]


@jit(KERNEL)
def lit_average(
    p: FloatArray, k: int, count: int, s1: float, s2: float, s3: float, ctx: Context
) -> Parts:
    """The Euler–Poinsot average, L-frame, and the power of the ``count`` facets at p[k:]
    (:data:`FACET`) lit from the inertial direction ŝ = (s1, s2, s3) under a unit pressure:
    exact over χ (the lit arcs), the trapezoidal rule over the polhode (module notes).
    Sunlight's and the air's (:mod:`tumble.kernels.terms.aerodynamic`) exact averages alike."""
    L, inv, a = ctx[0], ctx[2], ctx[7]
    F = ctx[8]
    ac, as_, ad, m, _, _, _ = ctx[9]
    sl = (
        column_dot(F, 0, s1, s2, s3),
        column_dot(F, 1, s1, s2, s3),
        column_dot(F, 2, s1, s2, s3),
    )
    if ac < _PURE and as_ < _PURE:  # a pure rotation: ℓ along the encircled axis
        ls = (0.0, 0.0, ad) if a == 2 else (ad, 0.0, 0.0)
        return _lit_about_l(p, k, count, ls, L, inv, sl)
    ratios, n_agm, a_agm = agm(1.0 - m)
    big_k = 0.5 * math.pi / a_agm
    kc = math.sqrt(1.0 - m)
    total = (0.0, 0.0, 0.0, 0.0)
    nodes = min(_POLHODE_NODES * math.ceil(big_k / _K_STEP), _MAX_NODES)
    for j in range(nodes + 1):
        sn, cn, dn = jacobi_quarter(j * big_k / nodes, big_k, kc, ratios, n_agm, a_agm)
        weight = 0.5 if j == 0 or j == nodes else 1.0
        n_c, n_s = (2 if cn > 0.0 else 1), (2 if sn > 0.0 else 1)
        w = weight / (n_c * n_s * nodes)
        for i_c in range(n_c):
            for i_s in range(n_s):
                ls = _on_polhode(a, ac, as_, ad, cn, sn, dn, i_c, i_s, 1.0)
                total = _plus4(total, w, _lit_about_l(p, k, count, ls, L, inv, sl))
    return total


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The Euler–Poinsot average of :func:`mean_moment` (module notes), L-frame, and its power:
    :func:`_exact_closed` for the exact illumination."""
    if p[v + _MEAN.exact] == 1.0:
        return _exact_closed(p, v, t, ctx)
    s1, s2, s3, scale = _sun_mean(p, v, t)
    total = expanded_average(p, v + _MEAN.coefficients, s1, s2, s3, ctx)
    return scale * total[0], scale * total[1], scale * total[2], scale * total[3]


@jit(KERNEL)
def expanded_average(p: FloatArray, k: int, s1: float, s2: float, s3: float, ctx: Context) -> Parts:
    """The Euler–Poinsot average, L-frame, and the power of the cubic M(s)/P at p[k:]
    (:func:`cubic`) lit from the inertial direction ŝ = (s1, s2, s3) under a unit pressure:
    exact (module notes, the closed form). Sunlight's and the air's
    (:mod:`tumble.kernels.terms.aerodynamic`) expanded averages alike."""
    L, inv, a, F = ctx[0], ctx[2], ctx[7], ctx[8]
    ac, as_, ad, m, x1, x2, dn1 = ctx[9]
    sl = (column_dot(F, 0, s1, s2, s3), column_dot(F, 1, s1, s2, s3), column_dot(F, 2, s1, s2, s3))
    total = (0.0, 0.0, 0.0, 0.0)
    for node in range(3):  # x = sn² = 0, ½, 1
        x = 0.5 * node
        weight = (2.0 * x2 - 3.0 * x1 + 1.0, 4.0 * (x1 - x2), 2.0 * x2 - x1)[node]
        cn, sn, dn = math.sqrt(1.0 - x), math.sqrt(x), math.sqrt(1.0 - m * x)
        n_c, n_s = (2 if cn > 0.0 else 1), (2 if sn > 0.0 else 1)
        odd = dn1 / dn if node == 1 else 0.0  # ⟨dn g⟩ = ⟨dn⟩ g(½) for g linear in x
        share = 0.5 / (n_c * n_s)  # the signs of cn and sn, and the two of dn
        for i_d in range(2):
            sd = 1.0 - 2.0 * i_d
            w = share * (weight + sd * odd)
            for i_c in range(n_c):
                for i_s in range(n_s):
                    ls = _on_polhode(a, ac, as_, ad, cn, sn, dn, i_c, i_s, sd)
                    total = _plus4(total, w, _about_l(p, k, ls, L, inv, sl))
    return total


ILLUMINATION = (1.0 / (3.0 * math.pi), 0.5, 4.0 / (3.0 * math.pi))
"""(g0, g1, g2): max(0, c) ≈ g0 + g1 c + g2 c², the second-order Fourier series
1/π + ½ cos θ + 2/(3π) cos 2θ of the illumination written in c = cos θ."""


def expanded_tensors(table: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The tensors C⁰ (3,), C¹ (3, 3), C² (3, 3, 3), C³ (3, 3, 3, 3) [m³] of the moment with the
    expanded illumination, M(s) = P (C⁰ + C¹ s + C² s s + C³ s s s), of the facets ``table``
    (rows :data:`FACET`), symmetric in their last indices.

    The facet at r has the moment −g(ĉ) [ks r × s + (kp ĉ + kd) r × n] with
    g(ĉ) = g0 + g1 ĉ + g2 ĉ² (:data:`ILLUMINATION`): the powers of ĉ = n·s give the tensors.
    """
    g0, g1, g2 = ILLUMINATION
    n, r = table[:, _F.normal : _F.normal + 3], table[:, _F.centre : _F.centre + 3]
    ks, kp, kd = table[:, _F.ks], table[:, _F.kp], table[:, _F.kd]
    X = np.einsum("ijk,fj->fik", _LEVI_CIVITA, r)  # r × s = X s
    b = np.cross(r, n)
    p0, p1, p2, p3 = kd * g0, kd * g1 + kp * g0, kd * g2 + kp * g1, kp * g2  # (kp ĉ + kd) g(ĉ)
    c0 = -np.einsum("f,fi->i", p0, b)
    c1 = -(np.einsum("f,fik->ik", ks * g0, X) + np.einsum("f,fi,fj->ij", p1, b, n))
    c2 = -(np.einsum("f,fik,fl->ikl", ks * g1, X, n) + np.einsum("f,fi,fj,fk->ijk", p2, b, n, n))
    c3 = -(
        np.einsum("f,fik,fl,fm->iklm", ks * g2, X, n, n)
        + np.einsum("f,fi,fj,fk,fl->ijkl", p3, b, n, n, n)
    )
    c2 = 0.5 * (c2 + c2.transpose(0, 2, 1))
    c3 = sum(c3.transpose(0, *order) for order in _ORDERS) / 6.0
    return c0, c1, c2, c3


_LEVI_CIVITA = np.zeros((3, 3, 3))
_LEVI_CIVITA[0, 1, 2] = _LEVI_CIVITA[1, 2, 0] = _LEVI_CIVITA[2, 0, 1] = 1.0
_LEVI_CIVITA[0, 2, 1] = _LEVI_CIVITA[2, 1, 0] = _LEVI_CIVITA[1, 0, 2] = -1.0
_ORDERS = ((1, 2, 3), (1, 3, 2), (2, 1, 3), (2, 3, 1), (3, 1, 2), (3, 2, 1))


def coefficients(table: FloatArray) -> FloatArray:
    """The mean term's 60 coefficients [m³] of the facets ``table`` (rows :data:`FACET`): for
    each axis, those of :func:`monomials` (a symmetric tensor's entry times its multinomial
    count)."""
    tensors = expanded_tensors(table)
    out = np.zeros((3, _TERMS_PER_AXIS))
    for j, (e1, e2, e3) in enumerate(monomials()):
        index = [0] * e1 + [1] * e2 + [2] * e3
        count = math.factorial(len(index)) // (
            math.factorial(e1) * math.factorial(e2) * math.factorial(e3)
        )
        where: tuple[Any, ...] = (slice(None), *index)
        out[:, j] = count * tensors[len(index)][where]
    return out.ravel()


def principal(table: FloatArray, axes: FloatArray) -> FloatArray:
    """The facets ``table`` (rows :data:`FACET`, the user's body axes) in the principal axes
    (R: the principal axes as columns, det R = 1): n → Rᵀ n, r → Rᵀ r, r × n → Rᵀ (r × n)."""
    out = np.array(table, dtype=float)
    for at in (_F.normal, _F.centre, _F.arm):
        out[:, at : at + 3] = out[:, at : at + 3] @ axes
    return out


def exact_illumination(context: OrbitContext) -> float:
    """The ``exact`` field of the averaged terms: 1.0 for ``surface.averaged_illumination =
    "exact"``, 0.0 for "expanded"."""
    if context.illumination not in ILLUMINATIONS:
        raise ParameterError(
            f"surface.averaged_illumination = {context.illumination!r} must be one of "
            + ", ".join(f'"{k}"' for k in ILLUMINATIONS)
        )
    return float(context.illumination == "exact")


def build(value: Any, context: OrbitContext) -> tuple[str, list[Any], list[Any]] | None:
    """The terms of ``[torques] solar_radiation = shadow`` on the ``[surface]`` facets, in the
    model's units (pressure times T0²/I0, facets in the principal axes)."""
    from tumble.kernels.terms import compiled_term  # the registry, loaded by now

    if value not in SHADOWS:
        raise ParameterError(
            f"torques.solar_radiation = {value!r} must be one of "
            + ", ".join(f'"{k}"' for k in SHADOWS)
        )
    if value == "none":
        return None
    if context.facets is None:
        raise ParameterError("torques.solar_radiation needs the body's surface: give [surface]")
    table = principal(context.facets, context.axes)
    sun = {
        "orbit": context.orbit,
        "jd0": context.jd,
        "days": context.T0 / 86400.0,
        "pressure": SOLAR_FLUX / SPEED_OF_LIGHT * context.T0**2 / context.I0,
    }
    full = compiled_term(
        "solar_radiation",
        {**sun, "shadow": SHADOWS[value], "count": float(table.shape[0])},
        tail=table.ravel(),
    )
    mean = compiled_term(
        "solar_radiation_mean",
        {
            **sun,
            "shadow": 1.0,
            "coefficients": coefficients(table),
            "exact": exact_illumination(context),
            "count": float(table.shape[0]),
        },
        tail=table.ravel(),
    )
    return "solar radiation", [full], [mean]


TERMS = (
    Term(
        name="solar_radiation",
        doc="sunlight on facets along an orbit, with the Earth's shadow",
        layout=LAYOUT,
        reads=frozenset({"attitude", "time", "orbit"}),
        moment=moment,
    ),
    Term(
        name="solar_radiation_mean",
        doc="sunlight on facets averaged over the orbit, the illumination expanded to second order",
        layout=MEAN_LAYOUT,
        reads=frozenset({"attitude", "time"}),
        moment=mean_moment,
        closed=closed,
        precession_degree=4,  # A M(Aᵀ ŝ), M cubic
    ),
)

ORBIT_KEYS = (
    OrbitKey(
        name="solar_radiation",
        kind="text",
        meaning='"conical", "cylindrical" or "none" (needs [surface])',
        unit="",
        default="none",
        doc="sunlight on the [surface] facets, with the Earth's shadow of that shape",
        build=build,
    ),
)
