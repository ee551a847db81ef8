"""The roots of the quartic f(u) (1.7): the turning points u1, u2 of the motion, to full
relative accuracy also next to θ = 0 or π, and the two outer roots with the modulus of the
Jacobi functions.

Two routes find the turning points. The careful one brackets every root on a monotone piece
of f, between its critical points, and refines it by bisection. The fast one (below) iterates
from sign-change brackets and certifies its result by deflation; where a check fails it returns
None and the careful route decides.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Literal

import numpy as np
from scipy import optimize

from tumble.errors import ParameterError
from tumble.unperturbed.symmetric_body.charts import _EPS

_POLE_REFINE = 0.5  # refine a turning point about u = ±1 when it lies this close to ±1

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


def _newton_polish(
    x: float, f: Callable[[float], float], fprime: Callable[[float], float]
) -> float:
    """x after at most three Newton steps on f(x) = 0, the polishing of a critical point.

    The iteration stops early at a zero slope, or before a step that is not finite or longer
    than 1e-3 (1 + |x|) (a poor start, which polishing must not move far).

    Parameters
    ----------
    x : float
        Starting point [1] (a value of u = cos θ).
    f, fprime : callable
        The function and its derivative, of one float [units of f, and of f per unit of u].

    Returns
    -------
    float
        The polished point [1].
    """
    for _ in range(3):
        slope = fprime(x)
        if slope == 0.0:
            break
        step = f(x) / slope
        if not math.isfinite(step) or abs(step) > 1e-3 * (1.0 + abs(x)):
            break
        x -= step
    return x


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
        x = _newton_polish(
            float(z.real), functools.partial(_horner, dd), functools.partial(_dhorner, dd)
        )
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
    """Deflate two known roots of f (1.7): c = (δ − d1)(δ − d2)(c4 δ² + q1 δ + q0).

    Used for the outer roots of an orbit (:func:`~.build._outer_roots`) and to certify the
    turning points of the fast path (:func:`_certified`, :func:`_fast_interval`).

    Parameters
    ----------
    c : tuple of float
        Coefficients of f, ascending (c0 … c4), in δ = u − u0 or in u itself [1/time²].
    d1, d2 : float
        The two roots to divide out, in the same variable [1].

    Returns
    -------
    c4, q1, q0 : float
        The remaining quadratic c4 δ² + q1 δ + q0, its coefficients from the leading one
        down [1/time²].
    """
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

        def search(side: _Side, end: float, f_end: float, x0: float | None) -> float | None:
            poly, f0, _ = side
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

    def p_prime(x: float) -> float:
        return ((e4 * x + e3) * x + e2) * x + e1

    def p_second(x: float) -> float:
        return (3.0 * e4 * x + 2.0 * e3) * x + e2

    out = []
    for x in raw:
        if not lo - 4e-3 * (1.0 + abs(x)) < x < hi + 4e-3 * (1.0 + abs(x)):
            continue  # three polishing steps of ≤ 1e-3 (1 + |x|) cannot bring it inside
        x = _newton_polish(x, p_prime, p_second)
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
    """k², 1 − k², β² of §4.1 (corrections S5) with A = u2, B = u1, P = u3, Q = u4.

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
    """k², 1 − k², β² = −2bη and ξ of §4.2 (corrections S6), without cancellation.

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
