"""Period averages over the orbit (§8 of the theory): the moments ⟨u^j⟩ in closed form and by
recurrence, with a periodic trapezoid rule as their fallback, and the quadratures that
:meth:`NutationOrbit.average` and :meth:`NutationOrbit.time_integral` use."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError
from tumble.unperturbed.elliptic import _jacobi
from tumble.unperturbed.symmetric_body.carlson import _drj_dp, _rj_complete
from tumble.unperturbed.symmetric_body.charts import _EPS, _Chart, _Jac
from tumble.unperturbed.symmetric_body.potential import quartic_coefficients

if TYPE_CHECKING:
    from tumble.unperturbed.symmetric_body.orbit import NutationOrbit

_X2_CLOSED_DIST = 0.02  # ⟨X²⟩ by (∂R_J/∂p) only when p is this far from 1 − k² and 1 (case 1)
_MOMENT_RTOL = 1e-13  # recurrence of §8 accepted while its error bound stays below this
_QUAD_RTOL = 4e-16  # internal trapezoid fallbacks: converged to round-off


def x_moments(orbit: NutationOrbit, ch: _Chart) -> tuple[float, float | None, float]:
    """(⟨X⟩, ⟨X²⟩, distance) for X = σ/((1 − σ) + νσ) in chart ``ch``, §8.

    Case 1: ⟨X⟩ = R_J(0, k'², 1, ν)/(3K), ⟨X²⟩ = −∂⟨X⟩/∂ν; ⟨X²⟩ is None when ν lies within
    _X2_CLOSED_DIST of the removable singularities ν = k'² (n = m) and ν = 1 (n = 0). Case 2:
    from I1, I2 of §8 with p = (ξ + 1)²/(4ξ) = 1 + ŵ; the ∂R_J term carries (ξ² − 1)² =
    4ξ(ξ + 1)²(p − 1), which cancels its 0/0 at p = 1, and p ≥ 1 > k'² away from n = m.
    """
    K, mc, nu = orbit._K, orbit.mc, ch.nu
    if orbit.root_case == 1:
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


def periodic_mean(
    orbit: NutationOrbit, func: Callable[[FloatArray, FloatArray], FloatArray], scale: float
) -> float:
    """Trapezoid in the Jacobi argument over one period of σ (uniform in time), doubling."""
    period_v = (2.0 if orbit.root_case == 1 else 4.0) * orbit._K

    def node_sum(v: FloatArray) -> float:  # Σ func(σ, 1 − σ) at Jacobi arguments v
        return float(np.sum(func(*orbit._sigma(_Jac(*_jacobi(v, orbit.k2, orbit.mc, orbit._K))))))

    n = 16
    total = node_sum(period_v * np.arange(n) / n)
    est = total / n
    while n < (1 << 20):
        total += node_sum(period_v * (np.arange(n) + 0.5) / n)
        n *= 2
        new = total / n
        if abs(new - est) <= _QUAD_RTOL * max(abs(new), scale) and n >= 64:
            return new
        est = new
    raise IntegrationError(
        f"period average did not converge (k² = {orbit.k2:.6g}, 1 − k² = {orbit.mc:.3g})"
    )


def u_moments(orbit: NutationOrbit, n: int) -> list[float]:
    """⟨u^j⟩, j = 0..n: closed forms (j ≤ 2), recurrence of §8, trapezoid fallback."""
    if orbit.kind == "steady":
        return [orbit._u0**j for j in range(n + 1)]
    scale = max(abs(orbit.u1), abs(orbit.u2))
    main = orbit._main
    x1_main = x_moments(orbit, main)[0]
    m1 = orbit._u0 + main.A.d + (main.B.d - main.A.d) * main.nu * x1_main
    moments = [1.0, m1]
    errs = [0.0, 8.0 * _EPS * max(scale, abs(m1))]
    if n <= 1:
        return moments[: n + 1]
    g = tuple(float(x) for x in quartic_coefficients(orbit.R, orbit.G, orbit.a, orbit.b, orbit.E))
    # Case 1: the chart (seed's or alternative anchoring) whose ν is farther from the
    # removable singularities of ∂R_J; case 2 has one chart and no such problem.
    charts = [main] if orbit._other is None else [main, orbit._other]
    best = max(((ch, *x_moments(orbit, ch)) for ch in charts), key=lambda item: item[3])
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
        m2 = power_quadrature(orbit, 2, scale)
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
        if lead == 0.0 or not (math.isfinite(val) and err <= _MOMENT_RTOL * max(scale**j, 1e-300)):
            # Ill-conditioned (outer roots far from [u2, u1], small |b|): trapezoid in time.
            moments.extend(power_quadrature(orbit, i, scale) for i in range(j, n + 1))
            break
        moments.append(val)
        errs.append(err + 4.0 * _EPS * abs(val))
    return moments


def power_quadrature(orbit: NutationOrbit, j: int, scale: float) -> float:
    ch = orbit._main
    ua, ub, nu = ch.A.u, ch.B.u, ch.nu

    def uj(sig: FloatArray, sigc: FloatArray) -> FloatArray:
        u = (ua * sigc + ub * nu * sig) / (sigc + nu * sig)
        return np.asarray(u**j, dtype=float)

    return periodic_mean(orbit, uj, scale**j)


def g_values(
    orbit: NutationOrbit, g: Callable[[FloatArray, FloatArray], ArrayLike], t: FloatArray
) -> FloatArray:
    th, thd = orbit._theta_pair(t)
    vals = np.broadcast_to(np.asarray(g(th, thd), dtype=float), t.shape)
    if not np.all(np.isfinite(vals)):
        raise IntegrationError(
            f"g returned non-finite values on the orbit (k² = {orbit.k2:.6g}, "
            f"1 − k² = {orbit.mc:.3g})"
        )
    return vals


def gauss_legendre(
    orbit: NutationOrbit,
    g: Callable[[FloatArray, FloatArray], ArrayLike],
    lo: float,
    hi: float,
    rtol: float,
) -> float:
    x20, w20 = np.polynomial.legendre.leggauss(20)
    x40, w40 = np.polynomial.legendre.leggauss(40)
    m = max(1, math.ceil((hi - lo) / (orbit.period / 8.0)))
    edges = np.linspace(lo, hi, m + 1)
    stack = [(float(edges[i]), float(edges[i + 1]), 0) for i in range(m)]
    total = 0.0
    while stack:
        a, b, depth = stack.pop()
        mid, half = 0.5 * (a + b), 0.5 * (b - a)
        f40 = g_values(orbit, g, mid + half * x40)
        fine = half * float(np.dot(w40, f40))
        coarse = half * float(np.dot(w20, g_values(orbit, g, mid + half * x20)))
        scale = half * float(np.dot(w40, np.abs(f40)))
        if abs(fine - coarse) <= rtol * scale:
            total += fine
        elif depth >= 40:
            raise IntegrationError(
                f"time_integral did not converge on [{lo:g}, {hi:g}] (k² = {orbit.k2:.6g}, "
                f"1 − k² = {orbit.mc:.3g})"
            )
        else:
            stack.append((a, mid, depth + 1))
            stack.append((mid, b, depth + 1))
    return total
