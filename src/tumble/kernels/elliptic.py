"""Carlson's symmetric elliptic integrals R_F, R_D, R_J (and R_C), compiled, the complete
Legendre integrals K, E, Π built from them, and the Jacobi functions sn, cn, dn by the
arithmetic-geometric mean, for right-hand sides the compiled integrator runs.

The definitions are scipy's (``scipy.special.elliprf``, ``elliprd``, ``elliprj``,
``elliprc``; DLMF §19.16), and so is the method: Carlson's duplication theorem until the
arguments agree to about 1e-3 relative, then the Taylor series of DLMF 19.36.1–19.36.2
through fifth-degree terms, whose remainder is then below 1e-17 (B. C. Carlson, "Numerical
computation of real or complex elliptic integrals", Numer. Algorithms 10 (1995) 13–26). A
test holds every function to scipy's values within 1e-14 over the arguments the averaged
equations use.

Why not call scipy from compiled code (through ``cython_special``)? numba cannot cache
machine code that calls a function pointer resolved at run time, and the integrator inlines
its right-hand side: every process would compile the averaged integrators again (seconds).

Domains (not checked here: the callers guarantee them): x, y, z ≥ 0 with at most one of
them 0; p > 0; the parameter m of K and E and the characteristic n of Π given through
their complements mc = 1 − m ∈ (0, 1], 1 − n > 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

import numpy as np
from numba.cpython.unsafe.tuple import tuple_setitem as _tuple_setitem

from tumble._typing import FloatArray
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit

__all__ = [
    "Table",
    "agm",
    "ellipe_mc",
    "ellipk_mc",
    "ellippi_mc",
    "elliprc1",
    "elliprd",
    "elliprf",
    "elliprj",
    "evaluate_carlson",
    "jacobi",
    "jacobi_quarter",
]

_AGREE = 1e-3
"""Relative spread of the arguments at which the duplication stops and the series takes
over: its first neglected terms are of degree 6 in the spread, ~1e-18."""


@jit(KERNEL)
def elliprf(x: float, y: float, z: float) -> float:
    """R_F(x, y, z) = ½∫0^∞ dt / √((t + x)(t + y)(t + z)) (DLMF 19.16.1)."""
    a0, x0, y0 = (x + y + z) / 3.0, x, y
    a, scale = a0, 1.0
    while max(abs(a - x), abs(a - y), abs(a - z)) > _AGREE * abs(a):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * sy + sx * sz + sy * sz
        x, y, z, a = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (a + lam)
        scale *= 0.25
    X = (a0 - x0) * scale / a  # (A0 − x0)/(4^m A_m), as Carlson writes it
    Y = (a0 - y0) * scale / a
    Z = -(X + Y)
    e2 = X * Y - Z * Z
    e3 = X * Y * Z
    series = (
        1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0
        - 5.0 * e2 * e2 * e2 / 208.0 + 3.0 * e3 * e3 / 104.0 + e2 * e2 * e3 / 16.0
    )  # fmt: skip
    return series / math.sqrt(a)


@jit(INLINE)
def _rj_series(e2: float, e3: float, e4: float, e5: float, scale: float, a: float) -> float:
    """The series R_J and R_D (R_J with p = z) end their duplication with: its value at the
    last mean ``a``, times ``scale`` = 4^(−m), in the elementary symmetric functions e2 … e5 of
    the scaled deviations from ``a`` (each function forms its own e's)."""
    series = (
        1.0 - 3.0 * e2 / 14.0 + e3 / 6.0 + 9.0 * e2 * e2 / 88.0 - 3.0 * e4 / 22.0
        - 9.0 * e2 * e3 / 52.0 + 3.0 * e5 / 26.0
    )  # fmt: skip
    return scale * series / (a * math.sqrt(a))


@jit(KERNEL)
def elliprd(x: float, y: float, z: float) -> float:
    """R_D(x, y, z) = (3/2)∫0^∞ dt / ((t + z)√((t + x)(t + y)(t + z))) (DLMF 19.16.5)."""
    a0, x0, y0 = (x + y + 3.0 * z) / 5.0, x, y
    a, scale, total = a0, 1.0, 0.0
    while max(abs(a - x), abs(a - y), abs(a - z)) > _AGREE * abs(a):
        sx, sy, sz = math.sqrt(x), math.sqrt(y), math.sqrt(z)
        lam = sx * sy + sx * sz + sy * sz
        total += scale / (sz * (z + lam))
        x, y, z, a = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam), 0.25 * (a + lam)
        scale *= 0.25
    X = (a0 - x0) * scale / a
    Y = (a0 - y0) * scale / a
    Z = -(X + Y) / 3.0
    xy, zz = X * Y, Z * Z
    e2 = xy - 6.0 * zz
    e3 = (3.0 * xy - 8.0 * zz) * Z
    e4 = 3.0 * (xy - zz) * zz
    e5 = xy * zz * Z
    return _rj_series(e2, e3, e4, e5, scale, a) + 3.0 * total


@jit(KERNEL)
def _rc(e: float, one_plus_e: float) -> float:
    """R_C(1, 1 + e), e > −1, given e and 1 + e each to full relative accuracy."""
    if abs(e) < 1e-4:  # the series (DLMF 19.2.18 expanded): its next term is below 1e-21
        return 1.0 - e / 3.0 + e * e / 5.0 - e * e * e / 7.0 + e * e * e * e / 9.0
    if e > 0.0:
        u = math.sqrt(e)
        return math.atan(u) / u
    # atanh u = ½ log1p(2u/(1 − u)) with 1 − u = (1 + e)/(1 + u): no cancellation as u → 1
    # (e → −1), nor in the logarithm of a number near 1 as u → 0.
    u = math.sqrt(-e)
    return 0.5 * math.log1p(2.0 * u * (1.0 + u) / one_plus_e) / u


@jit(KERNEL)
def elliprc1(e: float) -> float:
    """R_C(1, 1 + e) for e > −1 (DLMF 19.2.18, 19.2.19), the form R_J's duplication needs:
    with e given, not 1 + e, it keeps its digits where e is below the round-off of 1."""
    return _rc(e, 1.0 + e)


@jit(KERNEL)
def elliprj(x: float, y: float, z: float, p: float) -> float:
    """R_J(x, y, z, p) = (3/2)∫0^∞ dt / ((t + p)√((t + x)(t + y)(t + z))), p > 0
    (DLMF 19.16.2)."""
    a0, x0, y0, z0 = (x + y + z + 2.0 * p) / 5.0, x, y, z
    a, scale, total = a0, 1.0, 0.0
    while max(abs(a - x), abs(a - y), abs(a - z), abs(a - p)) > _AGREE * abs(a):
        sx, sy, sz, sp = math.sqrt(x), math.sqrt(y), math.sqrt(z), math.sqrt(p)
        lam = sx * sy + sx * sz + sy * sz
        d = (sp + sx) * (sp + sy) * (sp + sz)
        # Carlson's e_m = 4^(−3m) δ / d_m² = Π (√p − √x)/(√p + √x) over x, y, z at step m
        # (p − x shrinks by 4 at each duplication). Where p ≪ x, y, z every factor is near −1
        # and 1 + e cancels: then 1 + e = 1 − Π(1 − t) with t = 2 min(√p, √x)/(√p + √x).
        rx, ry, rz = (sp - sx) / (sp + sx), (sp - sy) / (sp + sy), (sp - sz) / (sp + sz)
        e = rx * ry * rz
        if e > -0.5:
            one_plus_e = 1.0 + e
        else:
            tx = 2.0 * min(sp, sx) / (sp + sx)
            ty = 2.0 * min(sp, sy) / (sp + sy)
            tz = 2.0 * min(sp, sz) / (sp + sz)
            one_plus_e = -math.expm1(math.log1p(-tx) + math.log1p(-ty) + math.log1p(-tz))
        total += scale / d * _rc(e, one_plus_e)
        x, y, z = 0.25 * (x + lam), 0.25 * (y + lam), 0.25 * (z + lam)
        p, a = 0.25 * (p + lam), 0.25 * (a + lam)
        scale *= 0.25
    X = (a0 - x0) * scale / a
    Y = (a0 - y0) * scale / a
    Z = (a0 - z0) * scale / a
    P = -(X + Y + Z) / 2.0
    e2 = X * Y + X * Z + Y * Z - 3.0 * P * P
    e3 = X * Y * Z + 2.0 * e2 * P + 4.0 * P * P * P
    e4 = (2.0 * X * Y * Z + e2 * P + 3.0 * P * P * P) * P
    e5 = X * Y * Z * P * P
    return _rj_series(e2, e3, e4, e5, scale, a) + 6.0 * total


@jit(KERNEL)
def ellipk_mc(mc: float) -> float:
    """K(m) = R_F(0, 1 − m, 1) = π/(2 AGM(1, √mc)) from the complementary parameter
    mc = 1 − m ∈ (0, 1] (DLMF 19.8.5): the arithmetic-geometric mean converges
    quadratically, a third of the cost of R_F's duplication (one square root a step, about
    five steps for mc ≥ 1e-9)."""
    a, g = 1.0, math.sqrt(mc)
    while a - g > 1e-15 * a:
        a, g = 0.5 * (a + g), math.sqrt(a * g)
    return 0.5 * math.pi / (0.5 * (a + g))


@jit(KERNEL)
def ellipe_mc(mc: float) -> float:
    """E(m) = R_F(0, mc, 1) − (m/3) R_D(0, mc, 1) from mc = 1 − m ∈ [0, 1]."""
    if mc == 0.0:
        return 1.0
    return elliprf(0.0, mc, 1.0) - (1.0 - mc) / 3.0 * elliprd(0.0, mc, 1.0)


@jit(KERNEL)
def ellippi_mc(n: float, mc: float) -> float:
    """Π(n | m) = R_F(0, mc, 1) + (n/3) R_J(0, mc, 1, 1 − n), n < 1, mc = 1 − m ∈ (0, 1]
    (the characteristic's sign as in :mod:`tumble.unperturbed.elliptic`)."""
    return elliprf(0.0, mc, 1.0) + n / 3.0 * elliprj(0.0, mc, 1.0, 1.0 - n)


@jit(ENTRY)
def evaluate_carlson(which: int, args: FloatArray) -> FloatArray:
    """One of the functions above at every row of ``args`` (for tests against scipy):
    0 R_F, 1 R_D, 2 R_J, 3 R_C(1, 1 + e), 4 K, 5 E, 6 Π, each reading its leading
    columns (x, y, z, p; or e; or mc; or n, mc)."""
    out = np.empty(args.shape[0])
    for i in range(args.shape[0]):
        r = args[i]
        if which == 0:
            out[i] = elliprf(r[0], r[1], r[2])
        elif which == 1:
            out[i] = elliprd(r[0], r[1], r[2])
        elif which == 2:
            out[i] = elliprj(r[0], r[1], r[2], r[3])
        elif which == 3:
            out[i] = elliprc1(r[0])
        elif which == 4:
            out[i] = ellipk_mc(r[0])
        elif which == 5:
            out[i] = ellipe_mc(r[0])
        else:
            out[i] = ellippi_mc(r[0], r[1])
    return out


# ---------------------------------------------------------------------------------------------
# Jacobi elliptic functions by the arithmetic-geometric mean.

AGM_STEPS = 24  # more than the AGM needs down to mc = MC_FLOOR (about 13 steps)

Table = tuple[float, ...]
"""The AGM's ratios c_n/a_n (:func:`agm`), a fixed-size tuple: no allocation, which the
right-hand sides may not make."""
_EMPTY = (0.0,) * AGM_STEPS
# numba's tuple "assignment" (a new tuple with one entry replaced).
tuple_setitem = cast(Callable[[Table, int, float], Table], _tuple_setitem)


@jit(KERNEL)
def agm(mc: float) -> tuple[Table, int, float]:
    """The AGM of 1 and √mc with c_n = (a_{n−1} − b_{n−1})/2 (DLMF 22.20.1): the ratios
    c_n/a_n (n = 1 … N), N, and a_N; K = π/(2 a_N) (DLMF 19.8.5)."""
    ratios = _EMPTY
    a, b = 1.0, math.sqrt(mc)
    n = 0
    while n < AGM_STEPS - 1 and a - b > 1e-16 * a:
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        n += 1
        ratios = tuple_setitem(ratios, n, c / a)
    return ratios, n, a


@jit(KERNEL)
def jacobi(u: float, ratios: Table, n: int, a: float) -> tuple[float, float, float]:
    """sn, cn, dn of u by the descending recurrence of the AGM's phases (DLMF 22.20.ii):
    φ_N = 2ᴺ a_N u, φ_{n−1} = (φ_n + arcsin((c_n/a_n) sin φ_n))/2, then sn = sin φ₀,
    cn = cos φ₀, dn = cos φ₀ / cos(φ₁ − φ₀)."""
    phi = u * a * 2.0**n
    before = phi
    for j in range(n, 0, -1):
        before = phi
        phi = 0.5 * (phi + math.asin(ratios[j] * math.sin(phi)))
    c = math.cos(phi)
    dn = c / math.cos(before - phi) if n > 0 else 1.0
    return math.sin(phi), c, dn


@jit(KERNEL)
def jacobi_quarter(
    v: float, big_k: float, kc: float, ratios: Table, n: int, a: float
) -> tuple[float, float, float]:
    """sn, cn, dn of v ∈ [0, K] (k′ = kc): directly up to K/2, beyond it from w = K − v by
    sn(K − w) = cn w/dn w, cn(K − w) = k′ sn w/dn w, dn(K − w) = k′/dn w (DLMF 22.4.iii):
    dn is then never formed below √k′ (its value at K/2), where it would lose digits."""
    if v <= 0.5 * big_k:
        return jacobi(v, ratios, n, a)
    s, c, d = jacobi(big_k - v, ratios, n, a)
    return c / d, kc * s / d, kc / d
