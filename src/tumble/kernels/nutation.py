"""The nutation of a symmetric body under the moment a sinθ + b sin2θ, compiled: the well of
u = cos θ at a given energy, its period averages ⟨u⟩ and ⟨u²⟩, and Volosov's averaged
equations of Serov (1991) with the capsule's damping and pressure, for the compiled
integrator.

The Python orbit (:class:`tumble.unperturbed.symmetric_body.NutationOrbit`) is the reference:
the same roots of f(u) = u'² (Serov (1991), eq. (1.7)), the same labelling of the outer roots,
modulus and charts, and the same closed forms of the averages by Carlson's R_J and its
derivative in p. It also refines turning points next to the poles θ = 0, π to
full relative accuracy, which ψ and φ need; the averages need the turning points only to
absolute accuracy, which plain roots of f give. A test holds both to 1e-12.

Where the closed form of ⟨u²⟩ has a removable singularity in both charts (outer roots far
from the motion: small |b|, or a = b = 0), ⟨u²⟩ comes from the periodic trapezoid rule in the
angle φ of u = c + h cos φ, in which dt ∝ dφ/√(−q(u)) with q the quadratic left when the
turning points are divided out of f: smooth and periodic, and there far from its zeros, so the
rule converges geometrically within a few dozen nodes.

Parameters of ``KIND_NUTATION_AVERAGED`` (the full kernel's, and the well's hint last):
``[μ, a0, b0, ε, d, ν, pressure kind, Q(0), table size n, τ_1..n, Q_1..n, u_hint]``.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.kernels.codes import NUTATION_SEPARATRIX_TOL
from tumble.kernels.elliptic import agm, ellipk_mc, elliprd, elliprj, jacobi_quarter
from tumble.kernels.jit import ENTRY, INLINE, KERNEL, jit
from tumble.kernels.limits import (
    MODULUS_ROUNDOFF,
    NUTATION_MAX,
    NUTATION_START,
    ROOT_MAXITER,
    SPIN_MAX,
    SPIN_START,
    X2_CLOSED_DIST,
)
from tumble.kernels.params import NONLINEAR_MOMENT, NUTATION_ENGINE
from tumble.kernels.torque import fixed_program

__all__ = [
    "evaluate_separatrix_distance",
    "evaluate_well",
    "nutation_averaged",
    "nutation_columns",
    "nutation_engine",
    "orbit_nodes",
    "pressure",
    "pressure_rate",
    "separatrix_distance",
    "well_averages",
]

_EPS = 2.220446049250313e-16
_QUAD_RTOL = 1e-15  # trapezoid fallback: successive doublings agree to this (round-off)
_QUAD_MAX = 1 << 16  # … within this many nodes, else the averages are refused (NaN)

_NM, _NE = NONLINEAR_MOMENT.at, NUTATION_ENGINE.at
_NE_PROGRAM = NUTATION_ENGINE.size
_TABLE = NONLINEAR_MOMENT.size  # the pressure table's knots τ_1..n, then its values Q_1..n

# The fields of a well's result (a tuple, in this order).
_OK, _U1, _U2, _M1, _M2, _K2, _MC, _K, _BETA, _CASE = range(10)


@jit(KERNEL)
def pressure(p: FloatArray, tau: float) -> float:
    """Q(τ)/Q(0) of the nonlinear-moment parameters: constant, exponential, or a table
    (piecewise linear between its knots; the run was checked to stay inside)."""
    return _pressure_law(p, tau)[0]


@jit(KERNEL)
def pressure_rate(p: FloatArray, tau: float) -> float:
    """dQ/dτ / Q(0): for a table the slope of the segment τ lies in (right-continuous, as
    :meth:`tumble.models.inputs.nonlinear_moment.Pressure.rate`)."""
    return _pressure_law(p, tau)[1]


@jit(INLINE)
def _pressure_law(p: FloatArray, tau: float) -> tuple[float, float]:
    """Q(τ)/Q(0) and dQ/dτ / Q(0), τ the paper's time: constant, exponential (Q = e^τ), or a
    table (between its knots linear; its slope that of the segment τ lies in)."""
    kind = int(p[_NM.pressure])
    if kind == 0:
        return 1.0, 0.0
    q0 = p[_NM.q0]
    if kind == 1:
        q = math.exp(tau) / q0
        return q, q
    lo, hi = _segment(p, tau)
    n = int(p[_NM.knots])
    x0, x1 = p[_TABLE + lo], p[_TABLE + hi]
    v0, v1 = p[_TABLE + n + lo], p[_TABLE + n + hi]
    return (v0 + (v1 - v0) * (tau - x0) / (x1 - x0)) / q0, (v1 - v0) / (x1 - x0) / q0


@jit(KERNEL)
def _segment(p: FloatArray, tau: float) -> tuple[int, int]:
    """Knots (lo, hi = lo + 1) of the table segment holding τ, the right one at a knot."""
    lo, hi = 0, int(p[_NM.knots]) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if p[_TABLE + mid] <= tau:
            lo = mid
        else:
            hi = mid
    return lo, hi


@jit(INLINE)
def _poly(
    c0: float, c1: float, c2: float, c3: float, c4: float, c5: float, x: float
) -> float:  # fmt: skip
    return ((((c5 * x + c4) * x + c3) * x + c2) * x + c1) * x + c0


@jit(KERNEL)
def _root(
    c0: float, c1: float, c2: float, c3: float, c4: float, c5: float,
    lo: float, f_lo: float, hi: float, f_hi: float,
) -> float:  # fmt: skip
    """The root of the polynomial c (degree ≤ 5, ascending) in [lo, hi], where it is monotone
    and changes sign: Newton steps inside the bracket, bisection when they leave it or stall."""
    if f_lo == 0.0:
        return lo
    if f_hi == 0.0:
        return hi
    pos, neg = (lo, hi) if f_lo > 0.0 else (hi, lo)
    x = lo + (hi - lo) * (f_lo / (f_lo - f_hi))
    if not lo < x < hi:
        x = 0.5 * (lo + hi)
    a0, a1, a2, a3, a4, a5 = abs(c0), abs(c1), abs(c2), abs(c3), abs(c4), abs(c5)
    last = hi - lo
    for _ in range(ROOT_MAXITER):
        fx = _poly(c0, c1, c2, c3, c4, c5, x)
        if fx == 0.0:
            return x
        if fx > 0.0:
            pos = x
        else:
            neg = x
        left, right = min(pos, neg), max(pos, neg)
        slope = _poly(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 5.0 * c5, 0.0, x)
        nxt = x - fx / slope if slope != 0.0 else left
        if not left < nxt < right or abs(nxt - x) > 0.5 * last:
            if abs(fx) <= 4.0 * _EPS * _poly(a0, a1, a2, a3, a4, a5, abs(x)):
                return x  # Newton jitters in the round-off band of c: x is the root
            nxt = 0.5 * (left + right)
        last = abs(nxt - x)
        x = nxt
        if last <= 2.0 * _EPS * abs(x) or right - left <= 2.0 * _EPS * max(abs(left), abs(right)):
            return x
    return x


@jit(INLINE)
def _pick(i: int, x0: float, x1: float, x2: float, x3: float, x4: float) -> float:
    """The i-th of five values (a short list without an array)."""
    if i == 0:
        return x0
    if i == 1:
        return x1
    if i == 2:
        return x2
    if i == 3:
        return x3
    return x4


_Roots = tuple[int, float, float, float, float, float]


@jit(KERNEL)
def _roots_on_pieces(
    c0: float, c1: float, c2: float, c3: float, c4: float, c5: float,
    k: int, s0: float, s1: float, s2: float, s3: float,
) -> _Roots:  # fmt: skip
    """The roots of c inside (−1, 1), ascending, where c is monotone between the k ascending
    split points s0 … inside (−1, 1): (their number, the roots, NaN for absent ones)."""
    n = 0
    r0, r1, r2, r3, r4 = math.nan, math.nan, math.nan, math.nan, math.nan
    lo = -1.0
    v_lo = _poly(c0, c1, c2, c3, c4, c5, lo)
    for i in range(k + 1):
        hi = _pick(i, s0, s1, s2, s3, 1.0) if i < k else 1.0
        v_hi = _poly(c0, c1, c2, c3, c4, c5, hi)
        x = math.nan
        if (v_lo < 0.0 < v_hi) or (v_lo > 0.0 > v_hi):
            x = _root(c0, c1, c2, c3, c4, c5, lo, v_lo, hi, v_hi)
        elif v_hi == 0.0 and hi < 1.0:
            x = hi
        if not math.isnan(x):
            if n == 0:
                r0 = x
            elif n == 1:
                r1 = x
            elif n == 2:
                r2 = x
            elif n == 3:
                r3 = x
            else:
                r4 = x
            n += 1
        lo, v_lo = hi, v_hi
    return n, r0, r1, r2, r3, r4


@jit(KERNEL)
def _roots3(c0: float, c1: float, c2: float, c3: float) -> _Roots:
    """The roots of a polynomial of degree ≤ 3 inside (−1, 1), split at those of its
    derivative (a quadratic, in closed form)."""
    h0, h1, h2 = c1, 2.0 * c2, 3.0 * c3
    s0, s1, k = 1.0, 1.0, 0
    if h2 != 0.0:
        disc = h1 * h1 - 4.0 * h2 * h0
        if disc > 0.0:
            qq = -0.5 * (h1 + math.copysign(math.sqrt(disc), h1))
            r1, r2 = qq / h2, (h0 / qq if qq != 0.0 else 0.0)
            for r in (min(r1, r2), max(r1, r2)):
                if -1.0 < r < 1.0 and (k == 0 or r > s0):
                    if k == 0:
                        s0 = r
                    else:
                        s1 = r
                    k += 1
    elif h1 != 0.0:
        r = -h0 / h1
        if -1.0 < r < 1.0:
            s0, k = r, 1
    return _roots_on_pieces(c0, c1, c2, c3, 0.0, 0.0, k, s0, s1, 1.0, 1.0)


@jit(KERNEL)
def _roots4(c0: float, c1: float, c2: float, c3: float, c4: float) -> _Roots:
    """The roots of a polynomial of degree ≤ 4 inside (−1, 1)."""
    k, s0, s1, s2, _, _ = _roots3(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4)
    return _roots_on_pieces(c0, c1, c2, c3, c4, 0.0, k, s0, s1, s2, 1.0)


@jit(KERNEL)
def _roots5(c0: float, c1: float, c2: float, c3: float, c4: float, c5: float) -> _Roots:
    """The roots of a polynomial of degree ≤ 5 inside (−1, 1)."""
    k, s0, s1, s2, s3, _ = _roots4(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 5.0 * c5)
    return _roots_on_pieces(c0, c1, c2, c3, c4, c5, k, s0, s1, s2, s3)


@jit(KERNEL)
def _well(
    g0: float, g1: float, g2: float, g3: float, g4: float, f_dn: float, f_up: float,
    u_hint: float,
) -> tuple[float, float]:  # fmt: skip
    """The turning points (u2, u1) of the well of f > 0 in [−1, 1] nearest to u_hint (the
    lower one on a tie), f(−1) = f_dn and f(1) = f_up given exactly; (NaN, NaN) if none."""
    nc, c0, c1, c2, _, _ = _roots3(g1, 2.0 * g2, 3.0 * g3, 4.0 * g4)  # f′ = 0
    v0 = _poly(g0, g1, g2, g3, g4, 0.0, c0)
    v1 = _poly(g0, g1, g2, g3, g4, 0.0, c1)
    v2 = _poly(g0, g1, g2, g3, g4, 0.0, c2)
    best_lo, best_hi, best = math.nan, math.nan, math.inf
    start = -1.0
    for i in range(nc + 1):
        x0 = _pick(i, -1.0, c0, c1, c2, 1.0)
        f0 = _pick(i, f_dn, v0, v1, v2, f_up)
        x1 = 1.0 if i == nc else _pick(i + 1, -1.0, c0, c1, c2, 1.0)
        f1 = f_up if i == nc else _pick(i + 1, f_dn, v0, v1, v2, f_up)
        if f0 <= 0.0 < f1:  # f rises through 0 on this monotone piece
            start = _root(g0, g1, g2, g3, g4, 0.0, x0, f0, x1, f1)
        elif f0 > 0.0 >= f1:  # … and falls through 0: a well (start, end)
            end = _root(g0, g1, g2, g3, g4, 0.0, x0, f0, x1, f1)
            dist = max(start - u_hint, u_hint - end, 0.0)
            if dist < best:
                best_lo, best_hi, best = start, end, dist
    return best_lo, best_hi


@jit(KERNEL)
def _drj_dp(mc: float, p: float, rf: float, rj: float) -> float:
    """∂R_J(0, mc, 1, p)/∂p by integration by parts, given rf = R_F(0, mc, 1) and
    rj = R_J(0, mc, 1, p) (as :func:`tumble.unperturbed.symmetric_body.carlson._drj_dp`;
    removable 0/0 at p = mc and p = 1, which the callers keep away from)."""
    if abs(p - mc) >= abs(p - 1.0):
        Y, Z = mc, 1.0
    else:
        Y, Z = 1.0, mc
    i_d = 2.0 / 3.0 * elliprd(0.0, Y, Z)
    cb = Z * (Y - Z) / (p - Z)
    cc = 3.0 * p - 2.0 * Y + Z - cb
    cd = 2.0 * p * (Y - p)
    return 1.5 * (-2.0 * rf + cb * i_d + cc * 2.0 / 3.0 * rj) / cd


@jit(KERNEL)
def _nu(A: float, B: float, P: float, big: bool, qq: float, c4: float) -> float:
    """ν = (P − A)/(P − B) of the chart with anchor A and pole P (a big root through c4·P = qq)."""
    if big:
        return (qq - c4 * A) / (qq - c4 * B)
    return (P - A) / (P - B)


@jit(KERNEL)
def _order(x: float, u1: float, u2: float) -> tuple[int, float]:
    """Key of a real root on the cycle u1 → u4 → u3 → u2 upwards through ±∞; class 3
    for a root inside the motion interval (a separatrix)."""
    if not math.isfinite(x):
        return 1, 0.0
    if x >= u1:
        return 0, x
    if x <= u2:
        return 2, x
    return 3, 0.0


@jit(KERNEL)
def _x2_by_trapezoid(u1: float, u2: float, c4: float, q1: float, q0: float) -> float:
    """⟨u²⟩ over the motion by the periodic trapezoid rule in φ, u = c + h cos φ (module
    notes); NaN if it has not converged within _QUAD_MAX nodes."""
    c, h = 0.5 * (u1 + u2), 0.5 * (u1 - u2)
    s0, s2 = 0.0, 0.0
    n, prev = 1, math.nan
    scale = max(abs(u1), abs(u2)) ** 2
    for j in range(2):  # φ = 0 and π, half weights
        u = c + h * (1.0 - 2.0 * j)
        w = 0.5 / math.sqrt(-((c4 * u + q1) * u + q0))
        s0 += w
        s2 += w * u * u
    while n < _QUAD_MAX:
        for j in range(n):  # the new nodes φ = π(2j + 1)/(2n)
            u = c + h * math.cos(math.pi * (2 * j + 1) / (2 * n))
            w = 1.0 / math.sqrt(-((c4 * u + q1) * u + q0))
            s0 += w
            s2 += w * u * u
        n *= 2
        new = s2 / s0
        if n >= 32 and abs(new - prev) <= _QUAD_RTOL * max(abs(new), scale):
            return new
        prev = new
    return math.nan


_Chart = tuple[bool, float, float, float, float, float, float, float, float, float, float,
               float, float, float, bool]  # fmt: skip


@jit(KERNEL)
def _well_chart(R: float, G: float, a: float, b: float, E: float, u_hint: float) -> _Chart:
    """The well of energy E nearest to u_hint and its charts, Serov (1991), eqs. (1.7)–(1.10):
    (ok, u1, u2, k², 1 − k², β², root case, ν, ν of the other chart (case 1), the main
    chart's anchor u_a and span u_b − u_a, c4, q1, q0 of the deflated quadratic, free).

    The main chart is u = (u_a (1 − σ) + u_b ν σ)/((1 − σ) + ν σ) with σ = sn²(βt) (case 1,
    anchored at u2, θmax) or σ = sin²(γ/2), γ = am(βt) (case 2, anchored at u1, θmin), as
    the Python orbit's (:mod:`tumble.unperturbed.symmetric_body.charts`).

    ok is False, the rest NaN: no motion at this energy, or a separatrix (1 − k² below
    ``NUTATION_SEPARATRIX_TOL``), or a root inside the motion interval.
    """
    nan = math.nan
    fail = (False, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, False)
    g0, g1, g2 = 2.0 * E - G * G, 2.0 * (G * R - a), -2.0 * b - R * R - 2.0 * E
    g3, g4 = 2.0 * a, 2.0 * b
    u2, u1 = _well(g0, g1, g2, g3, g4, -((G + R) ** 2), -((G - R) ** 2), u_hint)
    if not (u1 >= u2):
        return fail
    # f = (u − u1)(u − u2) q(u), q = c4 u² + q1 u + q0 < 0 on the motion (deflation).
    s, pr = u1 + u2, u1 * u2
    c4 = g4
    q1 = g3 + c4 * s
    q0 = g2 + s * q1 - c4 * pr
    free = a == 0.0 and b == 0.0
    case = 1.0
    ua, dab, nu, nu_other = u2, u1 - u2, 1.0, 1.0
    if free:  # q ≡ q0 = −(2E + R²): u″ = −(2E + R²)u + GR, harmonic
        m, mc, beta2 = 0.0, 1.0, -q0 / 4.0
    else:
        disc = q1 * q1 - 4.0 * c4 * q0
        disc_noise = 64.0 * _EPS * (q1 * q1 + abs(4.0 * c4 * q0))
        if disc < -disc_noise:  # complex outer roots c ± i d (case 2, b < 0)
            if c4 >= 0.0:
                return fail
            case = 2.0
            cc = -q1 / (2.0 * c4)
            dd = math.sqrt(-disc) / (2.0 * abs(c4))
            x1, x2 = u1 - cc, u2 - cc
            r1, r2 = math.hypot(x1, dd), math.hypot(x2, dd)
            if x1 >= 0.0:
                e1m, e1p = dd * dd / (r1 + x1), r1 + x1
            else:
                e1m, e1p = r1 - x1, dd * dd / (r1 - x1)
            if x2 >= 0.0:
                e2m, e2p = dd * dd / (r2 + x2), r2 + x2
            else:
                e2m, e2p = r2 - x2, dd * dd / (r2 - x2)
            w = (u1 - u2) / (r1 + r2)
            m = 0.25 * w * w * ((e1m + e2m) / r1) * ((e1p + e2p) / r2)
            mc = 0.25 * ((e1m + e2p) / r1) * ((e1p + e2m) / r2)
            beta2 = (-c4 * r1) * r2
            nu = r1 / r2  # ξ; the chart anchored at u1
            ua, dab = u1, u2 - u1
        else:
            sq = math.sqrt(max(disc, 0.0))
            qq = -0.5 * (q1 + math.copysign(sq, q1))
            if qq == 0.0:
                return fail
            r_small = q0 / qq
            r_big = qq / c4 if c4 != 0.0 else math.inf
            ks, xs = _order(r_small, u1, u2)
            kb, xb = _order(r_big, u1, u2)
            if ks == 3 or kb == 3:
                return fail
            if ks < kb or (ks == kb and xs <= xb):
                u4, u3, big4, big3 = r_small, r_big, False, True
            else:
                u4, u3, big4, big3 = r_big, r_small, True, False
            A, B = u2, u1
            if big4:  # Q big
                daq = c4 * A - qq
                m = (B - A) * (c4 * u3 - qq) / ((B - u3) * daq)
                mc = (c4 * B - qq) * (A - u3) / ((B - u3) * daq)
                beta2 = -0.25 * (B - u3) * daq
            else:  # P big
                dbp = c4 * B - qq
                m = (B - A) * (qq - c4 * u4) / (dbp * (A - u4))
                mc = (B - u4) * (c4 * A - qq) / (dbp * (A - u4))
                beta2 = -0.25 * dbp * (A - u4)
            nu = _nu(u2, u1, u3, big3, qq, c4)  # the main chart: anchor u2, pole u3
            nu_other = _nu(u1, u2, u4, big4, qq, c4)  # the other: anchor u1, pole u4
    if not (math.isfinite(m) and math.isfinite(mc)) or min(m, mc) < -MODULUS_ROUNDOFF:
        return fail
    m, mc = min(max(m, 0.0), 1.0), min(max(mc, 0.0), 1.0)
    if mc < NUTATION_SEPARATRIX_TOL or not (beta2 > 0.0 and math.isfinite(beta2)):
        return fail
    return True, u1, u2, m, mc, beta2, case, nu, nu_other, ua, dab, c4, q1, q0, free


@jit(KERNEL)
def well_averages(
    R: float, G: float, a: float, b: float, E: float, u_hint: float, moments: bool = True
) -> tuple[float, float, float, float, float, float, float, float, float, float]:
    """The nutation at energy E in the well nearest to u_hint: (ok, u1, u2, ⟨u⟩, ⟨u²⟩, k²,
    1 − k², K, β, root case), Serov (1991), eqs. (1.7)–(1.10); ⟨u⟩ and ⟨u²⟩ are NaN unless
    ``moments`` (the columns need the well only).

    ok is 1.0, or 0.0 with the rest NaN: no motion at this energy, or a separatrix
    (1 − k² below ``NUTATION_SEPARATRIX_TOL``), or a root inside the motion interval.
    """
    nan = math.nan
    fail = (0.0, nan, nan, nan, nan, nan, nan, nan, nan, nan)
    ok, u1, u2, m, mc, beta2, case, nu, nu_other, ua, dab, c4, q1, q0, free = _well_chart(
        R, G, a, b, E, u_hint
    )
    if not ok:
        return fail
    x1_closed, x2_closed = math.nan, math.nan
    K = ellipk_mc(mc)
    if not moments:
        return 1.0, u1, u2, nan, nan, m, mc, K, math.sqrt(beta2), case
    if free:
        m1 = u2 + 0.5 * (u1 - u2)  # ⟨X⟩ = 1/2 at ν = 1
    elif case == 2.0:
        xi = nu
        pp = (xi + 1.0) ** 2 / (4.0 * xi)
        rj = elliprj(0.0, mc, 1.0, pp)
        x1_closed = (1.0 + (xi * xi - 1.0) / (4.0 * xi) * rj / (3.0 * K)) / (2.0 * xi)
        x2_closed = 1.0 / (2.0 * xi * xi) - rj / (12.0 * K * xi**3)
        if pp > 1.0:  # p = 1 in floating point: the term is O(ε_machine), ∂R_J is 0/0
            x2_closed -= (xi * xi - 1.0) ** 2 * _drj_dp(mc, pp, K, rj) / (96.0 * K * xi**4)
        m1 = ua + dab * xi * x1_closed
    else:
        rj = elliprj(0.0, mc, 1.0, nu)
        x1_closed = rj / (3.0 * K)
        m1 = ua + dab * nu * x1_closed
        # ⟨X²⟩ = −∂⟨X⟩/∂ν in the chart farther from the singularities ν = 1 − k², ν = 1.
        dist = min(abs(nu - mc), abs(nu - 1.0)) / max(1.0, nu)
        dist_o = min(abs(nu_other - mc), abs(nu_other - 1.0)) / max(1.0, nu_other)
        if dist_o > dist:
            ua, dab, nu, dist = u1, u2 - u1, nu_other, dist_o
            rj = elliprj(0.0, mc, 1.0, nu)
            x1_closed = rj / (3.0 * K)
        if dist >= X2_CLOSED_DIST:
            x2_closed = -_drj_dp(mc, nu, K, rj) / (3.0 * K)
    if math.isnan(x2_closed):
        m2 = _x2_by_trapezoid(u1, u2, c4, q1, q0)
        if math.isnan(m2):
            return fail
    else:
        m2 = ua * ua + 2.0 * ua * dab * nu * x1_closed + dab * dab * nu * nu * x2_closed
    return 1.0, u1, u2, m1, m2, m, mc, K, math.sqrt(beta2), case


@jit(INLINE)
def nutation_averaged(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """Volosov's averaged equations (2.2)–(2.3) of Serov (1991) in the energy form,
    y = [H, R, G, a, b], under the capsule's damping and pressure with the averages in closed
    form: H′ = ε(−2d(H − a⟨u⟩ − b⟨u²⟩) + a′⟨u⟩ + b′⟨u²⟩), R′ = −ενR,
    G′ = −ε(d(G − R⟨u⟩) + νR⟨u⟩), a′ = εa0 Q′/Q(0), b′ = εb0 Q′/Q(0); NaN where the averages
    do not exist (no motion, a separatrix), so that the step is rejected."""
    eps, d, nu = p[_NM.eps], p[_NM.d], p[_NM.nu]
    H, R, G, a, b = y[0], y[1], y[2], y[3], y[4]
    w = well_averages(R, G, a, b, H, p[p.size - 1])
    if w[_OK] == 0.0:
        for j in range(5):
            out[j] = math.nan
        return
    m1, m2 = w[_M1], w[_M2]
    rate = pressure_rate(p, eps * t)
    da, db = p[_NM.a] * rate, p[_NM.b] * rate
    out[0] = eps * (-2.0 * d * (H - a * m1 - b * m2) + da * m1 + db * m2)
    out[1] = -eps * nu * R
    out[2] = -eps * (d * (G - R * m1) + nu * R * m1)
    out[3] = eps * da
    out[4] = eps * db


@jit(KERNEL)
def _spin_mean(
    p: FloatArray, start: int, tau: float, ps: float, thd: float, r: float, s: float,
    c: float, rtol: float,
) -> tuple[bool, float, float, float]:  # fmt: skip
    """(converged, Φθ, Φ_R, Φ_G) of the body moment of the torque program ``p[start:]``
    averaged over the spin φ at one point of the nutation: ω = (ψ' sinθ sinφ + θ' cosφ,
    ψ' sinθ cosφ − θ' sinφ, r), Φθ = M_p cosφ − M_q sinφ, Φ_R = M_r,
    Φ_G = (M_p sinφ + M_q cosφ) sinθ + M_r cosθ (``ps`` = ψ' sinθ, ``thd`` = θ'). The
    trapezoidal rule from 4 nodes, doubled until two levels agree to ``rtol`` of the largest
    mean, as :func:`tumble.averaging.nutation.torque_perturbation` averages a moment of the
    body rate only."""
    eye = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    t0, t1, t2 = 0.0, 0.0, 0.0
    n, offset = SPIN_START, 0.0
    old0, old1, old2 = 0.0, 0.0, 0.0
    while n <= SPIN_MAX:
        a0, a1, a2 = 0.0, 0.0, 0.0
        step = 2.0 * math.pi / n
        for j in range(n):
            phi = (j + offset) * step
            cf, sf = math.cos(phi), math.sin(phi)
            m1, m2, m3 = fixed_program(
                p, start, tau, ps * sf + thd * cf, ps * cf - thd * sf, r, eye
            )
            a0 += m1 * cf - m2 * sf
            a1 += m3
            a2 += (m1 * sf + m2 * cf) * s + m3 * c
        if offset == 0.0:
            t0, t1, t2 = a0 / n, a1 / n, a2 / n
            offset = 0.5
            continue
        old0, old1, old2 = t0, t1, t2
        t0, t1, t2 = 0.5 * (t0 + a0 / n), 0.5 * (t1 + a1 / n), 0.5 * (t2 + a2 / n)
        n *= 2
        tol = rtol * max(abs(t0), abs(t1), abs(t2))
        if max(abs(t0 - old0), abs(t1 - old1), abs(t2 - old2)) <= tol:
            return True, t0, t1, t2
    return False, math.nan, math.nan, math.nan


@jit(KERNEL)
def _nutation_sums(
    p: FloatArray, start: int, tau: float, rtol: float, mu: float, R: float, G: float,
    da: float, db: float, cc: float, hh: float, c4: float, q1: float, q0: float, n: int,
    offset: float,
) -> tuple[bool, float, float, float, float, float, float, float]:  # fmt: skip
    """Weighted sums over the nodes φ = (j + offset) 2π/n of u = cc + hh cos φ: Σw, Σw g,
    Σw Φ_R, Σw Φ_G and Σw |g|, Σw |Φ_R|, Σw |Φ_G| (``_engine_averages``)."""
    sw, sg, sr, sgg, ag, ar, agg = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    step = 2.0 * math.pi / n
    for j in range(n):
        phi = (j + offset) * step
        cphi, sphi = math.cos(phi), math.sin(phi)
        u = cc + hh * cphi
        sq = math.sqrt(-((c4 * u + q1) * u + q0))
        s_th = math.sqrt((1.0 - u) * (1.0 + u))
        thd = hh * sphi * sq / s_th  # θ' = −u'/sin θ, u' = −hh sin φ √(−q(u))
        # ψ' = (G − Ru)/(1 − u²) = ½[(G + R)/(1 + u) + (G − R)/(1 − u)]: a pole term whose
        # coefficient vanishes is absent (as in potential_gradient)
        h = 0.0
        if G + R != 0.0:
            h += 0.5 * (G + R) / (1.0 + u)
        if G - R != 0.0:
            h += 0.5 * (G - R) / (1.0 - u)
        ok, ph, pr, pg = _spin_mean(p, start, tau, h * s_th, thd, R / mu, s_th, u, rtol)
        if not ok:
            return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        g = ph * thd - pr * u * h + pg * h + da * u + db * u * u  # Φθθ' + Φz·W^z, (2.3)
        w = 1.0 / sq  # dt ∝ dφ/√(−q(u))
        sw += w
        sg += w * g
        sr += w * pr
        sgg += w * pg
        ag += w * abs(g)
        ar += w * abs(pr)
        agg += w * abs(pg)
    return True, sw, sg, sr, sgg, ag, ar, agg


@jit(KERNEL)
def _engine_averages(
    p: FloatArray, start: int, tau: float, rtol: float, mu: float, R: float, G: float,
    da: float, db: float, u1: float, u2: float, c4: float, q1: float, q0: float,
) -> tuple[bool, float, float, float]:  # fmt: skip
    """(converged, ⟨g⟩, ⟨Φ_R⟩, ⟨Φ_G⟩) over one nutation period for the torque program,
    g = Φθθ' + Φz·W^z: the general engine's nutation setting
    (:func:`tumble.averaging.nutation.numeric_averages`) for a moment of the body rate only.

    The time average as a periodic trapezoidal rule in φ, u = c + h cos φ, where
    dt ∝ dφ/√(−q(u)) (``_x2_by_trapezoid``): the nodes' weights are those of time. Doubled
    from 16 nodes until two levels agree to ``rtol`` of the integrand's size (the largest
    mean |row|, or the largest average), as the Python engine's rule uniform in time. Both
    converge geometrically; next to a separatrix this one needs more nodes (its rate falls
    like √(1 − k²))."""
    cc, hh = 0.5 * (u1 + u2), 0.5 * (u1 - u2)
    ok, sw, sg, sr, sgg, ag, ar, agg = _nutation_sums(
        p, start, tau, rtol, mu, R, G, da, db, cc, hh, c4, q1, q0, NUTATION_START, 0.0
    )
    if not ok:
        return False, math.nan, math.nan, math.nan
    n = NUTATION_START
    while n < NUTATION_MAX:
        ok, sw2, sg2, sr2, sgg2, ag2, ar2, agg2 = _nutation_sums(
            p, start, tau, rtol, mu, R, G, da, db, cc, hh, c4, q1, q0, n, 0.5
        )
        if not ok:
            return False, math.nan, math.nan, math.nan
        old_g, old_r, old_gg = sg / sw, sr / sw, sgg / sw
        sw, sg, sr, sgg = sw + sw2, sg + sg2, sr + sr2, sgg + sgg2
        ag, ar, agg = ag + ag2, ar + ar2, agg + agg2
        n *= 2
        new_g, new_r, new_gg = sg / sw, sr / sw, sgg / sw
        size = max(ag / sw, ar / sw, agg / sw, abs(da), abs(db))
        top = max(abs(new_g), abs(new_r), abs(new_gg), abs(da), abs(db), size, 1e-300)
        change = max(abs(new_g - old_g), abs(new_r - old_r), abs(new_gg - old_gg))
        if change <= rtol * top:
            return True, new_g, new_r, new_gg
    return False, math.nan, math.nan, math.nan


@jit(INLINE)
def nutation_engine(t: float, y: FloatArray, p: FloatArray, out: FloatArray) -> None:
    """Volosov's averaged equations in the energy form, y = [H, R, G, a, b], with the averages
    of a moment of the body rate only (a torque program) by the general engine's nutation
    setting: H′ = ε⟨Φθθ' + Φz·W^z⟩, z′ = ε⟨Φz⟩, Φ_a, Φ_b the pressure's law. Parameters: the
    full kernel's, then [u_hint, rtol, torque program]; NaN where the averages do not exist or
    do not converge, so that the step is rejected."""
    eps = p[_NM.eps]
    base = _TABLE + 2 * int(p[_NM.knots])
    u_hint, rtol = p[base + _NE.u_hint], p[base + _NE.rtol]
    H, R, G, a, b = y[0], y[1], y[2], y[3], y[4]
    w = well_averages(R, G, a, b, H, u_hint, False)
    ok = w[_OK] == 1.0
    if ok:
        u1, u2 = w[_U1], w[_U2]
        s, pr = u1 + u2, u1 * u2
        c4 = 2.0 * b  # the deflation of f, as in well_averages
        q1 = 2.0 * a + c4 * s
        q0 = -2.0 * b - R * R - 2.0 * H + s * q1 - c4 * pr
        tau = eps * t
        rate = pressure_rate(p, tau)
        da, db = p[_NM.a] * rate, p[_NM.b] * rate
        ok, g, pR, pG = _engine_averages(p, base + _NE_PROGRAM, tau, rtol, p[_NM.mu], R, G, da,
                                         db, u1, u2, c4, q1, q0)  # fmt: skip
    if not ok:
        for j in range(5):
            out[j] = math.nan
        return
    out[0] = eps * g
    out[1] = eps * pR
    out[2] = eps * pG
    out[3] = eps * da
    out[4] = eps * db


@jit(KERNEL)
def separatrix_distance(y: FloatArray) -> float:
    """min(barriers) − H for y = [H, R, G, a, b] (1.0 without a barrier): > 0 while the
    energy is below every barrier of W(θ), < 0 above one, as
    :func:`tumble.models.nonlinear_moment.barrier_energies` gives them. A barrier is a local
    maximum of W, a root u* in (−1, 1) of the quintic
    P(u) = (G − Ru)(R − Gu) − (1 − u²)²(a + 2bu) = F(θ) sin³θ at which P rises with u (F falls
    from + to − as θ grows)."""
    H, R, G, a, b = y[0], y[1], y[2], y[3], y[4]
    # P ascending: GR − (G² + R²)u + GR u² − (a + 2bu)(1 − 2u² + u⁴)
    c0, c1, c2 = G * R - a, -(G * G + R * R) - 2.0 * b, G * R + 2.0 * a
    c3, c4, c5 = 4.0 * b, -a, -2.0 * b
    n, r0, r1, r2, r3, r4 = _roots5(c0, c1, c2, c3, c4, c5)
    out = 1.0
    found = False
    for i in range(n):
        u = _pick(i, r0, r1, r2, r3, r4)
        if _poly(c1, 2.0 * c2, 3.0 * c3, 4.0 * c4, 5.0 * c5, 0.0, u) > 0.0:
            w = (G - R * u) ** 2 / (2.0 * (1.0 - u * u)) + a * u + b * u * u  # (1.6)
            out = w - H if not found else min(out, w - H)
            found = True
    return out


@jit(ENTRY)
def nutation_columns(Y: FloatArray, u_hint: float) -> FloatArray:
    """θmax, θmin, k², the period, the root case and H of each averaged state row
    ``[H, R, G, a, b]`` (NaN rows where the averages do not exist), shape (n, 6)."""
    n = Y.shape[0]
    out = np.full((n, 6), math.nan)
    for i in range(n):
        H = Y[i, 0]
        w = well_averages(Y[i, 1], Y[i, 2], Y[i, 3], Y[i, 4], H, u_hint, False)
        if w[_OK] == 0.0:
            continue
        u1, u2 = w[_U1], w[_U2]
        out[i, 0] = 2.0 * math.atan2(math.sqrt(max(1.0 - u2, 0.0)), math.sqrt(max(1.0 + u2, 0.0)))
        out[i, 1] = 2.0 * math.atan2(math.sqrt(max(1.0 - u1, 0.0)), math.sqrt(max(1.0 + u1, 0.0)))
        out[i, 2] = w[_K2]
        out[i, 3] = (2.0 if w[_CASE] == 1.0 else 4.0) * w[_K] / w[_BETA]
        out[i, 4] = w[_CASE]
        out[i, 5] = H
    return out


POLE_CLEARANCE = 1e-4
"""The compiled orbit's nodes (:func:`orbit_nodes`) need 1 − u1 and 1 + u2 above this: they
form 1 ∓ u of the turning points by subtraction, whose error ε_mach/(1 ∓ u) is then below
1e-12 relative, where the Python orbit refines them to full relative accuracy."""


@jit(ENTRY)
def orbit_nodes(X: FloatArray, u_hint: float, n: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """θ [rad] and θ' [rad/t] at the phase nodes t_i = iT/n (i < n) counted from θmax, and
    (ν = 2π/T, u1, u2) of the orbit of each row ``[H, R, G, a, b]`` of ``X`` in the well
    nearest to ``u_hint``: shapes (k, n), (k, n), (k, 3).

    The same nodes as the Python orbit's (:meth:`tumble.unperturbed.symmetric_body.
    NutationOrbit.nodes` of :meth:`~tumble.unperturbed.symmetric_body.NutationOrbit.
    from_energy`): the chart of :func:`_well_chart` at the Jacobi arguments βt_i + τ0 (τ0 = 0
    in case 1, 2K in case 2, where θmax is γ = π), reduced to |v_r| ≤ K; θ from 1 ∓ u as the
    chart's weighted means of the turning points', θ' = −u'/sin θ with u' from dσ/dt, Serov
    (1991), eqs. (1.9)–(1.10). A row is NaN where the well has no answer (no motion, a
    separatrix), where the motion is free (a = b = 0) or steady (u1 = u2), or where a turning
    point is within :data:`POLE_CLEARANCE` of u = ±1: the Python orbit serves those.
    """
    k = X.shape[0]
    theta = np.full((k, n), math.nan)
    theta_dot = np.full((k, n), math.nan)
    info = np.full((k, 3), math.nan)
    for r in range(k):
        ok, u1, u2, _, mc, beta2, case, nu, _, _, _, _, _, _, free = _well_chart(
            X[r, 1], X[r, 2], X[r, 3], X[r, 4], X[r, 0], u_hint
        )
        if not ok or free or not u1 > u2 or min(1.0 - u1, 1.0 + u2) < POLE_CLEARANCE:
            continue
        ua, ub = (u2, u1) if case == 1.0 else (u1, u2)
        beta = math.sqrt(beta2)
        big_k = ellipk_mc(mc)
        ratios, steps, top = agm(mc)
        kc = math.sqrt(mc)
        span = (2.0 if case == 1.0 else 4.0) * big_k  # β T
        info[r, 0] = 2.0 * math.pi * beta / span
        info[r, 1], info[r, 2] = u1, u2
        start = 0.0 if case == 1.0 else 2.0 * big_k
        for i in range(n):
            v = span * i / n + start
            j = round(v / (2.0 * big_k))
            vr = v - 2.0 * big_k * j
            sv, cn, dn = jacobi_quarter(min(abs(vr), big_k), big_k, kc, ratios, steps, top)
            sn = sv if vr >= 0.0 else -sv
            if case == 1.0:
                sig, sigc = sn * sn, cn * cn
                dsig = 2.0 * beta * sn * cn * dn  # d(sn²)/dt
            else:
                half_s, half_c = sn * sn / (2.0 * (1.0 + cn)), 0.5 * (1.0 + cn)
                odd = j % 2 == 1
                sig, sigc = (half_c, half_s) if odd else (half_s, half_c)
                dsig = (-0.5 if odd else 0.5) * beta * sn * dn  # d sin²(γ/2)/dt
            den = sigc + nu * sig
            om = ((1.0 - ua) * sigc + (1.0 - ub) * nu * sig) / den
            op = ((1.0 + ua) * sigc + (1.0 + ub) * nu * sig) / den
            theta[r, i] = 2.0 * math.atan2(math.sqrt(om), math.sqrt(op))
            theta_dot[r, i] = -(ub - ua) * nu * dsig / (den * den) / math.sqrt(om * op)
    return theta, theta_dot, info


@jit(ENTRY)
def evaluate_well(R: float, G: float, a: float, b: float, E: float, u_hint: float) -> FloatArray:
    """:func:`well_averages` from Python, as an array (tests, and the averaged start)."""
    w = well_averages(R, G, a, b, E, u_hint)
    out = np.empty(10)
    for i in range(10):
        out[i] = w[i]
    return out


@jit(ENTRY)
def evaluate_separatrix_distance(y: FloatArray) -> float:
    """:func:`separatrix_distance` from Python."""
    return separatrix_distance(y)
