"""Symmetric rigid body under the moment M0(θ) = A(a sinθ + b sin2θ): exact unperturbed motion.

(1.1)–(1.13), §§3–5 and §8 of spec/serov.md (V. M. Serov 1991, seed 003; the spec supersedes
the seed where they differ, its §12 errata). A is the equatorial and C the axial moment of
inertia, μ = C/A ∈ (0, 2]; R = μr and G = K·e_z/A are the reduced angular momenta, constant
with E = θ'²/2 + W(θ) (1.6). Time is the paper's t, in any unit consistent with a, b
[1/time²] and R, G [1/time].

Representation
--------------
With u = cosθ, u'² = f(u) = 2b(u − u1)(u − u2)(u − u3)(u − u4) (1.7) and the motion lives
on [u2, u1] (u1 = cos θmin). Every closed form here uses one *chart* of (1.9): a turning point
A_* (the anchor, γ = 0), the other one B_* and the pole root P of §4.1, written as the weighted
mean

    u = (A_* (1 − σ) + B_* ν σ) / ((1 − σ) + ν σ),   ν = (P − A_*)/(P − B_*) > 0,

with σ = sin²γ (case 1, δ = 1) or σ = sin²(γ/2) (case 2, δ = ½, ν = ξ of §4.2). This is (1.9)
with L = P, M = A_* − P, N = ν − 1, rewritten so that nothing is infinite when P is (b = 0,
§4.3) or when ξ = 1 (§4.2): a huge or infinite pole root only makes ν → 1. Case 1 uses the
seed's anchoring (A_* = u2, θmax at γ = 0, σ = −1 in (1.10)) for the motion and, for each pole
ρ = ±1 of (1.12), the anchoring whose anchor is the turning point farther from ρ (the
alternative anchoring of §4.3 is the seed's at βt + τ0 + K). Case 2 anchors at u1 (θmin,
σ = +1, errata 4).

Partial fractions are taken about the anchor instead of about L (§5):

    1/(u − ρ) = 1/(A_* − ρ) + ν(A_* − B_*)/(A_* − ρ)² · σ/(1 + (r − 1)σ),  r = ν(B_* − ρ)/(A_* − ρ),

and ∫ σ/(1 + wσ) dγ/Δ = S(γ, w) = (1/3) sin³γ R_J(cos²γ, Δ², 1, 1 + w sin²γ), i.e.
(F − Π(γ, w, k))/w without the 0/0 at w = 0. No 1/(1 ± L) appears, so a pole root P close to
±1 (§11) needs no special treatment and the term (G ∓ R)/(1 ∓ u) stays finite for G → ±R.
In case 2 the same algebra gives (1.13) with the corrected χ±, ϰ±, λ± and L±(γ) of errata
7–9 in a form that is finite at ξ = 1 and at 1 ± L = 0.

Roots and conditioning
----------------------
f is expanded about the initial u0 = cosθ0 with its constant term sin²θ0·θ0'² exact, the
turning points are bracketed on monotone pieces of f (between its critical points, so the
physical interval of a double well is the one containing u0, §3) and refined by bisection;
for turning points near ±1, 1 − u1 and 1 + u2 are computed again from the expansion about
u = ±1, where f(±1) = −(G ∓ R)² is exact, and the value with the smaller error bound is kept,
so that they keep their digits for θ near 0 or π. The other two roots
come from deflation (stable quadratic formula; a root at infinity for b = 0 is carried as
2b·root). The root case is 2 when the discriminant of the deflated quadratic is negative
beyond round-off (§14). Both forms agree where the case switches.

For ordinary orbits a fast path finds the same turning points by safeguarded Newton
iterations and certifies them by that deflation (section "Fast path" below); wherever its
checks fail the bracketing above decides. The Jacobi phase data of t = 0, needed by ψ(t)
and φ(t) only, are computed on first use.

Jacobi functions come from :func:`tumble.unperturbed.euler_poinsot._jacobi` (reduction to a
quarter period with Newton polishing), accurate up to the separatrix; incomplete integrals use
the quasi-periodic reduction of §5.

Limits of the data: see :data:`SEPARATRIX_TOL`, which refuses 1 − k² below 1e-9.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal, NamedTuple

import numpy as np
from scipy import optimize, special

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError, check_finite, check_range
from tumble.unperturbed.euler_poinsot import _jacobi

__all__ = [
    "SEPARATRIX_TOL",
    "NutationOrbit",
    "effective_potential",
    "energy",
    "potential_slope",
    "quartic_coefficients",
]

SEPARATRIX_TOL = 1e-9
"""A motion counts as at a separatrix (infinite period, §11) when 1 − k² < SEPARATRIX_TOL.

Near a separatrix 1 − k² ∝ (E − E_s) on the case-2 side (above a hump of W) but
∝ sqrt(E_s − E) on the case-1 side (inside a well), where an E known to ε_machine fixes
1 − k² only to ~1e-8: there values below 1e-9 arise only from an exact double root. The period
grows like ln(16/(1 − k²))/β, so its relative uncertainty is
δ(1 − k²)/((1 − k²) ln(16/(1 − k²)))."""

_EPS = float(np.finfo(float).eps)
_POLE_REFINE = 0.5  # refine a turning point about u = ±1 when it lies this close to ±1
_X2_CLOSED_DIST = 0.02  # ⟨X²⟩ by (∂R_J/∂p) only when p is this far from 1 − k² and 1 (case 1)
_MOMENT_RTOL = 1e-13  # recurrence of §8 accepted while its error bound stays below this
_QUAD_RTOL = 4e-16  # internal trapezoid fallbacks: converged to round-off
_N_START = 32  # first trapezoid level of :meth:`NutationOrbit.average`
_POLE_TOUCH = 1e-280  # 1 ∓ u at a turning point below this: the axis passes through ±e_z

Kind = Literal["elliptic", "steady", "free"]


# --------------------------------------------------------------------------------------
# Potential, slope, energy, f(u)
# --------------------------------------------------------------------------------------


def _theta_array(theta: ArrayLike, name: str = "theta") -> FloatArray:
    th = np.asarray(theta, dtype=float)
    ok = np.isfinite(th) & (th > 0.0) & (th < math.pi)
    if not np.all(ok):
        bad = float(th[~ok].flat[0]) if th.ndim else float(th)
        raise ParameterError(f"{name} = {bad:g} is outside the allowed range (0, π)")
    return th


def _finite(**values: float) -> None:
    for name, value in values.items():
        check_finite(name, float(value))


def effective_potential(theta: ArrayLike, R: float, G: float, a: float, b: float) -> FloatArray:
    """Effective potential W(θ) of the nutation, (1.6) of spec/serov.md.

    W(θ) = (G − R cosθ)²/(2 sin²θ) + a cosθ + b cos²θ.

    Parameters
    ----------
    theta : array_like
        Nutation angle [rad], strictly inside (0, π).
    R, G : float
        Reduced angular momenta μr and K·e_z/A [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].

    Returns
    -------
    ndarray
        W [1/time²], shape of ``theta`` (0-d for a scalar).

    Raises
    ------
    ParameterError
        θ outside (0, π) or an input not finite (W is infinite at θ = 0, π unless G = ±R).
    """
    _finite(R=R, G=G, a=a, b=b)
    th = _theta_array(theta)
    u, s = np.cos(th), np.sin(th)
    return np.asarray((G - R * u) ** 2 / (2.0 * s * s) + a * u + b * u * u, dtype=float)


def potential_slope(theta: ArrayLike, R: float, G: float, a: float, b: float) -> FloatArray:
    """Slope F(θ) = ∂W/∂θ of the effective potential, (2.1) of spec/serov.md.

    F(θ) = (G − R cosθ)(R − G cosθ)/sin³θ − a sinθ − b sin2θ; θ'' + F = 0 is the nutation.

    Parameters
    ----------
    theta : array_like
        Nutation angle [rad], strictly inside (0, π).
    R, G : float
        Reduced angular momenta [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].

    Returns
    -------
    ndarray
        F [1/time²], shape of ``theta``.

    Raises
    ------
    ParameterError
        θ outside (0, π) or an input not finite.
    """
    _finite(R=R, G=G, a=a, b=b)
    th = _theta_array(theta)
    u, s = np.cos(th), np.sin(th)
    return np.asarray((G - R * u) * (R - G * u) / s**3 - a * s - b * np.sin(2.0 * th), dtype=float)


def energy(
    theta: ArrayLike, theta_dot: ArrayLike, R: float, G: float, a: float, b: float
) -> FloatArray:
    """Energy integral E = θ'²/2 + W(θ), (1.6) of spec/serov.md.

    Parameters
    ----------
    theta : array_like
        Nutation angle [rad], strictly inside (0, π).
    theta_dot : array_like
        Nutation rate θ' [rad/time].
    R, G : float
        Reduced angular momenta [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].

    Returns
    -------
    ndarray
        E [1/time²], broadcast shape of ``theta`` and ``theta_dot``.
    """
    td = np.asarray(theta_dot, dtype=float)
    if not np.all(np.isfinite(td)):
        raise ParameterError("theta_dot must be finite")
    return np.asarray(0.5 * td * td + effective_potential(theta, R, G, a, b), dtype=float)


def quartic_coefficients(R: float, G: float, a: float, b: float, E: float) -> FloatArray:
    """Coefficients g0 … g4 of f(u) = u'² = Σ g_i u^i, (1.7) of spec/serov.md.

    g0 = 2E − G², g1 = 2(GR − a), g2 = −2b − R² − 2E, g3 = 2a, g4 = 2b.

    Parameters
    ----------
    R, G : float
        Reduced angular momenta [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].
    E : float
        Energy (1.6) [1/time²].

    Returns
    -------
    ndarray, shape (5,)
        (g0, g1, g2, g3, g4), ascending powers of u [1/time²].
    """
    _finite(R=R, G=G, a=a, b=b, E=E)
    return np.array(
        [2.0 * E - G * G, 2.0 * (G * R - a), -2.0 * b - R * R - 2.0 * E, 2.0 * a, 2.0 * b]
    )


# --------------------------------------------------------------------------------------
# Polynomials (plain floats: called inside bisection loops)
# --------------------------------------------------------------------------------------


def _horner(c: tuple[float, ...], x: float) -> float:
    if len(c) == 5:  # the quartics of this module, unrolled (the same operations)
        c0, c1, c2, c3, c4 = c
        return (((c4 * x + c3) * x + c2) * x + c1) * x + c0
    acc = 0.0
    for ci in reversed(c):
        acc = acc * x + ci
    return acc


def _dhorner(c: tuple[float, ...], x: float) -> float:
    if len(c) == 5:
        _, c1, c2, c3, c4 = c
        return ((4 * c4 * x + 3 * c3) * x + 2 * c2) * x + c1
    acc = 0.0
    for i in range(len(c) - 1, 0, -1):
        acc = acc * x + i * c[i]
    return acc


def _noise(c: tuple[float, ...], x: float) -> float:
    """Round-off level of _horner(c, x): a few ulps of Σ|c_i x^i|."""
    ax = abs(x)
    if len(c) == 5:
        c0, c1, c2, c3, c4 = c
        return (
            16.0
            * _EPS
            * (abs(c0) + abs(c1) * ax + abs(c2) * ax**2 + abs(c3) * ax**3 + abs(c4) * ax**4)
        )
    return 16.0 * _EPS * sum(abs(ci) * ax**i for i, ci in enumerate(c))


def _critical_points(c: tuple[float, ...], lo: float, hi: float) -> list[float]:
    """Real parts of the roots of p'(x) inside (lo, hi), Newton-polished, sorted.

    Every root's real part is kept, real or not: extra points only subdivide the monotone
    pieces, while a true critical point mistaken for a complex one would merge two pieces.
    """
    d = [i * c[i] for i in range(len(c) - 1, 0, -1)]  # descending coefficients of p'
    # A leading coefficient below 1e-18 of the others only adds a root beyond 1e17 (and
    # moves the others by ~1e-18 on |x| ≤ 2): drop it, also against overflow in np.roots.
    while d and abs(d[0]) <= 1e-18 * max(abs(x) for x in d):
        d.pop(0)
    if len(d) < 2:
        return []
    dd = tuple(i * c[i] for i in range(1, len(c)))  # ascending coefficients of p'
    out = []
    for z in np.roots(d):
        x = float(z.real)
        for _ in range(3):
            slope = _dhorner(dd, x)
            if slope == 0.0:
                break
            step = _horner(dd, x) / slope
            if not math.isfinite(step) or abs(step) > 1e-3 * (1.0 + abs(x)):
                break
            x -= step
        if lo < x < hi:
            out.append(x)
    return sorted(out)


def _root_between(c: tuple[float, ...], lo: float, hi: float) -> float:
    """Root of the polynomial c in [lo, hi], where c changes sign (exact end values).

    If round-off makes the evaluated polynomial keep its sign, the root is within round-off of
    the end where |c| is smaller.
    """
    f0, f1 = _horner(c, lo), _horner(c, hi)
    if f0 == 0.0:
        return lo
    if f1 == 0.0:
        return hi
    if (f0 > 0.0) == (f1 > 0.0):
        return lo if abs(f0) < abs(f1) else hi
    # xtol ~ 0: a root next to x = 0 (a start next to a turning point) keeps relative accuracy;
    # that can take ~1000 bisections, and the last iterate is returned in any case (disp=False).
    root = optimize.brentq(
        lambda x: _horner(c, x), lo, hi, xtol=1e-300, rtol=4.0 * _EPS, maxiter=3000, disp=False
    )
    return float(root)


def _first_root(
    c: tuple[float, ...], c0_exact: float, end: float, end_value: float, crit: list[float]
) -> float:
    """First root x > 0 of the polynomial c (in x ≥ 0) up to ``end``, where c(end) = end_value ≤ 0.

    c(0) = c0_exact ≥ 0. With c(0) = 0 (a turning-point start, c'(0) > 0 assumed) the first
    piece must rise; if it does not within round-off the amplitude is below resolution and 0
    is returned.
    """
    pts = [x for x in crit if 0.0 < x < end]  # critical points of c, ascending
    prev, prev_val = 0.0, c0_exact
    for x in [*pts, end]:
        val = end_value if x == end else _horner(c, x)
        if val <= 0.0:
            if prev_val <= 0.0:
                return 0.0  # turning start whose first piece never rises: no resolvable swing
            if x == end and end_value == 0.0:
                return end  # f(±1) = 0 exactly (G = ±R): the motion reaches the pole
            return _root_between(c, prev, x)
        prev, prev_val = x, val
    return end  # unreachable: end_value ≤ 0


def _reflect(c: tuple[float, ...]) -> tuple[float, ...]:
    """Coefficients of p(−x)."""
    return tuple(ci if i % 2 == 0 else -ci for i, ci in enumerate(c))


def _pole_coefficients(
    side: int, h0: float, u0: float, dp: float, dm: float, R: float, G: float, a: float, b: float
) -> tuple[float, ...]:
    """Coefficients e_i of f(side·(1 − ε)) in ε (u = 1 − ε for side = +1, −1 + ε for −1).

    e0 = −(G ∓ R)² exactly (§3); h = E ∓ a − b is formed from h0 = E − a u0 − b u0².
    """
    if side > 0:
        h = h0 - a * dp - b * dp * dm  # E − a − b
        k = a + 2.0 * b
        g = G - R
        e1 = 4.0 * h - 2.0 * R * g
    else:
        h = h0 + a * dm - b * dp * dm  # E + a − b
        k = -a + 2.0 * b
        g = G + R
        e1 = 4.0 * h + 2.0 * R * g
    return (-g * g, e1, 4.0 * k - 2.0 * h - R * R, -4.0 * b - 2.0 * k, 2.0 * b)


def _pole_distance(c: tuple[float, ...], x: float, end: float, e: tuple[float, ...]) -> float:
    """Distance end − x from a turning point x ≥ 0 (in the variable of c) to the pole at ``end``.

    Either end − x directly or refined about the pole (expansion e, exact constant term),
    whichever has the smaller error bound (round-off of the polynomial over |slope|).
    """
    direct = end - x
    if x <= 0.0 or direct >= _POLE_REFINE:
        return direct
    slope = abs(_dhorner(c, x))
    if slope == 0.0:
        return direct
    refined = _refine_pole_distance(e, direct)
    err_direct = 4.0 * _EPS * end + _noise(c, x) / slope
    err_refined = _noise(e, refined) / slope
    return refined if err_refined < err_direct else direct


def _refine_pole_distance(e: tuple[float, ...], eps0: float) -> float:
    """Root ε ≥ 0 of Σ e_i ε^i near eps0 by safeguarded Newton (e0 exact)."""
    if e[0] == 0.0 and eps0 <= _noise(e, eps0) / max(abs(e[1]), 1e-300):
        return 0.0  # f(±1) = 0 and the turning point is the pole itself
    x = eps0
    fx = _horner(e, x)
    for _ in range(8):
        slope = _dhorner(e, x)
        if slope == 0.0:
            break
        nxt = x - fx / slope
        if not (nxt >= 0.0 and math.isfinite(nxt)) or abs(nxt - eps0) > 0.5 * max(eps0, 1e-300):
            break  # left the root's neighbourhood: keep the bracketed value
        fn = _horner(e, nxt)
        if abs(fn) > abs(fx):
            break
        done = abs(nxt - x) <= 4.0 * _EPS * nxt
        x, fx = nxt, fn
        if done:
            break
    return x


# --------------------------------------------------------------------------------------
# Fast path for the turning points (plain floats, certified, else the careful path)
# --------------------------------------------------------------------------------------
#
# The careful path brackets every root on a monotone piece of f, between critical points
# from np.roots, and refines it by brentq: robust, but ~0.5 ms per orbit, and the averaged
# equations build an orbit at every right-hand side. The fast path finds the same turning
# points by Newton's method safeguarded by bisection on a sign-change bracket whose end
# values are exact (c(0) and f(±1) = −(G ∓ R)², §3) and then *certifies* them: deflating the
# two turning points leaves a quadratic whose roots (the other two roots of f) must lie at a
# distance of at least _FAST_MARGIN × (u1 − u2) from [u2, u1] in the complex plane. Then f > 0
# on (u2, u1) and nowhere else nearby, so they are the roots the careful path brackets, to
# round-off (measured: as close to the exact roots of the same floating-point polynomial as
# the careful ones). from_energy first finds the well the same way as _allowed_intervals
# does, with the critical points in closed form, when every critical value and f(±1) are
# clearly nonzero. Anything else (a near-double root: separatrix, steady precession, an
# energy at round-off level of a minimum of W; f(±1) at round-off level, G ≈ ±R; f'(u0) at
# round-off level at a turning start; a closed form it cannot trust; a failed iteration)
# returns None, and the careful path decides, with its own results and error messages.

_FAST_MARGIN = 1e-3  # other roots this far (relative to u1 − u2) from the interval: certified
_FAST_CLEAR = 1e3  # a value counts as nonzero when this many times its round-off bound
_FAST_EDGE = 1e-9  # from_energy: roots this far outside [−1, 1] are certainly outside
_FAST_LEAD = 1e-3  # cubic p' with |leading| below this × the others: divide the huge root out
_FAST_CUBIC = 1e-4  # … and below this, if that fails, no closed form at all (None)
_FAST_MAXITER = 200  # Newton–bisection steps before giving up (bisection alone needs ≤ ~1100)

_Side = tuple[tuple[float, ...], float, float]  # one side of u0: (c(±δ) or c(±δ)/δ, at 0, at ±1)


def _bracket_root(c: tuple[float, ...], pos: float, neg: float, x: float) -> float | None:
    """Root of the polynomial c between pos (c > 0) and neg (c < 0), starting at x between.

    Newton steps while they stay inside the bracket and shrink fast enough, else bisection
    (rtsafe). Stops when a step is below 2 ulp of x, or when Newton stops converging with
    c(x) at its round-off level (the last step has put x within the actual evaluation error
    over the slope of the root): the root to round-off, like brentq with rtol = 4ε in
    :func:`_root_between`. None if it does not settle.
    """
    last = abs(neg - pos)
    c0, c1, c2, c3, c4 = (*c, 0.0, 0.0)[:5] if len(c) < 5 else c  # degree ≤ 4, unrolled
    a0, a1, a2, a3, a4 = abs(c0), abs(c1), abs(c2), abs(c3), abs(c4)
    for _ in range(_FAST_MAXITER):
        fx = (((c4 * x + c3) * x + c2) * x + c1) * x + c0
        slope = ((4.0 * c4 * x + 3.0 * c3) * x + 2.0 * c2) * x + c1
        ax = abs(x)
        mag = (((a4 * ax + a3) * ax + a2) * ax + a1) * ax + a0
        if fx == 0.0:
            return x
        if fx > 0.0:
            pos = x
        else:
            neg = x
        lo, hi = (pos, neg) if pos < neg else (neg, pos)
        nxt = x - fx / slope if slope != 0.0 else lo
        if not lo < nxt < hi or abs(nxt - x) > 0.5 * last:
            if abs(fx) <= 4.0 * _EPS * mag:
                return x  # Newton jitters in the round-off band of c: x is the root
            nxt = 0.5 * (lo + hi)
        last = abs(nxt - x)
        x = nxt
        if last <= 2.0 * _EPS * abs(x):
            return x
    return None


def _regula_falsi(lo: float, f_lo: float, hi: float, f_hi: float) -> float:
    """Secant point of a sign-change bracket, kept strictly inside it."""
    x = lo + (hi - lo) * (f_lo / (f_lo - f_hi))
    return x if min(lo, hi) < x < max(lo, hi) else 0.5 * (lo + hi)


def _clear_of(c4: float, q1: float, q0: float, lo: float, hi: float, margin: float) -> bool:
    """Whether every root of c4 z² + q1 z + q0 is farther than margin from [lo, hi] in ℂ."""

    def far(re: float, im: float) -> bool:
        gap = lo - re if re < lo else (re - hi if re > hi else 0.0)
        return math.hypot(gap, im) > margin

    if c4 == 0.0:
        if q1 == 0.0:
            return q0 != 0.0  # a nonzero constant: no root
        return far(-q0 / q1, 0.0)
    disc = q1 * q1 - 4.0 * c4 * q0
    if not math.isfinite(disc):
        return False
    if disc < 0.0:
        return far(-q1 / (2.0 * c4), math.sqrt(-disc) / (2.0 * abs(c4)))
    qq = -0.5 * (q1 + math.copysign(math.sqrt(disc), q1))
    if qq == 0.0:
        return False  # q1 = q0 = 0: a double root at 0
    return far(qq / c4, 0.0) and far(q0 / qq, 0.0)


def _deflate(c: tuple[float, ...], d1: float, d2: float) -> tuple[float, float, float]:
    """(c4, q1, q0) with c = (δ − d1)(δ − d2)(c4 δ² + q1 δ + q0), as in :func:`_build`."""
    s, pr = d1 + d2, d1 * d2
    q1 = c[3] + c[4] * s
    return c[4], q1, c[2] + s * q1 - c[4] * pr


def _certified(c: tuple[float, ...], d1: float, d2: float) -> bool:
    """Whether f > 0 on (d2, d1) with no other root of c nearby (deflation, as in _build)."""
    width = d1 - d2
    if not width > 0.0:
        return False
    c4, q1, q0 = _deflate(c, d1, d2)
    mid = 0.5 * (d1 + d2)
    # c = (δ − d1)(δ − d2) q(δ): c > 0 between the roots needs q < 0 there
    return (c4 * mid + q1) * mid + q0 < 0.0 and _clear_of(c4, q1, q0, d2, d1, _FAST_MARGIN * width)


def _inner_pair(c: tuple[float, ...], d1: float, d2: float) -> tuple[float, float] | None:
    """The two other roots of c if both are real and on one side of 0 inside (d2, d1).

    Then the bracketed search has found a root beyond the first one (a double well whose
    other well lies between u0 and ±1): the first root is the one of the pair nearer to 0.
    """
    c4, q1, q0 = _deflate(c, d1, d2)
    if c4 == 0.0:
        return None
    disc = q1 * q1 - 4.0 * c4 * q0
    if not disc > 0.0:
        return None
    qq = -0.5 * (q1 + math.copysign(math.sqrt(disc), q1))
    if qq == 0.0:
        return None
    z1, z2 = sorted((qq / c4, q0 / qq))
    return (z1, z2) if d2 < z1 and z2 < d1 and (z1 > 0.0) == (z2 > 0.0) else None


def _fast_turning_points(
    c: tuple[float, ...],
    dp: float,
    dm: float,
    end_up: float,
    end_dn: float,
    side: Literal["lower"] | None,
    c1_noise: float,
    d1_guess: float | None,
) -> tuple[float, float] | None:
    """(δ1, δ2) of :func:`_build` by the fast path, or None (section notes above).

    c: f(u0 + δ) with c0 = c(0) exact; dp = 1 − u0, dm = 1 + u0; end_up, end_dn = f(±1).
    On each side the root is searched on (0, dp) or (0, dm) of c(±δ) (of c(±δ)/δ at a
    turning start: the same sign for δ > 0). If the deflation then shows the two other roots
    between 0 and the root found, the search is repeated up to the midpoint of that pair
    (where c < 0 is checked), from the one nearer to 0.
    """
    if not all(math.isfinite(x) for x in c):
        return None
    if not (end_up < -_FAST_CLEAR * _noise(c, dp) and end_dn < -_FAST_CLEAR * _noise(c, -dm)):
        return None  # f(±1) at round-off level (G ≈ ±R): the careful path's case
    try:
        c0, c1 = c[0], c[1]
        up: _Side | None
        dn: _Side | None
        if c0 > 0.0:
            up, dn = (c, c0, end_up), (_reflect(c), c0, end_dn)
        elif c0 == 0.0 and abs(c1) > _FAST_CLEAR * c1_noise:
            # Turning start: δ = 0 is a root; the other turning point is the first root on
            # the side where f rises (§3).
            if c1 > 0.0:
                up, dn = (c[1:], c1, end_up / dp), None
            elif side is None:
                up, dn = None, (_reflect(c)[1:], -c1, end_dn / dm)
            else:
                return None  # "lower" with f'(u2) < 0: the careful path's steady fallback
        else:
            return None

        def search(spec: _Side, end: float, f_end: float, x0: float | None) -> float | None:
            poly, f0, _ = spec
            start = _regula_falsi(0.0, f0, end, f_end) if x0 is None else x0
            return _bracket_root(poly, 0.0, end, start)

        guess = d1_guess if d1_guess is not None and 0.0 < d1_guess < dp else None
        r1 = 0.0 if up is None else search(up, dp, up[2], guess)
        r2 = 0.0 if dn is None else search(dn, dm, dn[2], None)
        for _ in range(3):
            if r1 is None or r2 is None:
                return None
            d1, d2 = r1, -r2
            pair = _inner_pair(c, d1, d2)
            if pair is None:
                break
            z1, z2 = pair
            mid = 0.5 * (z1 + z2)
            if mid > 0.0 and up is not None:
                f_mid = _horner(up[0], mid)
                r1 = search(up, mid, f_mid, z1) if f_mid < 0.0 else None
            elif mid < 0.0 and dn is not None:
                f_mid = _horner(dn[0], -mid)
                r2 = search(dn, -mid, f_mid, -z2) if f_mid < 0.0 else None
            else:
                return None
        else:
            return None
        if not (d1 < dp and -d2 < dm and _certified(c, d1, d2)):
            return None
        return d1, d2
    except (ArithmeticError, ValueError):  # pragma: no cover - plain-float overflow guard
        return None


def _quadratic_real_parts(q2: float, q1: float, q0: float) -> list[float]:
    """Real parts of the roots of q2 x² + q1 x + q0 (q2 ≠ 0), stable quadratic formula."""
    disc = q1 * q1 - 4.0 * q2 * q0
    if disc < 0.0:
        return [-q1 / (2.0 * q2)]
    qq = -0.5 * (q1 + math.copysign(math.sqrt(disc), q1))
    return [qq / q2, q0 / qq] if qq != 0.0 else [0.0]


def _cubic_real_parts(d0: float, d1: float, d2: float, d3: float) -> list[float] | None:
    """Real parts of the roots of d0 x³ + d1 x² + d2 x + d3 (d0 ≠ 0), unpolished; None if unsure.

    Trigonometric or Cardano form. With |d0| small against the others (small |b|) that form
    loses the small roots to cancellation: then the one huge root, Newton-refined from
    −d1/d0, is divided out backwards (stable for the largest root) and the small ones come
    from the quotient.
    """
    big = max(abs(d1), abs(d2), abs(d3))
    if abs(d0) < _FAST_LEAD * big and d1 != 0.0:
        asc = (d3, d2, d1, d0)
        r = -d1 / d0
        for _ in range(8):
            slope = _dhorner(asc, r)
            if slope == 0.0:
                break
            step = _horner(asc, r) / slope
            r -= step
            if abs(step) <= 1e-14 * abs(r):
                q0 = -d3 / r
                q1 = (q0 - d2) / r
                small = _quadratic_real_parts((q1 - d1) / r, q1, q0)
                if max(abs(x) for x in small) <= 0.1 * abs(r):
                    return [r, *small]
                break
        if abs(d0) < _FAST_CUBIC * big:
            return None  # two large roots and a tiny d0: neither form is reliable
    A, B, C = d1 / d0, d2 / d0, d3 / d0
    Q = (A * A - 3.0 * B) / 9.0
    Rq = (2.0 * A * A * A - 9.0 * A * B + 27.0 * C) / 54.0
    shift = A / 3.0
    Q3 = Q * Q * Q
    if Rq * Rq < Q3:  # three real roots
        th = math.acos(max(-1.0, min(1.0, Rq / math.sqrt(Q3))))
        r = -2.0 * math.sqrt(Q)
        third = 2.0 * math.pi / 3.0
        return [r * math.cos(th / 3.0 + k * third) - shift for k in (-1, 0, 1)]
    S = -math.copysign(math.cbrt(abs(Rq) + math.sqrt(Rq * Rq - Q3)), Rq)
    T = Q / S if S != 0.0 else 0.0
    return [S + T - shift, -0.5 * (S + T) - shift]


def _fast_critical_points(c: tuple[float, ...], lo: float, hi: float) -> list[float] | None:
    """:func:`_critical_points` of a quartic c with p' solved in closed form, not by np.roots.

    Real parts of complex pairs are kept and the same Newton polishing follows, as there.
    None when the closed form is unsure (:func:`_cubic_real_parts`).
    """
    e1, e2, e3, e4 = c[1], 2.0 * c[2], 3.0 * c[3], 4.0 * c[4]  # ascending coefficients of p'
    d = [e4, e3, e2, e1]
    while d and abs(d[0]) <= 1e-18 * max(abs(x) for x in d):
        d.pop(0)
    raw: list[float] | None
    if len(d) < 2:
        return []
    if len(d) == 4:
        raw = _cubic_real_parts(d[0], d[1], d[2], d[3])
        if raw is None or not all(math.isfinite(x) for x in raw):
            return None
    elif len(d) == 3:
        raw = _quadratic_real_parts(d[0], d[1], d[2])
    else:
        raw = [-d[1] / d[0]]
    out = []
    for x in raw:
        if not lo - 4e-3 * (1.0 + abs(x)) < x < hi + 4e-3 * (1.0 + abs(x)):
            continue  # three polishing steps of ≤ 1e-3 (1 + |x|) cannot bring it inside
        for _ in range(3):
            slope = (3.0 * e4 * x + 2.0 * e3) * x + e2
            if slope == 0.0:
                break
            step = (((e4 * x + e3) * x + e2) * x + e1) / slope
            if not math.isfinite(step) or abs(step) > 1e-3 * (1.0 + abs(x)):
                break
            x -= step
        if lo < x < hi:
            out.append(x)
    return sorted(out)


def _fast_interval(
    g: tuple[float, ...], R: float, G: float, u_hint: float
) -> tuple[float, float] | None:
    """The allowed interval of from_energy by the fast path, or None (section notes above).

    The walk of :func:`_allowed_intervals` over the monotone pieces of f between its critical
    points, certified when every critical value in (−1, 1) is clearly nonzero (no well at
    round-off level, so that function's special cases do not arise) and the sign changes are
    all the roots of f in [−1, 1]: four (f has no more), or two whose deflation leaves no
    root within _FAST_EDGE of [−1, 1]. Of two wells only the roots of the chosen one are
    refined when their brackets already decide the choice (the nearest to u_hint, the lower
    one on a tie, as there).
    """
    if not all(math.isfinite(x) for x in g):
        return None
    end_dn, end_up = -((G + R) ** 2), -((G - R) ** 2)  # f(−1), f(1): exact (§3)
    clear = _FAST_CLEAR * 16.0 * _EPS * sum(abs(x) for x in g)  # ≥ that × _noise on [−1, 1]
    if not (end_dn < -clear and end_up < -clear):
        return None  # f(±1) at round-off level (G ≈ ±R): the careful path's case
    try:
        crit = _fast_critical_points(g, -1.0, 1.0)
        if crit is None:
            return None
        vals = [_horner(g, x) for x in crit]
        if any(abs(v) <= clear for v in vals):
            return None
        pts, fv = [-1.0, *crit, 1.0], [end_dn, *vals, end_up]
        brackets = [
            (pts[i], fv[i], pts[i + 1], fv[i + 1])
            for i in range(len(pts) - 1)
            if (fv[i] > 0.0) != (fv[i + 1] > 0.0)
        ]

        def refine(k: int) -> float | None:
            x0, f0, x1, f1 = brackets[k]
            pos, neg = (x0, x1) if f0 > 0.0 else (x1, x0)
            return _bracket_root(g, pos, neg, _regula_falsi(x0, f0, x1, f1))

        if len(brackets) == 4:
            # Four sign changes: all roots of f are real and each is alone in its bracket.
            # Distance of a well (lo, hi) to u_hint, max(lo − u_hint, u_hint − hi, 0), is
            # bounded through the brackets of lo (k) and hi (k + 1).
            def bounds(k: int) -> tuple[float, float]:
                lo_a, lo_b = brackets[k][0], brackets[k][2]
                hi_a, hi_b = brackets[k + 1][0], brackets[k + 1][2]
                least = max(lo_a - u_hint, u_hint - hi_b, 0.0)
                return least, max(lo_b - u_hint, u_hint - hi_a, 0.0)

            (least0, most0), (least1, most1) = bounds(0), bounds(2)
            if most0 < least1:
                wells = [0]
            elif most1 < least0:
                wells = [2]
            else:
                wells = [0, 2]
            found = []
            for k in wells:
                lo_k, hi_k = refine(k), refine(k + 1)
                if lo_k is None or hi_k is None:
                    return None
                found.append((lo_k, hi_k))
            lo, hi = min(found, key=lambda iv: max(iv[0] - u_hint, u_hint - iv[1], 0.0))
            c4, q1, q0 = _deflate(g, lo, hi)
        elif len(brackets) == 2:
            lo_0, hi_0 = refine(0), refine(1)
            if lo_0 is None or hi_0 is None:
                return None
            lo, hi = lo_0, hi_0
            c4, q1, q0 = _deflate(g, lo, hi)
            if not _clear_of(c4, q1, q0, -1.0, 1.0, _FAST_EDGE):
                return None  # two more roots in [−1, 1]: a well the walk has missed
        else:
            return None  # no motion with this energy: the careful path raises
        # The other roots well away from the well (no separatrix, no near-double root).
        return (lo, hi) if _clear_of(c4, q1, q0, lo, hi, _FAST_MARGIN * (hi - lo)) else None
    except (ArithmeticError, ValueError):  # pragma: no cover - plain-float overflow guard
        return None


# --------------------------------------------------------------------------------------
# Carlson pieces
# --------------------------------------------------------------------------------------


def _ellipf_scalar(s: float, c: float, mc: float) -> float:
    """F(φ | m) from s = sin φ, c = cos φ ≥ 0: :func:`_ellipf_sc` for plain floats."""
    return s * float(special.elliprf(c * c, c * c + mc * s * s, 1.0))


def _rj_complete(mc: float, p: float) -> float:
    return float(special.elliprj(0.0, mc, 1.0, p))


def _drj_dp(mc: float, p: float) -> float:
    """∂R_J(0, mc, 1, p)/∂p by integration by parts (derived for this module).

    With s(t) = t(t + Y)(t + Z) ({Y, Z} = {mc, 1}) and d/dt[√s/((t + p)(t + Z))] integrated over
    (0, ∞): −I_F + c_b I_D + c_c I_J + c_d J2 = 0, I_F = 2R_F, I_D = (2/3)R_D(0, Y, Z),
    I_J = (2/3)R_J, J2 = −(2/3)∂R_J/∂p, c_b = Z(Y − Z)/(p − Z), c_c = 3p − 2Y + Z − c_b,
    c_d = 2p(Y − p). Removable 0/0 at p = Y and p = Z, i.e. at n = m and n = 0 (§8): callers
    keep away from them.
    """
    Y, Z = (mc, 1.0) if abs(p - mc) >= abs(p - 1.0) else (1.0, mc)
    i_f = 2.0 * float(special.elliprf(0.0, Y, Z))
    i_d = 2.0 / 3.0 * float(special.elliprd(0.0, Y, Z))
    i_j = 2.0 / 3.0 * _rj_complete(mc, p)
    cb = Z * (Y - Z) / (p - Z)
    cc = 3.0 * p - 2.0 * Y + Z - cb
    cd = 2.0 * p * (Y - p)
    return 1.5 * (-i_f + cb * i_d + cc * i_j) / cd


def _s_integral(
    sn: FloatArray, cn: FloatArray, dn: FloatArray, j: FloatArray, p: float, Sc: float
) -> FloatArray:
    """S(γ) = ∫0^γ sin²/((1 + (p − 1) sin²)Δ), γ = jπ + γr, from sn γr, cn γr ≥ 0, Δ (§5)."""
    s2, c2 = sn * sn, cn * cn
    return np.asarray(
        2.0 * j * Sc + sn * s2 * special.elliprj(c2, dn * dn, 1.0, c2 + p * s2) / 3.0, dtype=float
    )


def _lam_integral(sin_g: FloatArray, dn: FloatArray, lam: float) -> FloatArray:
    """Λ(γ) = λ⁻¹ arctan(λ sinγ/Δ) = −L(γ) of (1.13) (errata 8); sinγ/Δ when λ = 0."""
    y = sin_g / dn
    if lam == 0.0:
        return np.asarray(y, dtype=float)
    return np.asarray(np.arctan(lam * y) / lam, dtype=float)


# --------------------------------------------------------------------------------------
# Internal structures
# --------------------------------------------------------------------------------------


# NamedTuples, not frozen dataclasses: as immutable, and several are built per orbit.


class _Point(NamedTuple):
    """A turning point: u, 1 − u and 1 + u, each to full relative accuracy."""

    u: float
    om: float  # 1 − u
    op: float  # 1 + u
    d: float  # u − u0 (the δ coordinate)

    def minus(self, rho: float) -> float:
        """u − ρ, exact in the last digits for ρ = ±1."""
        if rho == 1.0:
            return -self.om
        if rho == -1.0:
            return self.op
        return self.u - rho


class _Chart(NamedTuple):
    """u = (A (1 − σ) + B ν σ)/((1 − σ) + ν σ); Jacobi argument βt + τ0 + offset."""

    A: _Point
    B: _Point
    nu: float
    offset: float  # 0 (main chart) or K (case 1, anchored at the other turning point)


class _Pole(NamedTuple):
    """∫0^t dt/(u − ρ) = sec·t + (cper/β)·[kS (S − S0) − (Λ − Λ0)] (Λ only in case 2).

    S0 = S(γ0) and Λ0 = Λ(γ0) belong to the phase at t = 0 and are needed only by ψ(t), φ(t):
    they are computed on first use (:attr:`NutationOrbit._pole_starts`, :func:`_pole_start`).
    """

    sec: float
    cper: float
    kS: float
    p: float  # fourth Carlson argument coefficient: 1 + w
    Sc: float  # S(π/2) = R_J(0, 1 − k², 1, p)/3
    lam: float  # case 2 only
    chart: _Chart  # case 1: whose Jacobi argument

    def mean(self, K: float) -> float:
        return self.sec + self.cper * self.kS * self.Sc / K


@dataclass(frozen=True)
class _Jac:
    """Jacobi functions of βt + τ0 + offset, reduced (§5): v = 2jK + v_r, |v_r| ≤ K."""

    sn: FloatArray  # sn v_r (with sign)
    cn: FloatArray  # cn v_r ≥ 0
    dn: FloatArray
    j: FloatArray


# --------------------------------------------------------------------------------------
# The orbit
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class NutationOrbit:
    """Unperturbed motion through a given state, (1.9)–(1.13) of spec/serov.md.

    Frozen: R, G, a, b and E are constants of this motion. Build it with :meth:`from_state`,
    :meth:`from_turning_point` or :meth:`from_energy`; t = 0 is the construction state.

    Attributes
    ----------
    mu : float
        C/A [1], in (0, 2].
    a, b : float
        Moment coefficients of (1.5) [1/time²].
    R, G : float
        Reduced angular momenta [1/time].
    E : float
        Energy (1.6) [1/time²].
    root_case : int
        1 (u3, u4 real; also b = 0 and a = b = 0) or 2 (complex pair), §3 and §14.
    roots : ndarray, complex, shape (4,)
        (u1, u2, u3, u4) in the cyclic labelling of §3 (u1 → u4 → u3 → u2 going upwards from u1
        through ±∞); case 2: u3 = c + id, u4 = c − id. A root at infinity (b = 0) is
        ``complex(inf)``; for a = b = 0 (f quadratic) u3 = u4 = ``complex(inf)``.
    u1, u2 : float
        cos θmin ≥ cos θmax [1].
    theta_min, theta_max : float
        Turning points [rad].
    k2, mc : float
        Parameter m = k² and 1 − k² [1], each from its own cancellation-free formula.
    beta : float
        β of §4 (errata 5, 6) [1/time].
    period : float
        Nutation period T = 2K/β (case 1) or 4K/β (case 2) [time]; for a steady precession the
        limit of small oscillations about it.
    kind : {"elliptic", "steady", "free"}
        "steady": u1 = u2 (constant θ; takes precedence), "free": a = b = 0 (harmonic u, §11),
        else "elliptic".
    mean_psidot, mean_phidot : float
        Secular precession and spin rates over one period, §5 "Mean rates" [rad/time].
    psi0, phi0 : float
        ψ(0), φ(0) [rad].

    Notes
    -----
    If G = R (G = −R) exactly, the term (G ∓ R)/(1 ∓ u) of (1.12) is absent. If moreover the
    motion reaches u = 1 (u = −1), the symmetry axis passes through ±e_z: the true ψ and φ then
    jump by π at each passage, while :meth:`psi` and :meth:`phi` return the continuous branch of
    (1.13) (the true attitude after n passages is Rz(ψ + nπ) Rx(θ) Rz(φ + nπ)). The same holds
    when 1 − u1 (1 + u2) is below 1e-280 (the axis passes within ~1e-140 rad of ±e_z), which is
    beyond the range of the Carlson functions: the term is then treated as absent.

    Accuracy: θ, ψ, φ to a few ulps of the phase for any 1 − k² ≥ SEPARATRIX_TOL. In case 2
    the pole terms lose digits like 1/sqrt(1 ∓ u) when θmin → 0 or θmax → π (measured 1e-13 at
    1 + u2 = 1.5e-5); case 1 anchors each pole term at the far turning point and does not.
    """

    mu: float
    a: float
    b: float
    R: float
    G: float
    E: float
    root_case: int
    roots: np.ndarray = field(repr=False)
    u1: float
    u2: float
    theta_min: float
    theta_max: float
    k2: float
    mc: float
    beta: float
    period: float
    kind: Kind
    mean_psidot: float
    mean_phidot: float
    psi0: float = field(repr=False)
    phi0: float = field(repr=False)
    _u0: float = field(repr=False)
    _K: float = field(repr=False)
    _tau0: float = field(repr=False)
    _turning_start: bool = field(repr=False)
    _main: _Chart = field(repr=False)
    _other: _Chart | None = field(repr=False)
    _poles: tuple[tuple[float, float, _Pole], ...] = field(repr=False)  # (wψ, wφ, pole)
    _p1: _Point = field(repr=False)
    _p2: _Point = field(repr=False)

    # ----------------------------------------------------------------------------------
    # Constructors
    # ----------------------------------------------------------------------------------

    @classmethod
    def from_state(
        cls,
        mu: float,
        a: float,
        b: float,
        R: float,
        G: float,
        theta: float,
        theta_dot: float,
        psi: float = 0.0,
        phi: float = 0.0,
    ) -> NutationOrbit:
        """The motion through (θ, θ', ψ, φ) at t = 0, (1.9)–(1.13) of spec/serov.md.

        Parameters
        ----------
        mu : float
            C/A [1], in (0, 2].
        a, b : float
            Moment coefficients of (1.5) [1/time²].
        R, G : float
            Reduced angular momenta μr and K·e_z/A [1/time].
        theta : float
            Nutation angle θ0 [rad], strictly inside (0, π).
        theta_dot : float
            θ0' [rad/time]; 0 starts at a turning point (side chosen by the sign of f'(u0), §3).
        psi, phi : float
            ψ0, φ0 [rad].

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            An input out of range, or a motion at a separatrix (1 − k² < SEPARATRIX_TOL,
            including a start at an unstable equilibrium), or a body at rest with a = b = 0.
        """
        return cls._from_state(mu, a, b, R, G, theta, theta_dot, psi, phi, "theta", True)

    @classmethod
    def _from_state(
        cls,
        mu: float,
        a: float,
        b: float,
        R: float,
        G: float,
        theta: float,
        theta_dot: float,
        psi: float,
        phi: float,
        theta_name: str,
        fast: bool,
    ) -> NutationOrbit:
        mu, a, b, R, G, psi, phi = _check_common(mu, a, b, R, G, psi, phi)
        th = float(theta)
        if not (math.isfinite(th) and 0.0 < th < math.pi):  # as _theta_array, for a scalar
            raise ParameterError(f"{theta_name} = {th:g} is outside the allowed range (0, π)")
        check_finite("theta_dot", float(theta_dot))
        u0 = math.cos(th)
        dp, dm = 2.0 * math.sin(0.5 * th) ** 2, 2.0 * math.cos(0.5 * th) ** 2
        s0sq = dp * dm
        e0 = G - R * u0
        td = float(theta_dot)
        h0 = 0.5 * td * td + e0 * e0 / (2.0 * s0sq)
        E = h0 + a * u0 + b * u0 * u0
        direction = 0 if td == 0.0 else (1 if td > 0.0 else -1)
        c0 = s0sq * td * td
        return _build(mu, a, b, R, G, E, psi, phi, u0, dp, dm, h0, c0, direction, None, None, fast)

    @classmethod
    def from_turning_point(
        cls,
        mu: float,
        a: float,
        b: float,
        R: float,
        G: float,
        theta_ext: float,
        psi: float = 0.0,
        phi: float = 0.0,
    ) -> NutationOrbit:
        """The motion with θ(0) = θext and θ'(0) = 0, (1.10) with γ0 ∈ {0, π/(2δ)}.

        θext is θmax if f'(u0) > 0 and θmin if f'(u0) < 0 (§3, last bullet).

        Parameters
        ----------
        mu : float
            C/A [1], in (0, 2].
        a, b : float
            Moment coefficients [1/time²].
        R, G : float
            Reduced angular momenta [1/time].
        theta_ext : float
            Turning point θ(0) [rad], strictly inside (0, π).
        psi, phi : float
            ψ0, φ0 [rad].

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            As :meth:`from_state`.
        """
        return cls._from_state(mu, a, b, R, G, theta_ext, 0.0, psi, phi, "theta_ext", True)

    @classmethod
    def from_energy(
        cls, mu: float, a: float, b: float, R: float, G: float, E: float, u_hint: float
    ) -> NutationOrbit:
        """The motion of energy E on the allowed interval [u2, u1] containing u_hint, (1.7).

        If no allowed interval contains u_hint, the one nearest to it (one well of a double
        well). t = 0 at the turning point u2 (θmax); ψ(0) = φ(0) = 0. An energy equal to a
        minimum of W (within round-off) gives the steady precession there.

        Parameters
        ----------
        mu : float
            C/A [1], in (0, 2].
        a, b : float
            Moment coefficients [1/time²].
        R, G : float
            Reduced angular momenta [1/time].
        E : float
            Energy (1.6) [1/time²].
        u_hint : float
            A value of cosθ [1] that selects the interval.

        Returns
        -------
        NutationOrbit

        Raises
        ------
        ParameterError
            No motion with this energy (E below the minimum of W beyond round-off), a
            separatrix, or an input out of range.
        """
        return cls._from_energy(mu, a, b, R, G, E, u_hint, True)

    @classmethod
    def _from_energy(
        cls, mu: float, a: float, b: float, R: float, G: float, E: float, u_hint: float, fast: bool
    ) -> NutationOrbit:
        mu, a, b, R, G, _, _ = _check_common(mu, a, b, R, G, 0.0, 0.0)
        check_finite("E", float(E))
        check_finite("u_hint", float(u_hint))
        E, u_hint = float(E), float(u_hint)
        # g of quartic_coefficients (1.7), as plain floats
        g = (2.0 * E - G * G, 2.0 * (G * R - a), -2.0 * b - R * R - 2.0 * E, 2.0 * a, 2.0 * b)
        quick = _fast_interval(g, R, G, u_hint) if fast else None
        # An uncertified interval (a well at round-off level, f(±1) ≈ 0, a separatrix, …) may
        # also be beyond what u2 as a root of f resolves: then the careful path throughout.
        fast = quick is not None
        intervals = [quick] if quick is not None else _allowed_intervals(g, R, G)
        if not intervals:
            raise ParameterError(
                f"E = {E:g} is below the minimum of the effective potential W(θ) (1.6) for "
                f"R = {R:g}, G = {G:g}, a = {a:g}, b = {b:g}: no motion has this energy"
            )

        def distance(iv: tuple[float, float]) -> float:
            return max(iv[0] - u_hint, u_hint - iv[1], 0.0)

        lo, hi = min(intervals, key=distance)
        if lo == hi:  # a minimum of W at round-off level: steady precession there
            u0 = lo
            dp, dm = 1.0 - u0, 1.0 + u0
            h0 = E - a * u0 - b * u0 * u0
            return _build(mu, a, b, R, G, E, 0.0, 0.0, u0, dp, dm, h0, 0.0, 0, "steady", None, fast)
        u0 = lo
        dp, dm = 1.0 - u0, 1.0 + u0
        if 0.0 < dm < _POLE_REFINE:  # θmax near π: 1 + u2 again about u = −1 (f(−1) exact)
            h0 = E - a * u0 - b * u0 * u0
            e = _pole_coefficients(-1, h0, u0, dp, dm, R, G, a, b)
            refined = _refine_pole_distance(e, dm)
            slope = abs(_dhorner(g, u0))
            if slope > 0.0 and _noise(e, refined) < 4.0 * _EPS * slope + _noise(g, u0):
                dm = refined
                u0, dp = dm - 1.0, 2.0 - dm
        h0 = E - a * u0 - b * u0 * u0
        return _build(mu, a, b, R, G, E, 0.0, 0.0, u0, dp, dm, h0, 0.0, 0, "lower", hi - u0, fast)

    # ----------------------------------------------------------------------------------
    # Evaluation
    # ----------------------------------------------------------------------------------

    def _t(self, t: ArrayLike) -> FloatArray:
        tt = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(tt)):
            raise ParameterError("t must be finite")
        return tt

    def _jac(self, tt: FloatArray) -> _Jac:
        v = self.beta * tt + self._tau0
        m = self.k2
        sn, cn, dn, j = _jacobi(np.asarray(v, dtype=float), m, self.mc, self._K)
        return _Jac(sn, cn, dn, j)

    def _shifted(self, jac: _Jac) -> _Jac:
        """Jacobi functions at v + K from those at v (sn → cd, cn → −k' sd, dn → k' nd)."""
        kc = math.sqrt(self.mc)
        low = jac.sn <= 0.0  # v_r ∈ [−K, 0]: v_r + K ∈ [0, K], same j
        sn = np.where(low, 1.0, -1.0) * jac.cn / jac.dn
        cn = kc * np.abs(jac.sn) / jac.dn
        dn = kc / jac.dn
        j = np.where(low, jac.j, jac.j + 1.0)
        return _Jac(sn, cn, dn, j)

    def _sigma(self, jac: _Jac) -> tuple[FloatArray, FloatArray]:
        """(σ, 1 − σ) of the chart: sin²γ (case 1) or sin²(γ/2) (case 2), no cancellation."""
        if self.root_case == 1:
            return jac.sn * jac.sn, jac.cn * jac.cn
        half_s = jac.sn * jac.sn / (2.0 * (1.0 + jac.cn))  # sin²(γr/2)
        half_c = 0.5 * (1.0 + jac.cn)  # cos²(γr/2)
        odd = np.mod(jac.j, 2.0) == 1.0
        return np.where(odd, half_c, half_s), np.where(odd, half_s, half_c)

    def _mix(self, sig: FloatArray, sigc: FloatArray, xa: float, xb: float) -> FloatArray:
        ch = self._main
        return np.asarray((xa * sigc + xb * ch.nu * sig) / (sigc + ch.nu * sig), dtype=float)

    def cos_theta(self, t: ArrayLike) -> FloatArray:
        """u(t) = cos θ(t), (1.9)–(1.10) of spec/serov.md.

        Parameters
        ----------
        t : array_like
            Times [time], any real values (t = 0 is the construction state).

        Returns
        -------
        ndarray
            cos θ [1], shape of ``t``.
        """
        tt = self._t(t)
        if self.kind == "steady":
            return np.full_like(tt, self._u0)
        sig, sigc = self._sigma(self._jac(tt))
        ch = self._main
        d = self._mix(sig, sigc, ch.A.d, ch.B.d)
        return np.asarray(self._u0 + d, dtype=float)

    def _theta_from(
        self, sig: FloatArray, sigc: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """θ, 1 − u and 1 + u, the latter two as weighted means (no cancellation near ±1)."""
        ch = self._main
        om = self._mix(sig, sigc, ch.A.om, ch.B.om)
        op = self._mix(sig, sigc, ch.A.op, ch.B.op)
        return np.asarray(2.0 * np.arctan2(np.sqrt(om), np.sqrt(op)), dtype=float), om, op

    def theta(self, t: ArrayLike) -> FloatArray:
        """Nutation angle θ(t), (1.9) of spec/serov.md, accurate also near θ = 0 and π.

        Parameters
        ----------
        t : array_like
            Times [time].

        Returns
        -------
        ndarray
            θ [rad] in [0, π], shape of ``t``.
        """
        tt = self._t(t)
        if self.kind == "steady":
            return np.full_like(tt, self.theta_min)
        sig, sigc = self._sigma(self._jac(tt))
        return self._theta_from(sig, sigc)[0]

    def _theta_dot_from(
        self, jac: _Jac, sig: FloatArray, sigc: FloatArray, om: FloatArray, op: FloatArray
    ) -> FloatArray:
        """θ' = −u'/sinθ with u' from d σ/dt of the chart (no f(u) near the turning points)."""
        ch = self._main
        den = sigc + ch.nu * sig
        if self.root_case == 1:
            dsig = 2.0 * self.beta * jac.sn * jac.cn * jac.dn  # d(sn²)/dt, reduced signs cancel
        else:
            sign = 1.0 - 2.0 * np.mod(jac.j, 2.0)
            dsig = 0.5 * self.beta * sign * jac.sn * jac.dn  # d sin²(γ/2)/dt = β sn dn/2
        udot = (ch.B.d - ch.A.d) * ch.nu * dsig / (den * den)
        sin_th = np.sqrt(om * op)
        safe = np.where(sin_th > 0.0, sin_th, 1.0)
        # Exactly at θ = 0 (θ = π), only possible for G = R (G = −R): the limit
        # θ'² = 2(E ∓ a − b) of f/(1 − u²), with the sign of the motion leaving the pole.
        up = math.sqrt(max(2.0 * (self.E - self.a - self.b), 0.0))
        down = -math.sqrt(max(2.0 * (self.E + self.a - self.b), 0.0))
        limit = np.where(om == 0.0, up, down)
        return np.asarray(np.where(sin_th > 0.0, -udot / safe, limit), dtype=float)

    def theta_dot(self, t: ArrayLike) -> FloatArray:
        """Nutation rate θ'(t) = −u'/sinθ, from (1.9)–(1.10) of spec/serov.md.

        Parameters
        ----------
        t : array_like
            Times [time].

        Returns
        -------
        ndarray
            θ' [rad/time], shape of ``t``.
        """
        tt = self._t(t)
        if self.kind == "steady":
            return np.zeros_like(tt)
        jac = self._jac(tt)
        sig, sigc = self._sigma(jac)
        _, om, op = self._theta_from(sig, sigc)
        return self._theta_dot_from(jac, sig, sigc, om, op)

    @functools.cached_property
    def _pole_starts(self) -> tuple[tuple[float, float], ...]:
        """(S0, Λ0) of each pole of :attr:`_poles`: the phase data of t = 0, on first use."""
        if not self._poles or self.kind == "steady":
            return tuple((0.0, 0.0) for _ in self._poles)
        jac0 = self._jac(np.zeros(()))
        return tuple(_pole_start(self, pole, jac0) for _, _, pole in self._poles)

    def _pole_integral(
        self,
        pole: _Pole,
        start: tuple[float, float],
        tt: FloatArray,
        jac: _Jac,
        jac_k: _Jac | None,
    ) -> FloatArray:
        """∫0^t dt'/(u − ρ) for one pole, (1.13) in the anchor-based form of the module notes."""
        if self.kind == "steady":
            return np.asarray(pole.sec * tt, dtype=float)
        S0, L0 = start
        jj = jac if pole.chart.offset == 0.0 or jac_k is None else jac_k
        S = _s_integral(jj.sn, jj.cn, jj.dn, jj.j, pole.p, pole.Sc)
        per = pole.kS * (S - S0)
        if self.root_case == 2:
            sign = 1.0 - 2.0 * np.mod(jj.j, 2.0)
            per = per - (_lam_integral(sign * jj.sn, jj.dn, pole.lam) - L0)
        return np.asarray(pole.sec * tt + pole.cper / self.beta * per, dtype=float)

    def _angles(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        tt = self._t(t)
        psi = np.zeros_like(tt)
        phi = np.zeros_like(tt)
        if self._poles:
            jac = None if self.kind == "steady" else self._jac(tt)
            jac_k = None if jac is None or self._other is None else self._shifted(jac)
            for (w_psi, w_phi, pole), start in zip(self._poles, self._pole_starts, strict=True):
                if jac is None:
                    integral = np.asarray(pole.sec * tt, dtype=float)
                else:
                    integral = self._pole_integral(pole, start, tt, jac, jac_k)
                psi = psi + w_psi * integral
                phi = phi + w_phi * integral
        phi = phi + self.R * (1.0 / self.mu - 1.0) * tt
        return np.asarray(self.psi0 + psi, dtype=float), np.asarray(self.phi0 + phi, dtype=float)

    def psi(self, t: ArrayLike) -> FloatArray:
        """Precession angle ψ(t), (1.11)–(1.13) of spec/serov.md; continuous, ψ(0) = ψ0.

        Parameters
        ----------
        t : array_like
            Times [time].

        Returns
        -------
        ndarray
            ψ [rad] (unwrapped), shape of ``t``.
        """
        return self._angles(t)[0]

    def phi(self, t: ArrayLike) -> FloatArray:
        """Proper rotation φ(t), (1.11)–(1.13) of spec/serov.md; continuous, φ(0) = φ0.

        Parameters
        ----------
        t : array_like
            Times [time].

        Returns
        -------
        ndarray
            φ [rad] (unwrapped), shape of ``t``.
        """
        return self._angles(t)[1]

    def turning_time(self, which: Literal["last", "next"] = "last") -> float:
        """Time of the nearest turning point of θ before (≤ 0) or after (> 0) t = 0, (1.10).

        Turning points are at βt + τ0 ∈ (T β/2)·ℤ. For a steady precession every instant is a
        turning point: "last" gives 0 and "next" T/2.

        Parameters
        ----------
        which : {"last", "next"}
            "last": largest turning time ≤ 0 (0.0 if t = 0 is one); "next": smallest > 0.

        Returns
        -------
        float
            [time].
        """
        if which not in ("last", "next"):
            raise ParameterError(f"which = {which!r} is not one of 'last', 'next'")
        half = 0.5 * self.period
        if self._turning_start or self.kind == "steady":
            return 0.0 if which == "last" else half
        h = self._K if self.root_case == 1 else 2.0 * self._K  # Jacobi argument per half swing
        j = math.floor(self._tau0 / h)
        t_last = (j * h - self._tau0) / self.beta
        if which == "last":
            return min(t_last, 0.0)
        t_next = ((j + 1) * h - self._tau0) / self.beta
        return t_next if t_next > 0.0 else t_next + half

    # ----------------------------------------------------------------------------------
    # Averages (§8)
    # ----------------------------------------------------------------------------------

    def _x_moments(self, ch: _Chart) -> tuple[float, float | None, float]:
        """(⟨X⟩, ⟨X²⟩, distance) for X = σ/((1 − σ) + νσ) in chart ``ch``, §8.

        Case 1: ⟨X⟩ = R_J(0, k'², 1, ν)/(3K), ⟨X²⟩ = −∂⟨X⟩/∂ν; ⟨X²⟩ is None when ν lies within
        _X2_CLOSED_DIST of the removable singularities ν = k'² (n = m) and ν = 1 (n = 0). Case 2:
        from I1, I2 of §8 with p = (ξ + 1)²/(4ξ) = 1 + ŵ; the ∂R_J term carries (ξ² − 1)² =
        4ξ(ξ + 1)²(p − 1), which cancels its 0/0 at p = 1, and p ≥ 1 > k'² away from n = m.
        """
        K, mc, nu = self._K, self.mc, ch.nu
        if self.root_case == 1:
            x1 = _rj_complete(mc, nu) / (3.0 * K)
            dist = min(abs(nu - mc), abs(nu - 1.0)) / max(1.0, nu)
            if dist < _X2_CLOSED_DIST:
                return x1, None, dist
            return x1, -_drj_dp(mc, nu) / (3.0 * K), dist
        xi = nu
        p = (xi + 1.0) ** 2 / (4.0 * xi)
        rj = _rj_complete(mc, p)
        x1 = (1.0 + (xi * xi - 1.0) / (4.0 * xi) * rj / (3.0 * K)) / (2.0 * xi)
        x2 = 1.0 / (2.0 * xi * xi) - rj / (12.0 * K * xi**3)
        if p > 1.0:  # p = 1 in floating point: the term is O(ε_machine), and ∂R_J is 0/0
            x2 -= (xi * xi - 1.0) ** 2 * _drj_dp(mc, p) / (96.0 * K * xi**4)
        return x1, x2, math.inf

    def _periodic_mean(
        self, func: Callable[[FloatArray, FloatArray], FloatArray], scale: float
    ) -> float:
        """Trapezoid in the Jacobi argument over one period of σ (uniform in time), doubling."""
        period_v = (2.0 if self.root_case == 1 else 4.0) * self._K
        n = 16
        v = period_v * np.arange(n) / n
        total = float(np.sum(func(*self._sigma(_Jac(*_jacobi(v, self.k2, self.mc, self._K))))))
        est = total / n
        while n < (1 << 20):
            v = period_v * (np.arange(n) + 0.5) / n
            total += float(np.sum(func(*self._sigma(_Jac(*_jacobi(v, self.k2, self.mc, self._K))))))
            n *= 2
            new = total / n
            if abs(new - est) <= _QUAD_RTOL * max(abs(new), scale) and n >= 64:
                return new
            est = new
        raise IntegrationError(
            f"period average did not converge (k² = {self.k2:.6g}, 1 − k² = {self.mc:.3g})"
        )

    def _u_moments(self, n: int) -> list[float]:
        """⟨u^j⟩, j = 0..n: closed forms (j ≤ 2), recurrence of §8, trapezoid fallback."""
        if self.kind == "steady":
            return [self._u0**j for j in range(n + 1)]
        scale = max(abs(self.u1), abs(self.u2))
        main = self._main
        x1_main = self._x_moments(main)[0]
        m1 = self._u0 + main.A.d + (main.B.d - main.A.d) * main.nu * x1_main
        moments = [1.0, m1]
        errs = [0.0, 8.0 * _EPS * max(scale, abs(m1))]
        if n <= 1:
            return moments[: n + 1]
        g = tuple(float(x) for x in quartic_coefficients(self.R, self.G, self.a, self.b, self.E))
        # Case 1: the chart (seed's or alternative anchoring) whose ν is farther from the
        # removable singularities of ∂R_J; case 2 has one chart and no such problem.
        charts = [main] if self._other is None else [main, self._other]
        best = max(((ch, *self._x_moments(ch)) for ch in charts), key=lambda item: item[3])
        m2: float | None = None
        if best[2] is not None:
            ch, x1, x2 = best[0], best[1], best[2]
            ua, dab = ch.A.u, ch.B.d - ch.A.d
            m2 = ua * ua + 2.0 * ua * dab * ch.nu * x1 + dab * dab * ch.nu * ch.nu * x2
        elif g[4] == 0.0 and g[3] != 0.0:
            # Cubic (b = 0): ⟨f'(u)⟩ = 0 gives ⟨u²⟩ = −(g1 + 2 g2 ⟨u⟩)/(3 g3) (§8, k = 0).
            cand = -(g[1] + 2.0 * g[2] * m1) / (3.0 * g[3])
            bound = 8.0 * _EPS * (abs(g[1]) + 2.0 * abs(g[2] * m1)) / abs(3.0 * g[3])
            bound += abs(2.0 * g[2] / (3.0 * g[3])) * errs[1]
            if bound <= _MOMENT_RTOL * max(scale * scale, 1e-300):
                m2 = cand
        if m2 is None:
            m2 = self._power_quadrature(2, scale)
        moments.append(m2)
        errs.append(32.0 * _EPS * max(scale * scale, abs(m2)))
        for j in range(3, n + 1):
            if g[4] != 0.0:
                k = j - 3  # k⟨u^{k−1} f⟩ + ½⟨u^k f'⟩ = 0 solved for ⟨u^{k+3}⟩
                coef = [g[0] * k, g[1] * (k + 0.5), g[2] * (k + 1.0), g[3] * (k + 1.5)]
                lead = g[4] * (k + 2.0)
            else:
                k = j - 2  # cubic: solved for ⟨u^{k+2}⟩
                coef = [g[0] * k, g[1] * (k + 0.5), g[2] * (k + 1.0)]
                lead = g[3] * (k + 1.5)
            idx = range(k - 1, k - 1 + len(coef))
            terms = [cf * moments[i] for cf, i in zip(coef, idx, strict=True) if i >= 0]
            bound = sum(abs(cf) * errs[i] for cf, i in zip(coef, idx, strict=True) if i >= 0)
            if lead != 0.0:
                val = -sum(terms) / lead
                err = (bound + 8.0 * _EPS * sum(abs(x) for x in terms)) / abs(lead)
            if lead == 0.0 or not (
                math.isfinite(val) and err <= _MOMENT_RTOL * max(scale**j, 1e-300)
            ):
                # Ill-conditioned (outer roots far from [u2, u1], small |b|): trapezoid in time.
                moments.extend(self._power_quadrature(i, scale) for i in range(j, n + 1))
                break
            moments.append(val)
            errs.append(err + 4.0 * _EPS * abs(val))
        return moments

    def _power_quadrature(self, j: int, scale: float) -> float:
        ch = self._main
        ua, ub, nu = ch.A.u, ch.B.u, ch.nu

        def uj(sig: FloatArray, sigc: FloatArray) -> FloatArray:
            u = (ua * sigc + ub * nu * sig) / (sigc + nu * sig)
            return np.asarray(u**j, dtype=float)

        return self._periodic_mean(uj, scale**j)

    def mean_u_power(self, n: int) -> float:
        """Period average ⟨u^n⟩ = ⟨cos^n θ⟩, (2.5) and §8 of spec/serov.md.

        ⟨u⟩ and ⟨u²⟩ in closed form by R_F, R_D, R_J (K, E, Π); higher powers by the recurrence
        k⟨u^{k−1} f⟩ + ½⟨u^k f'⟩ = 0 of §8 while its propagated error bound stays below 1e-13
        of max|u|^n. Near the removable singularities of I2 (case 1 with ν within 2% of 1 − k²
        or 1, e.g. b → 0) and when the recurrence is ill-conditioned (small |b|, outer roots
        far from [u2, u1]) the average is the periodic trapezoid rule in time, converged to
        round-off.

        Parameters
        ----------
        n : int
            Power, n ≥ 0.

        Returns
        -------
        float
            ⟨u^n⟩ [1].
        """
        if not isinstance(n, int | np.integer) or n < 0:
            raise ParameterError(f"n = {n!r} is outside the allowed range: integers ≥ 0")
        return float(self._u_moments(int(n))[int(n)])

    def _pole(self, rho: float) -> _Pole:
        return _make_pole(self, rho)

    def mean_pole(self, rho: float) -> float:
        """Period average ⟨1/(u − ρ)⟩ for a real pole outside [u2, u1], §8 of spec/serov.md.

        Closed form 1/(A_* − ρ) + ν(A_* − B_*)/(A_* − ρ)² ⟨σ/(1 + (r − 1)σ)⟩ (module notes),
        the same reduction as W_ρ, C_ρ of §8 anchored at a turning point.

        Parameters
        ----------
        rho : float
            Pole [1], outside [u2, u1] (ρ = u1 or u2 diverges).

        Returns
        -------
        float
            ⟨1/(u − ρ)⟩ [1].
        """
        check_finite("rho", rho)
        if self.u2 <= rho <= self.u1:
            raise ParameterError(
                f"rho = {rho:g} is inside the motion interval [u2, u1] = "
                f"[{self.u2:g}, {self.u1:g}]; allowed: rho < u2 or rho > u1"
            )
        value = self._pole(float(rho)).mean(self._K)
        if not math.isfinite(value):
            raise ParameterError(
                f"rho = {rho:g} is too close to the motion interval [{self.u2:g}, {self.u1:g}] "
                "for ⟨1/(u − ρ)⟩ in double precision"
            )
        return value

    def mean_inverse(self, sign: int) -> float:
        """Period average ⟨1/(1 + sign·u)⟩, sign = ±1, (2.5) and §8 of spec/serov.md.

        Parameters
        ----------
        sign : int
            +1 for ⟨1/(1 + u)⟩, −1 for ⟨1/(1 − u)⟩.

        Returns
        -------
        float
            [1]; infinite averages (the motion reaches u = ∓1) raise ParameterError.
        """
        if sign not in (1, -1):
            raise ParameterError(f"sign = {sign!r} is not one of +1, −1")
        if sign == 1:
            if self._p2.op <= _POLE_TOUCH:
                raise ParameterError(
                    f"⟨1/(1 + u)⟩ diverges: the motion reaches u = −1 (1 + u2 = {self._p2.op:g}, "
                    f"allowed > {_POLE_TOUCH:g})"
                )
            return self._pole(-1.0).mean(self._K)
        if self._p1.om <= _POLE_TOUCH:
            raise ParameterError(
                f"⟨1/(1 − u)⟩ diverges: the motion reaches u = 1 (1 − u1 = {self._p1.om:g}, "
                f"allowed > {_POLE_TOUCH:g})"
            )
        return -self._pole(1.0).mean(self._K)

    def nodes(self, n: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Quadrature nodes over one nutation period, the fallback average of §8.

        The periodic trapezoidal rule in time (uniform in the Jacobi argument βt + τ0, i.e.
        in F(γ)): t_i = iT/n, weights 1/n. It converges geometrically like
        exp(−πn K'/K) (case 1), faster than the rule in γ with weights 1/Δ of §8,
        exp(−2n arcsinh(k'/k)), and without its collapse near the separatrix.

        Parameters
        ----------
        n : int
            Number of nodes, ≥ 1.

        Returns
        -------
        t, theta, theta_dot, w : ndarray, shape (n,)
            Times [time], θ [rad], θ' [rad/time] (both halves of the swing) and weights [1]
            (≥ 0, sum 1).
        """
        if not isinstance(n, int | np.integer) or n < 1:
            raise ParameterError(f"n = {n!r} is outside the allowed range: integers ≥ 1")
        t = self.period * np.arange(int(n)) / int(n)
        th, thd = self._theta_pair(t)
        return t, th, thd, np.full(int(n), 1.0 / int(n))

    def _theta_pair(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        if self.kind == "steady":
            return np.full_like(t, self.theta_min), np.zeros_like(t)
        jac = self._jac(t)
        sig, sigc = self._sigma(jac)
        th, om, op = self._theta_from(sig, sigc)
        return th, self._theta_dot_from(jac, sig, sigc, om, op)

    def _g_values(
        self, g: Callable[[FloatArray, FloatArray], ArrayLike], t: FloatArray
    ) -> FloatArray:
        th, thd = self._theta_pair(t)
        vals = np.broadcast_to(np.asarray(g(th, thd), dtype=float), t.shape)
        if not np.all(np.isfinite(vals)):
            raise IntegrationError(
                f"g returned non-finite values on the orbit (k² = {self.k2:.6g}, "
                f"1 − k² = {self.mc:.3g})"
            )
        return vals

    def average(
        self,
        g: Callable[[FloatArray, FloatArray], ArrayLike],
        rtol: float = 1e-12,
        atol: float = 1e-14,
        n_max: int = 1 << 16,
    ) -> float:
        """Period average ⟨g(θ, θ')⟩ = (1/T)∫0^T g dt, (2.3) of spec/serov.md, adaptively.

        Periodic trapezoid rule of :meth:`nodes`, doubled (reusing nodes) from 32 nodes until
        two successive results agree within max(atol, rtol·|result|).

        Parameters
        ----------
        g : callable
            g(theta [rad], theta_dot [rad/time]) → values, vectorised over arrays.
        rtol, atol : float
            Relative and absolute tolerances [1] and [units of g].
        n_max : int
            Largest number of nodes.

        Returns
        -------
        float
            ⟨g⟩ [units of g].

        Raises
        ------
        IntegrationError
            No convergence with n_max nodes (for instance too near a separatrix), or g not finite.
        """
        check_range("rtol", rtol, low=0.0)
        check_range("atol", atol, low=0.0, low_open=False)
        check_range("n_max", n_max, low=2 * _N_START, low_open=False)
        T = self.period
        n = _N_START
        vals = self._g_values(g, T * np.arange(n) / n)
        total, total_abs = float(np.sum(vals)), float(np.sum(np.abs(vals)))
        est = total / n
        while 2 * n <= n_max:
            vals = self._g_values(g, T * (np.arange(n) + 0.5) / n)
            total += float(np.sum(vals))
            total_abs += float(np.sum(np.abs(vals)))
            n *= 2
            new = total / n
            # Round-off floor: g itself is evaluated to a few ulps of |g| only.
            floor = 64.0 * _EPS * total_abs / n
            if abs(new - est) <= max(atol, rtol * abs(new), floor):
                return new
            est = new
        raise IntegrationError(
            f"the period average did not converge with n_max = {n_max} nodes on the orbit with "
            f"k² = {self.k2:.6g}, 1 − k² = {self.mc:.3g} (g too sharply peaked, e.g. 1/(1 ∓ cos θ) "
            "for θ passing near 0 or π, or the orbit too near a separatrix)"
        )

    def time_integral(
        self,
        g: Callable[[FloatArray, FloatArray], ArrayLike],
        t0: float,
        t1: float,
        rtol: float = 1e-12,
    ) -> float:
        """∫_{t0}^{t1} g(θ(t), θ'(t)) dt along the orbit, §7 ("corrected" initial state).

        Whole periods contribute T⟨g⟩ (:meth:`average`); the rest is adaptive Gauss–Legendre in
        t (the integrand is analytic in t), panels of at most T/8 bisected until a 20- and a
        40-point rule agree.

        Parameters
        ----------
        g : callable
            g(theta [rad], theta_dot [rad/time]), vectorised.
        t0, t1 : float
            Limits [time].
        rtol : float
            Relative tolerance [1] (relative to ∫|g|).

        Returns
        -------
        float
            [units of g × time].
        """
        check_finite("t0", t0)
        check_finite("t1", t1)
        check_range("rtol", rtol, low=0.0)
        if t1 == t0:
            return 0.0
        if t1 < t0:
            return -self.time_integral(g, t1, t0, rtol)
        T = self.period
        n_per = math.floor((t1 - t0) / T)
        whole = 0.0
        if n_per > 0:
            size = float(np.mean(np.abs(self._g_values(g, T * np.arange(64) / 64))))
            whole = n_per * T * self.average(g, rtol=0.1 * rtol, atol=0.1 * rtol * size + 1e-300)
        lo = t0 + n_per * T
        return whole + self._gauss_legendre(g, lo, t1, rtol)

    def _gauss_legendre(
        self, g: Callable[[FloatArray, FloatArray], ArrayLike], lo: float, hi: float, rtol: float
    ) -> float:
        x20, w20 = np.polynomial.legendre.leggauss(20)
        x40, w40 = np.polynomial.legendre.leggauss(40)
        m = max(1, math.ceil((hi - lo) / (self.period / 8.0)))
        edges = np.linspace(lo, hi, m + 1)
        stack = [(float(edges[i]), float(edges[i + 1]), 0) for i in range(m)]
        total = 0.0
        while stack:
            a, b, depth = stack.pop()
            mid, half = 0.5 * (a + b), 0.5 * (b - a)
            f40 = self._g_values(g, mid + half * x40)
            fine = half * float(np.dot(w40, f40))
            coarse = half * float(np.dot(w20, self._g_values(g, mid + half * x20)))
            scale = half * float(np.dot(w40, np.abs(f40)))
            if abs(fine - coarse) <= rtol * scale:
                total += fine
            elif depth >= 40:
                raise IntegrationError(
                    f"time_integral did not converge on [{lo:g}, {hi:g}] (k² = {self.k2:.6g}, "
                    f"1 − k² = {self.mc:.3g})"
                )
            else:
                stack.append((a, mid, depth + 1))
                stack.append((mid, b, depth + 1))
        return total


# --------------------------------------------------------------------------------------
# Construction
# --------------------------------------------------------------------------------------


def _check_common(
    mu: float, a: float, b: float, R: float, G: float, psi: float, phi: float
) -> tuple[float, ...]:
    """Range checks; the values as plain floats (attributes never become numpy scalars)."""
    check_range("mu", float(mu), low=0.0, high=2.0, high_open=False)
    _finite(a=a, b=b, R=R, G=G, psi=psi, phi=phi)
    return tuple(float(x) for x in (mu, a, b, R, G, psi, phi))


def _allowed_intervals(g: tuple[float, ...], R: float, G: float) -> list[tuple[float, float]]:
    """Intervals of [−1, 1] where f ≥ 0 (one per well); (c, c) for a maximum of f at 0 ± noise."""
    crit = _critical_points(g, -1.0, 1.0)
    pts = [-1.0, *crit, 1.0]
    vals = [-((G + R) ** 2), *(_horner(g, x) for x in crit), -((G - R) ** 2)]  # f(±1) exact
    out: list[tuple[float, float]] = []
    start: float | None = None
    peak = (pts[0], vals[0])  # highest critical point of the current interval
    for i in range(len(pts) - 1):
        x0, x1, f0, f1 = pts[i], pts[i + 1], vals[i], vals[i + 1]
        if f0 <= 0.0 < f1:  # f rises through 0 on this monotone piece
            start = x0 if f0 == 0.0 else _root_between(g, x0, x1)
            peak = (x1, f1)
        elif f0 > 0.0 >= f1:  # f falls through 0
            end = x1 if f1 == 0.0 else _root_between(g, x0, x1)
            if 0 < i < len(pts) - 1 and peak[1] <= _noise(g, peak[0]):
                # The whole well is within round-off of f = 0: E is the minimum of W.
                out.append((peak[0], peak[0]))
            else:
                out.append((x0 if start is None else start, end))
            start = None
        elif f1 > peak[1]:
            peak = (x1, f1)
    # Maxima of f within round-off below zero (an energy at a minimum of W): steady precession.
    fpp = tuple(i * (i - 1) * g[i] for i in range(2, len(g)))
    for x, fx in zip(crit, vals[1:-1], strict=True):
        if fx <= 0.0 and -fx <= _noise(g, x) and _horner(fpp, x) < 0.0:
            if not any(lo <= x <= hi for lo, hi in out):
                out.append((x, x))
    return out


def _build(
    mu: float,
    a: float,
    b: float,
    R: float,
    G: float,
    E: float,
    psi0: float,
    phi0: float,
    u0: float,
    dp: float,
    dm: float,
    h0: float,
    c0: float,
    direction: int,
    side: Literal["lower", "steady"] | None,
    d1_guess: float | None = None,
    fast: bool = True,
) -> NutationOrbit:
    """The orbit about u0 (δ = u − u0), from f(u0 + δ) = Σ c_i δ^i with c0 exact.

    direction: sign of θ'(0) (0 at a turning point); side: "lower" forces u0 = u2, "steady"
    forces the steady precession at u0, None chooses the side by f'(u0) (§3). d1_guess: an
    estimate of u1 − u0 for the fast path; fast = False forces the careful path (tests).
    """
    s0sq = dp * dm
    e0 = G - R * u0
    h1 = a + 2.0 * b * u0
    c1 = -2.0 * s0sq * h1 - 4.0 * u0 * h0 + 2.0 * R * e0
    c2 = -2.0 * s0sq * b + 4.0 * u0 * h1 - 2.0 * h0 - R * R
    c3 = 4.0 * u0 * b + 2.0 * h1
    c4 = 2.0 * b
    c = (c0, c1, c2, c3, c4)
    end_up, end_dn = -((G - R) ** 2), -((G + R) ** 2)  # f(1), f(−1): exact (§3)
    free = a == 0.0 and b == 0.0

    turning = c0 == 0.0
    # f'(u0) at round-off level with f'' < 0 at a turning start: a steady precession given in
    # floating point (u0 is a double root of f to working accuracy).
    c1_noise = 16.0 * _EPS * (abs(2.0 * s0sq * h1) + abs(4.0 * u0 * h0) + abs(2.0 * R * e0))
    if turning and side is None and abs(c1) <= c1_noise and c2 < 0.0:
        side = "steady"
    quick = None
    if fast and side != "steady":
        quick = _fast_turning_points(c, dp, dm, end_up, end_dn, side, c1_noise, d1_guess)
    if side == "steady":
        d1 = d2 = 0.0
    elif quick is not None:
        d1, d2 = quick
    else:
        d1, d2 = _careful_turning_points(c, dp, dm, end_up, end_dn, turning, side, u0)

    # 1 − u1 and 1 + u2: the difference dp − δ1 loses digits when θmin is near 0 (θmax near
    # π); then they come again from the expansion about ±1, where f(±1) is exact. Each route's
    # error bound is (round-off of its polynomial)/|f'(u1)|; the smaller wins. δ1, δ2 keep their
    # own digits (they fix the phase τ0 of a start next to a turning point).
    om1 = _pole_distance(c, d1, dp, _pole_coefficients(1, h0, u0, dp, dm, R, G, a, b))
    op2 = _pole_distance(_reflect(c), -d2, dm, _pole_coefficients(-1, h0, u0, dp, dm, R, G, a, b))
    p1 = _Point(u=u0 + d1 if om1 == dp - d1 else 1.0 - om1, om=om1, op=dm + d1, d=d1)
    p2 = _Point(u=u0 + d2 if op2 == dm + d2 else op2 - 1.0, om=dp - d2, op=op2, d=d2)
    steady = d1 == d2

    # Deflation: f(u0 + δ) = (δ − d1)(δ − d2)(c4 δ² + q1 δ + q0).
    s, pr = d1 + d2, d1 * d2
    q1 = c3 + c4 * s
    q0 = c2 + s * q1 - c4 * pr

    roots = np.empty(4, dtype=complex)
    roots[0], roots[1] = p1.u, p2.u
    if free:
        root_case = 1
        kind: Kind = "steady" if steady else "free"
        beta2 = -q0 / 4.0  # q ≡ c2 = −(2E + R²): u'' = −(2E + R²)u + GR (§11)
        m, mc = 0.0, 1.0
        roots[2] = roots[3] = complex(math.inf)
        nu_max = nu_min = 1.0
        xi = 1.0
    else:
        kind = "steady" if steady else "elliptic"
        disc = q1 * q1 - 4.0 * c4 * q0
        disc_noise = 64.0 * _EPS * (q1 * q1 + abs(4.0 * c4 * q0))
        if disc < -disc_noise:
            if c4 >= 0.0:
                raise ParameterError(
                    f"b = {b:g}: complex outer roots need b < 0; the state is numerically "
                    "degenerate (at a separatrix?)"
                )
            root_case = 2
            cc = -q1 / (2.0 * c4)
            dd = math.sqrt(-disc) / (2.0 * abs(c4))
            roots[2], roots[3] = complex(u0 + cc, dd), complex(u0 + cc, -dd)
            m, mc, beta2, xi = _case2_modulus(d1, d2, cc, dd, c4)
            nu_max = nu_min = xi
        else:
            root_case = 1
            sq = math.sqrt(max(disc, 0.0))
            qq = -0.5 * (q1 + math.copysign(sq, q1))
            if qq == 0.0:
                raise ParameterError(
                    "the motion is at a separatrix: f has a double root at the initial cos θ "
                    "(1 − k² = 0, allowed > SEPARATRIX_TOL)"
                )
            r_small = q0 / qq
            r_big = qq / c4 if c4 != 0.0 else math.inf  # b = 0: the root at infinity
            u4, u3, big4, big3 = _label(r_small, r_big, d1, d2)
            roots[2] = complex(u0 + u3) if math.isfinite(u3) else complex(math.inf)
            roots[3] = complex(u0 + u4) if math.isfinite(u4) else complex(math.inf)
            m, mc, beta2 = _case1_modulus(d1, d2, u3, u4, big3, big4, qq, c4)
            nu_max = _nu(d2, d1, u3, big3, qq, c4)  # seed's anchoring: A = u2, P = u3
            nu_min = _nu(d1, d2, u4, big4, qq, c4)  # alternative: A = u1, P = u4
            xi = 1.0
    if not (math.isfinite(mc) and math.isfinite(m)) or m < -1e-12 or mc < -1e-12:
        raise ParameterError(
            f"the motion is at a separatrix: the roots of f(u) are numerically degenerate "
            f"(k² = {m:.3g}, allowed [0, 1 − SEPARATRIX_TOL])"
        )
    # Clamp to [0, 1]: a product form can round to 1 + 2e-16 near k = 0 (case 2), which
    # would make the removable singularities of §8 exact zero divisions.
    m, mc = min(max(m, 0.0), 1.0), min(max(mc, 0.0), 1.0)
    if mc < SEPARATRIX_TOL:
        raise ParameterError(
            f"the motion is at a separatrix: 1 − k² = {mc:.3g} is below SEPARATRIX_TOL = "
            f"{SEPARATRIX_TOL:g} (the nutation period is infinite)"
        )
    if not (beta2 > 0.0 and math.isfinite(beta2)):
        if free:
            raise ParameterError(
                "a = b = 0 with R = G = E = 0 is a body at rest: no nutation period "
                "(2E + R² must be > 0)"
            )
        raise ParameterError(
            f"β² = {beta2:.3g} is not positive: the roots of f(u) are numerically degenerate "
            "(the motion is at a separatrix)"
        )
    beta = math.sqrt(beta2)
    K = float(special.elliprf(0.0, mc, 1.0))
    period = (2.0 if root_case == 1 else 4.0) * K / beta

    if root_case == 1:
        main = _Chart(A=p2, B=p1, nu=nu_max, offset=0.0)
        other: _Chart | None = _Chart(A=p1, B=p2, nu=nu_min, offset=K)
        # σ0 = sin²γ0 of (1.10) in the seed's anchoring (σ = −1: γ = 0 is θmax)
        den = -d2 + nu_max * d1
        sig0 = -d2 / den if den > 0.0 else 0.0
        sigc0 = nu_max * d1 / den if den > 0.0 else 1.0
        sgn = -1.0 if direction > 0 else 1.0
        tau0 = _ellipf_scalar(sgn * math.sqrt(sig0), math.sqrt(sigc0), mc)
    else:
        main = _Chart(A=p1, B=p2, nu=xi, offset=0.0)
        other = None
        # s0 = sin²(γ0/2) of §4.2 (σ = +1: γ = 0 is θmin, errata 4)
        den = d1 - xi * d2
        s0 = d1 / den if den > 0.0 else 0.0
        sc0 = -xi * d2 / den if den > 0.0 else 1.0
        sgn = 1.0 if direction >= 0 else -1.0
        sin_g0 = 2.0 * math.sqrt(s0 * sc0)
        cos_g0 = sc0 - s0
        if cos_g0 >= 0.0:
            tau0 = sgn * _ellipf_scalar(sin_g0, cos_g0, mc)
        else:
            tau0 = sgn * (2.0 * K - _ellipf_scalar(sin_g0, -cos_g0, mc))

    theta_min = 2.0 * math.atan2(math.sqrt(p1.om), math.sqrt(p1.op))
    theta_max = 2.0 * math.atan2(math.sqrt(p2.om), math.sqrt(p2.op))

    orbit = NutationOrbit(
        mu=float(mu),
        a=float(a),
        b=float(b),
        R=float(R),
        G=float(G),
        E=float(E),
        root_case=root_case,
        roots=roots,
        u1=p1.u,
        u2=p2.u,
        theta_min=theta_min,
        theta_max=theta_max,
        k2=m,
        mc=mc,
        beta=beta,
        period=period,
        kind=kind,
        mean_psidot=0.0,
        mean_phidot=0.0,
        psi0=float(psi0),
        phi0=float(phi0),
        _u0=float(u0),
        _K=K,
        _tau0=tau0,
        _turning_start=turning,
        _main=main,
        _other=other,
        _poles=(),
        _p1=p1,
        _p2=p2,
    )
    # ψ' = ½[(G+R)/(1+u) + (G−R)/(1−u)], φ' = ½[(G+R)/(1+u) − (G−R)/(1−u)] + R(1/μ − 1),
    # (1.12); with 1/(1 − u) = −1/(u − 1). A term with G ∓ R = 0 is absent (§11).
    # A turning point within _POLE_TOUCH of ±1 (θ within ~1e-140 rad of 0 or π, G ∓ R ~ 1e-140)
    # is beyond the range of R_J: that term is treated as absent too (continuous branch).
    poles: list[tuple[float, float, _Pole]] = []
    if G + R != 0.0 and p2.op > _POLE_TOUCH:
        poles.append((0.5 * (G + R), 0.5 * (G + R), _make_pole(orbit, -1.0)))
    if G - R != 0.0 and p1.om > _POLE_TOUCH:
        poles.append((-0.5 * (G - R), 0.5 * (G - R), _make_pole(orbit, 1.0)))
    means = [pole.mean(K) for _, _, pole in poles]
    rate_psi = sum(wp * mk for (wp, _, _), mk in zip(poles, means, strict=True))
    rate_phi = sum(wf * mk for (_, wf, _), mk in zip(poles, means, strict=True))
    rate_phi += R * (1.0 / mu - 1.0)
    roots.flags.writeable = False  # a frozen orbit
    object.__setattr__(orbit, "_poles", tuple(poles))
    object.__setattr__(orbit, "mean_psidot", float(rate_psi))
    object.__setattr__(orbit, "mean_phidot", float(rate_phi))
    return orbit


def _careful_turning_points(
    c: tuple[float, ...],
    dp: float,
    dm: float,
    end_up: float,
    end_dn: float,
    turning: bool,
    side: Literal["lower"] | None,
    u0: float,
) -> tuple[float, float]:
    """(δ1, δ2) of :func:`_build` on the monotone pieces of c between its critical points."""
    c1, c2 = c[1], c[2]
    crit = _critical_points(c, -dm, dp)
    crit_up, crit_dn = crit, [-x for x in reversed(crit)]  # the latter: of c(−x)
    if not turning:
        d1 = _first_root(c, c[0], dp, end_up, crit_up)
        d2 = -_first_root(_reflect(c), c[0], dm, end_dn, crit_dn)
        return d1, d2
    if side == "lower":
        up = True
    elif c1 != 0.0:
        up = c1 > 0.0  # f'(u0) > 0: u0 = u2, the motion is above (§3)
    elif c2 < 0.0:
        up = True  # double root with f'' < 0: steady precession (found as d1 = 0 below)
    else:
        raise ParameterError(
            f"theta = {math.degrees(math.acos(max(-1.0, min(1.0, u0)))):g}° with theta_dot = 0 "
            "is an unstable (or degenerate) equilibrium: the motion is at a separatrix or at "
            "rest (1 − k² = 0)"
        )
    if up:
        return (_first_root(c, 0.0, dp, end_up, crit_up) if c1 >= 0.0 else 0.0), 0.0
    return 0.0, (-_first_root(_reflect(c), 0.0, dm, end_dn, crit_dn) if c1 <= 0.0 else 0.0)


def _label(r_small: float, r_big: float, d1: float, d2: float) -> tuple[float, float, bool, bool]:
    """(u4, u3, u4 is the big root, u3 is the big root) by the cyclic rule of §3.

    Going upwards from u1 and wrapping through ±∞ the order is u1 → u4 → u3 → u2.
    """

    def key(x: float) -> tuple[int, float]:
        if not math.isfinite(x):
            return (1, 0.0)
        if x >= d1:
            return (0, x)
        if x <= d2:
            return (2, x)
        raise ParameterError(
            "the motion is at a separatrix: a root of f(u) lies inside the motion interval "
            "(1 − k² ≈ 0, allowed > SEPARATRIX_TOL)"
        )

    ks, kb = key(r_small), key(r_big)
    if ks <= kb:
        return r_small, r_big, False, True
    return r_big, r_small, True, False


def _case1_modulus(
    d1: float, d2: float, u3: float, u4: float, big3: bool, big4: bool, qq: float, c4: float
) -> tuple[float, float, float]:
    """k², 1 − k², β² of §4.1 (errata 5) with A = u2, B = u1, P = u3, Q = u4.

    k² = (B − A)(P − Q)/((B − P)(A − Q)), 1 − k² = (B − Q)(A − P)/((B − P)(A − Q)),
    β² = −(b/2)(B − P)(A − Q); the big root X enters through c4·X = qq (finite at b = 0).
    """
    A, B = d2, d1
    if big4:  # Q big
        DAQ = c4 * A - qq
        m = (B - A) * (c4 * u3 - qq) / ((B - u3) * DAQ)
        mc = (c4 * B - qq) * (A - u3) / ((B - u3) * DAQ)
        beta2 = -0.25 * (B - u3) * DAQ
    elif big3:  # P big
        DBP = c4 * B - qq
        m = (B - A) * (qq - c4 * u4) / (DBP * (A - u4))
        mc = (B - u4) * (c4 * A - qq) / (DBP * (A - u4))
        beta2 = -0.25 * DBP * (A - u4)
    else:  # pragma: no cover - one root is always carried as the big one
        raise AssertionError("no big root")
    return m, mc, beta2


def _nu(A: float, B: float, P: float, big: bool, qq: float, c4: float) -> float:
    """ν = (P − A)/(P − B) of the chart with anchor A and pole P (1 when P = ∞)."""
    if big:
        return (qq - c4 * A) / (qq - c4 * B)
    return (P - A) / (P - B)


def _case2_modulus(
    d1: float, d2: float, c: float, d: float, c4: float
) -> tuple[float, float, float, float]:
    """k², 1 − k², β² = −2bη and ξ of §4.2 (errata 6), without cancellation.

    With x_i = u_i − c, ρ_i = sqrt(x_i² + d²): e_i∓ = ρ_i ∓ x_i ≥ 0, each either a sum or
    d²/(the sum), and k² = (u1 − u2)²(e1− + e2−)(e1+ + e2+)/(4η(ρ1 + ρ2)²),
    1 − k² = (e1− + e2+)(e1+ + e2−)/(4η).
    """
    x1, x2 = d1 - c, d2 - c
    r1, r2 = math.hypot(x1, d), math.hypot(x2, d)

    def pair(r: float, x: float) -> tuple[float, float]:
        if x >= 0.0:
            return d * d / (r + x), r + x
        return r - x, d * d / (r - x)

    e1m, e1p = pair(r1, x1)
    e2m, e2p = pair(r2, x2)
    # Only bounded ratios are formed: for |b| → 0 with a = 0 the pair c ± id goes to infinity
    # like |b|^(−1/2) and η = ρ1ρ2 alone would overflow (β² = −c4 η stays finite).
    w = (d1 - d2) / (r1 + r2)
    m = 0.25 * w * w * ((e1m + e2m) / r1) * ((e1p + e2p) / r2)
    mc = 0.25 * ((e1m + e2p) / r1) * ((e1p + e2m) / r2)
    return m, mc, (-c4 * r1) * r2, r1 / r2


def _make_pole(orbit: NutationOrbit, rho: float) -> _Pole:
    """Coefficients of ∫dt/(u − ρ) (module notes; (1.13) with errata 7–9 in case 2)."""
    mc, m = orbit.mc, orbit.k2
    p1, p2 = orbit._p1, orbit._p2
    if orbit.root_case == 1:
        # Anchor at the turning point farther from ρ: no cancellation between the parts.
        above = rho > orbit.u1 or rho == 1.0
        ch = orbit._main if above else orbit._other
        assert ch is not None
        dA, dB = ch.A.minus(rho), ch.B.minus(rho)
        if dA == 0.0:
            raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
        r = ch.nu * dB / dA
        if not r > 0.0:
            raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
        Sc = _rj_complete(mc, r) / 3.0
        return _Pole(
            sec=1.0 / dA,
            cper=ch.nu * (ch.A.d - ch.B.d) / (dA * dA),
            kS=1.0,
            p=r,
            Sc=Sc,
            lam=0.0,
            chart=ch,
        )
    ch = orbit._main
    xi = ch.nu
    e1, e2 = p1.minus(rho), p2.minus(rho)
    if e1 == 0.0 or e2 == 0.0:
        raise ParameterError(f"rho = {rho:g} is a turning point: ⟨1/(u − ρ)⟩ diverges")
    r = xi * e2 / e1
    what = (r - 1.0) ** 2 / (4.0 * r)  # ŵ of §5 (case 2), ≥ 0
    p = (r + 1.0) ** 2 / (4.0 * r)  # 1 + ŵ
    Sc = _rj_complete(mc, p) / 3.0
    lam = math.sqrt(m + what)
    return _Pole(
        sec=(e1 + e2) / (2.0 * e1 * e2),
        cper=(p1.d - p2.d) / (2.0 * e1 * e2),
        kS=(r - 1.0) * (r + 1.0) / (4.0 * r),
        p=p,
        Sc=Sc,
        lam=lam,
        chart=ch,
    )


def _pole_start(orbit: NutationOrbit, pole: _Pole, jac0: _Jac) -> tuple[float, float]:
    """(S0, Λ0) of ``pole`` at t = 0, by the same path as at any t (ψ(0) = ψ0 exactly)."""
    if orbit.root_case == 1:
        j0 = jac0 if pole.chart.offset == 0.0 else orbit._shifted(jac0)
        return float(_s_integral(j0.sn, j0.cn, j0.dn, j0.j, pole.p, pole.Sc)), 0.0
    sign = 1.0 - 2.0 * float(np.mod(jac0.j, 2.0))
    S0 = float(_s_integral(jac0.sn, jac0.cn, jac0.dn, jac0.j, pole.p, pole.Sc))
    L0 = float(_lam_integral(np.asarray(sign * jac0.sn), jac0.dn, pole.lam))
    return S0, L0
