"""Building an orbit: from a state, a turning point or an energy to the turning points, the
outer roots, the modulus and phase of the Jacobi functions, and the pole terms of ψ and φ."""

from __future__ import annotations

import math
from typing import Literal, NamedTuple

import numpy as np
from scipy import special

from tumble._typing import FloatArray
from tumble.errors import ParameterError, check_finite, check_range
from tumble.kernels.codes import NUTATION_SEPARATRIX_TOL as SEPARATRIX_TOL
from tumble.unperturbed.symmetric_body.carlson import _ellipf_scalar
from tumble.unperturbed.symmetric_body.charts import (
    _EPS,
    _POLE_TOUCH,
    Kind,
    _Chart,
    _make_pole,
    _Point,
    _Pole,
)
from tumble.unperturbed.symmetric_body.orbit import NutationOrbit
from tumble.unperturbed.symmetric_body.potential import _finite
from tumble.unperturbed.symmetric_body.quartic import (
    _POLE_REFINE,
    _allowed_intervals,
    _careful_turning_points,
    _case1_modulus,
    _case2_modulus,
    _deflate,
    _dhorner,
    _fast_interval,
    _fast_turning_points,
    _label,
    _noise,
    _nu,
    _pole_coefficients,
    _pole_distance,
    _refine_pole_distance,
    _reflect,
)

__all__ = ["from_energy", "from_state"]


class _Motion(NamedTuple):
    """The constants of the motion (plain floats)."""

    mu: float
    a: float
    b: float
    R: float
    G: float
    E: float


class _Start(NamedTuple):
    """Where the orbit is expanded: u0 = cos θ0, 1 − u0, 1 + u0, the kinetic part h0 of E,
    f(u0) (exact), the sign of θ'(0), and how a turning start is read."""

    u0: float
    dp: float
    dm: float
    h0: float
    c0: float
    direction: int
    side: Literal["lower", "steady"] | None = None  # "lower": u0 = u2; "steady": u0 = u1 = u2
    d1_guess: float | None = None  # an estimate of u1 − u0 for the fast path


class _Outer(NamedTuple):
    """The outer roots u3, u4, the modulus, β² and the chart weights of §4."""

    root_case: int
    u3: complex
    u4: complex
    m: float
    mc: float
    beta2: float
    nu_max: float  # case 1: the paper's anchoring (A = u2, P = u3); case 2: ξ
    nu_min: float  # case 1: the alternative anchoring (A = u1, P = u4)


def _check_common(
    mu: float, a: float, b: float, R: float, G: float, psi: float, phi: float
) -> tuple[float, ...]:
    """Range checks; the values as plain floats (attributes never become numpy scalars)."""
    check_range("mu", float(mu), low=0.0, high=2.0, high_open=False)
    _finite(a=a, b=b, R=R, G=G, psi=psi, phi=phi)
    return tuple(float(x) for x in (mu, a, b, R, G, psi, phi))


def from_state(
    mu: float,
    a: float,
    b: float,
    R: float,
    G: float,
    theta: float,
    theta_dot: float,
    psi: float,
    phi: float,
    theta_name: str = "theta",
    fast: bool = True,
) -> NutationOrbit:
    """:meth:`NutationOrbit.from_state`; ``fast = False`` forces the careful path (tests)."""
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
    start = _Start(u0, dp, dm, h0, s0sq * td * td, direction)
    return _build(_Motion(mu, a, b, R, G, E), psi, phi, start, fast)


def from_energy(
    mu: float, a: float, b: float, R: float, G: float, E: float, u_hint: float, fast: bool = True
) -> NutationOrbit:
    """:meth:`NutationOrbit.from_energy`; ``fast = False`` forces the careful path (tests)."""
    mu, a, b, R, G, _, _ = _check_common(mu, a, b, R, G, 0.0, 0.0)
    check_finite("E", float(E))
    check_finite("u_hint", float(u_hint))
    E, u_hint = float(E), float(u_hint)
    motion = _Motion(mu, a, b, R, G, E)
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
    u0 = lo
    dp, dm = 1.0 - u0, 1.0 + u0
    if lo == hi:  # a minimum of W at round-off level: steady precession there
        h0 = E - a * u0 - b * u0 * u0
        return _build(motion, 0.0, 0.0, _Start(u0, dp, dm, h0, 0.0, 0, "steady"), fast)
    if 0.0 < dm < _POLE_REFINE:  # θmax near π: 1 + u2 again about u = −1 (f(−1) exact)
        h0 = E - a * u0 - b * u0 * u0
        e = _pole_coefficients(-1, h0, u0, dp, dm, R, G, a, b)
        refined = _refine_pole_distance(e, dm)
        slope = abs(_dhorner(g, u0))
        if slope > 0.0 and _noise(e, refined) < 4.0 * _EPS * slope + _noise(g, u0):
            dm = refined
            u0, dp = dm - 1.0, 2.0 - dm
    h0 = E - a * u0 - b * u0 * u0
    return _build(motion, 0.0, 0.0, _Start(u0, dp, dm, h0, 0.0, 0, "lower", hi - u0), fast)


def _expansion(mo: _Motion, st: _Start) -> tuple[tuple[float, ...], float]:
    """f(u0 + δ) = Σ c_i δ^i with c0 exact, and the round-off level of c1."""
    a, b, R, G = mo.a, mo.b, mo.R, mo.G
    u0, h0 = st.u0, st.h0
    s0sq = st.dp * st.dm
    e0 = G - R * u0
    h1 = a + 2.0 * b * u0
    c1 = -2.0 * s0sq * h1 - 4.0 * u0 * h0 + 2.0 * R * e0
    c2 = -2.0 * s0sq * b + 4.0 * u0 * h1 - 2.0 * h0 - R * R
    c3 = 4.0 * u0 * b + 2.0 * h1
    c1_noise = 16.0 * _EPS * (abs(2.0 * s0sq * h1) + abs(4.0 * u0 * h0) + abs(2.0 * R * e0))
    return (st.c0, c1, c2, c3, 2.0 * b), c1_noise


def _turning_points(
    mo: _Motion, st: _Start, c: tuple[float, ...], c1_noise: float, fast: bool
) -> tuple[float, float]:
    """(δ1, δ2) = (u1 − u0, u2 − u0): the fast path, else the careful one (module notes)."""
    end_up, end_dn = -((mo.G - mo.R) ** 2), -((mo.G + mo.R) ** 2)  # f(1), f(−1): exact (§3)
    turning = st.c0 == 0.0
    side = st.side
    # f'(u0) at round-off level with f'' < 0 at a turning start: a steady precession given in
    # floating point (u0 is a double root of f to working accuracy).
    if turning and side is None and abs(c[1]) <= c1_noise and c[2] < 0.0:
        side = "steady"
    if side == "steady":
        return 0.0, 0.0
    if fast:
        quick = _fast_turning_points(c, st.dp, st.dm, end_up, end_dn, side, c1_noise,
                                     st.d1_guess)  # fmt: skip
        if quick is not None:
            return quick
    return _careful_turning_points(c, st.dp, st.dm, end_up, end_dn, turning, side, st.u0)


def _points(
    mo: _Motion, st: _Start, c: tuple[float, ...], d1: float, d2: float
) -> tuple[_Point, _Point]:
    """The turning points with 1 − u1 and 1 + u2 to full relative accuracy.

    The difference dp − δ1 loses digits when θmin is near 0 (θmax near π); then they come
    again from the expansion about ±1, where f(±1) is exact. Each route's error bound is
    (round-off of its polynomial)/|f'(u1)|; the smaller wins. δ1, δ2 keep their own digits
    (they fix the phase τ0 of a start next to a turning point).
    """
    u0, dp, dm = st.u0, st.dp, st.dm
    args = (st.h0, u0, dp, dm, mo.R, mo.G, mo.a, mo.b)
    om1 = _pole_distance(c, d1, dp, _pole_coefficients(1, *args))
    op2 = _pole_distance(_reflect(c), -d2, dm, _pole_coefficients(-1, *args))
    p1 = _Point(u=u0 + d1 if om1 == dp - d1 else 1.0 - om1, om=om1, op=dm + d1, d=d1)
    p2 = _Point(u=u0 + d2 if op2 == dm + d2 else op2 - 1.0, om=dp - d2, op=op2, d=d2)
    return p1, p2


def _outer_roots(mo: _Motion, u0: float, c: tuple[float, ...], d1: float, d2: float) -> _Outer:
    """Deflation f(u0 + δ) = (δ − d1)(δ − d2)(c4 δ² + q1 δ + q0), and §4 from its roots."""
    c4, q1, q0 = _deflate(c, d1, d2)
    inf = complex(math.inf)
    if mo.a == 0.0 and mo.b == 0.0:
        # q ≡ c2 = −(2E + R²): u'' = −(2E + R²)u + GR (§11)
        return _Outer(1, inf, inf, 0.0, 1.0, -q0 / 4.0, 1.0, 1.0)
    disc = q1 * q1 - 4.0 * c4 * q0
    disc_noise = 64.0 * _EPS * (q1 * q1 + abs(4.0 * c4 * q0))
    if disc < -disc_noise:
        if c4 >= 0.0:
            raise ParameterError(
                f"b = {mo.b:g}: complex outer roots need b < 0; the state is numerically "
                "degenerate (at a separatrix?)"
            )
        cc = -q1 / (2.0 * c4)
        dd = math.sqrt(-disc) / (2.0 * abs(c4))
        m, mc, beta2, xi = _case2_modulus(d1, d2, cc, dd, c4)
        return _Outer(2, complex(u0 + cc, dd), complex(u0 + cc, -dd), m, mc, beta2, xi, xi)
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
    m, mc, beta2 = _case1_modulus(d1, d2, u3, u4, big3, big4, qq, c4)
    return _Outer(
        1,
        complex(u0 + u3) if math.isfinite(u3) else inf,
        complex(u0 + u4) if math.isfinite(u4) else inf,
        m,
        mc,
        beta2,
        _nu(d2, d1, u3, big3, qq, c4),
        _nu(d1, d2, u4, big4, qq, c4),
    )


def _checked_modulus(out: _Outer, free: bool) -> tuple[float, float, float]:
    """(k², 1 − k², β) clamped to [0, 1]; ParameterError at a separatrix or at rest."""
    m, mc, beta2 = out.m, out.mc, out.beta2
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
    return m, mc, math.sqrt(beta2)


def _charts_and_phase(
    out: _Outer, p1: _Point, p2: _Point, direction: int, mc: float, K: float
) -> tuple[_Chart, _Chart | None, float]:
    """The main chart, the other one (case 1), and the Jacobi argument τ0 of t = 0."""
    d1, d2 = p1.d, p2.d
    if out.root_case == 1:
        nu_max = out.nu_max
        # σ0 = sin²γ0 of (1.10) in the paper's anchoring (σ = −1: γ = 0 is θmax)
        den = -d2 + nu_max * d1
        sig0 = -d2 / den if den > 0.0 else 0.0
        sigc0 = nu_max * d1 / den if den > 0.0 else 1.0
        sgn = -1.0 if direction > 0 else 1.0
        tau0 = _ellipf_scalar(sgn * math.sqrt(sig0), math.sqrt(sigc0), mc)
        main = _Chart(A=p2, B=p1, nu=nu_max, offset=0.0)
        return main, _Chart(A=p1, B=p2, nu=out.nu_min, offset=K), tau0
    xi = out.nu_max
    # s0 = sin²(γ0/2) of §4.2 (σ = +1: γ = 0 is θmin)
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
    return _Chart(A=p1, B=p2, nu=xi, offset=0.0), None, tau0


def _build(mo: _Motion, psi0: float, phi0: float, st: _Start, fast: bool = True) -> NutationOrbit:
    """The orbit about u0 (δ = u − u0), from f(u0 + δ) = Σ c_i δ^i with c0 exact."""
    c, c1_noise = _expansion(mo, st)
    d1, d2 = _turning_points(mo, st, c, c1_noise, fast)
    p1, p2 = _points(mo, st, c, d1, d2)
    free = mo.a == 0.0 and mo.b == 0.0
    out = _outer_roots(mo, st.u0, c, d1, d2)
    m, mc, beta = _checked_modulus(out, free)
    kind: Kind = "steady" if d1 == d2 else ("free" if free else "elliptic")
    K = float(special.elliprf(0.0, mc, 1.0))
    main, other, tau0 = _charts_and_phase(out, p1, p2, st.direction, mc, K)
    roots: FloatArray = np.array([p1.u, p2.u, out.u3, out.u4], dtype=complex)
    roots.flags.writeable = False  # a frozen orbit
    orbit = NutationOrbit(
        mu=mo.mu, a=mo.a, b=mo.b, R=mo.R, G=mo.G, E=mo.E,
        root_case=out.root_case, roots=roots, u1=p1.u, u2=p2.u,
        theta_min=2.0 * math.atan2(math.sqrt(p1.om), math.sqrt(p1.op)),
        theta_max=2.0 * math.atan2(math.sqrt(p2.om), math.sqrt(p2.op)),
        k2=m, mc=mc, beta=beta, period=(2.0 if out.root_case == 1 else 4.0) * K / beta,
        kind=kind, mean_psidot=0.0, mean_phidot=0.0, psi0=float(psi0), phi0=float(phi0),
        _u0=float(st.u0), _K=K, _tau0=tau0, _turning_start=st.c0 == 0.0, _main=main,
        _other=other, _poles=(), _p1=p1, _p2=p2,
    )  # fmt: skip
    _attach_poles(orbit)
    return orbit


def _attach_poles(orbit: NutationOrbit) -> None:
    """The pole terms of ψ' and φ' and the mean rates, (1.12).

    ψ' = ½[(G+R)/(1+u) + (G−R)/(1−u)], φ' = ½[(G+R)/(1+u) − (G−R)/(1−u)] + R(1/μ − 1), with
    1/(1 − u) = −1/(u − 1). A term with G ∓ R = 0 is absent (§11). A turning point within
    _POLE_TOUCH of ±1 (θ within ~1e-140 rad of 0 or π, G ∓ R ~ 1e-140) is beyond the range
    of R_J: that term is treated as absent too (continuous branch).
    """
    G, R = orbit.G, orbit.R
    poles: list[tuple[float, float, _Pole]] = []
    if G + R != 0.0 and orbit._p2.op > _POLE_TOUCH:
        poles.append((0.5 * (G + R), 0.5 * (G + R), _make_pole(orbit, -1.0)))
    if G - R != 0.0 and orbit._p1.om > _POLE_TOUCH:
        poles.append((-0.5 * (G - R), 0.5 * (G - R), _make_pole(orbit, 1.0)))
    means = [pole.mean(orbit._K) for _, _, pole in poles]
    rate_psi = sum(wp * mk for (wp, _, _), mk in zip(poles, means, strict=True))
    rate_phi = sum(wf * mk for (_, wf, _), mk in zip(poles, means, strict=True))
    rate_phi += R * (1.0 / orbit.mu - 1.0)
    object.__setattr__(orbit, "_poles", tuple(poles))
    object.__setattr__(orbit, "mean_psidot", float(rate_psi))
    object.__setattr__(orbit, "mean_phidot", float(rate_phi))
