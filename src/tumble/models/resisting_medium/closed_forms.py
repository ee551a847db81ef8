"""The averaged motion of the resisting-medium model in closed form (§8 of
``docs/theory/resisting-medium.md``): W = k cos ϑ and V = k sin ϑ from the scalar Riccati
equations of (2.3), with the branch switch at ϑ = π/2, and the paper's printed formulas
(2.4)–(2.10), each valid in its window.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError
from tumble.models.inputs.resisting_medium import Params, State

# ---------------------------------------------------------------------------------------------
# Closed forms, §8. Internally in slow time s = ε τ.
#
# Both components obey scalar Riccati equations. In a window where W keeps its sign, with
# d = δ (W ≥ 0) or d = −δ (W < 0):  dW/ds = a3 − βW − dW².  V obeys dV/ds = −αV − γV².
# Real roots: with r the root that stays bounded as d → 0 and λ = β + 2dr, u = W − r solves the
# Bernoulli equation du/ds = −λu − du² (this is (2.4) for V, and (2.5)/(2.7) rewritten so that
# neither d → 0 nor a double root loses digits). Complex roots: the tangent law (2.6)/(2.8), in
# the division-free form of §8.5.


def _bernoulli(u0: float, lam: float, d: float, s: FloatArray) -> FloatArray:
    """Solution of du/ds = −λu − du², u(0) = u0 (no blow-up inside ``s`` assumed)."""
    if lam >= 0.0:
        growth = s if lam == 0.0 else -np.expm1(-lam * s) / lam  # (1 − e^{−λs})/λ
        return u0 * np.exp(-lam * s) / (1.0 + d * u0 * growth)
    # λ < 0: divide through by e^{−λs}, which grows, to avoid overflow.
    return u0 / (np.exp(lam * s) + d * u0 * np.expm1(lam * s) / lam)


def _bernoulli_blowup(u0: float, lam: float, d: float) -> float:
    """Slow time at which the Bernoulli solution diverges, or inf."""
    c = d * u0
    if c >= 0.0:
        return math.inf
    e_star = -1.0 / c  # the denominator 1 + c (1 − e^{−λs})/λ vanishes there
    if lam == 0.0:
        return e_star
    if lam > 0.0 and lam * e_star >= 1.0:
        return math.inf
    return -math.log1p(-lam * e_star) / lam


@dataclass(frozen=True)
class _Riccati:
    """dW/ds = a3 − βW − dW² from W(0) = W0 (one sign window of (2.3))."""

    W0: float
    a3: float
    beta: float
    d: float

    @property
    def _disc(self) -> float:
        return self.beta * self.beta + 4.0 * self.d * self.a3

    def _root_rate(self) -> tuple[float, float]:
        lam = math.sqrt(self._disc)
        lam = lam if self.beta >= 0.0 else -lam
        r = 0.0 if self.beta + lam == 0.0 else 2.0 * self.a3 / (self.beta + lam)
        return r, lam

    def __call__(self, s: FloatArray) -> FloatArray:
        s = np.asarray(s, dtype=float)
        a3, beta, d, W0 = self.a3, self.beta, self.d, self.W0
        if d == 0.0:
            if beta == 0.0:
                return W0 + a3 * s
            return W0 * np.exp(-beta * s) - a3 * np.expm1(-beta * s) / beta
        if self._disc >= 0.0:
            r, lam = self._root_rate()
            return r + _bernoulli(W0 - r, lam, d, s)
        # Complex roots: y = W + h obeys dy/dx = −(y² + μ²), x = d s (§8.5, tan branch).
        h = beta / (2.0 * d)
        mu = math.sqrt(-self._disc) / (2.0 * abs(d))
        x = d * s
        y0 = W0 + h
        c = np.cos(mu * x)
        sin_over_mu = x * np.sinc(mu * x / math.pi)
        return (y0 * c - mu * mu * sin_over_mu) / (c + y0 * sin_over_mu) - h

    def blowup(self) -> float:
        """Slow time at which W diverges (inf if never)."""
        if self.d == 0.0:
            return math.inf
        if self._disc >= 0.0:
            r, lam = self._root_rate()
            return _bernoulli_blowup(self.W0 - r, lam, self.d)
        h = self.beta / (2.0 * self.d)
        mu = math.sqrt(-self._disc) / (2.0 * abs(self.d))
        theta0 = math.atan((self.W0 + h) / mu)
        # y = μ tan(θ0 − μx) has its pole at θ0 − μx = ∓π/2, reached for x of the sign of d.
        x_pole = (theta0 + math.pi / 2) / mu if self.d > 0 else (theta0 - math.pi / 2) / mu
        return x_pole / self.d

    def zero_crossing(self) -> float:
        """Slow time at which W reaches 0 (inf if it does not), §8.4."""
        a3, beta, d, W0 = self.a3, self.beta, self.d, self.W0
        if W0 == 0.0 or a3 == 0.0 or (a3 > 0) == (W0 > 0):
            return math.inf  # W = 0 is crossed only in the direction of a3
        if d == 0.0:
            if beta == 0.0:
                s1 = -W0 / a3
            else:
                arg = -beta * W0 / a3
                s1 = math.log1p(arg) / beta if arg > -1.0 else math.inf
        elif self._disc >= 0.0:
            r, lam = self._root_rate()
            u0 = W0 - r
            if u0 == 0.0:
                return math.inf
            e_star = W0 / (u0 * 0.5 * (lam + beta))  # u(s1) = −r
            if e_star <= 0.0 or (lam > 0.0 and lam * e_star >= 1.0):
                return math.inf
            s1 = e_star if lam == 0.0 else -math.log1p(-lam * e_star) / lam
        else:
            h = beta / (2.0 * d)
            mu = math.sqrt(-self._disc) / (2.0 * abs(d))
            y0 = W0 + h
            # (arctan(y0/μ) − arctan(h/μ))/μ without losing the branch (§8.4 table);
            # y0 − h is W0 itself, kept exact for a start near ϑ = π/2.
            s1 = math.atan2(mu * W0, mu * mu + y0 * h) / mu / d
        return s1 if (s1 >= 0.0 and s1 < self.blowup()) else math.inf


@dataclass(frozen=True)
class _AxialSolution:
    """W(s) over both sign windows, switching branch at the crossing (§8.4)."""

    first: _Riccati | None  # None: W ≡ 0
    s_cross: float
    second: _Riccati | None
    s_blowup: float

    def __call__(self, s: FloatArray) -> FloatArray:
        s = np.asarray(s, dtype=float)
        if self.first is None:
            return np.zeros_like(s)
        out = np.empty_like(s)
        before = s <= self.s_cross
        out[before] = self.first(s[before])
        if self.second is not None and np.any(~before):
            out[~before] = self.second(s[~before] - self.s_cross)
        return out


def _axial_solution(W0: float, a3: float, beta: float, delta: float) -> _AxialSolution:
    if W0 == 0.0 and a3 == 0.0:
        return _AxialSolution(None, math.inf, None, math.inf)
    side = math.copysign(1.0, W0) if W0 != 0.0 else math.copysign(1.0, a3)
    # Lower hemisphere: −δW|W| = +δW², i.e. d = −δ (the "∓" of (2.3)).
    first = _Riccati(W0, a3, beta, side * delta)
    s_cross = first.zero_crossing()
    if math.isinf(s_cross):
        return _AxialSolution(first, math.inf, None, first.blowup())
    second = _Riccati(0.0, a3, beta, -side * delta)
    return _AxialSolution(first, s_cross, second, s_cross + second.blowup())


def _slow_time(tau: ArrayLike, p: Params) -> FloatArray:
    return p.eps * np.asarray(tau, dtype=float)


def _check_no_blowup(s: FloatArray, s_blow: float, what: str, p: Params) -> None:
    if s.size and np.max(s) >= s_blow:
        raise IntegrationError(
            f"the closed-form {what} diverges at τ = {s_blow / p.eps:.6g} (negative damping "
            f"coefficients, §11); request times before it"
        )


def equatorial_momentum(tau: ArrayLike, V0: float, p: Params) -> FloatArray:
    """V(τ) = k sin ϑ, closed form (2.4), valid in both hemispheres.

    Parameters
    ----------
    tau : array_like
        Times τ ≥ 0 [1].
    V0 : float
        Initial k0 sin ϑ0 ≥ 0 [1].
    p : Params
        Model parameters (α, γ, ε are used).

    Returns
    -------
    ndarray
        V at the requested times [1].
    """
    s = _slow_time(tau, p)
    _check_no_blowup(s, _bernoulli_blowup(V0, p.alpha, p.gamma), "V = k sin ϑ of (2.4)", p)
    return _bernoulli(V0, p.alpha, p.gamma, s)


def axial_momentum(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """W(τ) = k cos ϑ, closed forms (2.5)–(2.8) with the branch switch of §8.4.

    Each hemisphere's formula is used only while W keeps its sign; at the crossing time τ1 the
    other hemisphere's formula continues from W = 0. Written in the well-conditioned forms of
    §8.5 (algebraically identical to (2.5)–(2.8), the double roots and δ = 0).

    Parameters
    ----------
    tau : array_like
        Times τ ≥ 0 [1].
    W0 : float
        Initial k0 cos ϑ0 [1].
    p : Params
        Model parameters (a3, β, δ, ε are used).

    Returns
    -------
    ndarray
        W at the requested times [1].
    """
    s = _slow_time(tau, p)
    sol = _axial_solution(W0, float(p.a[2]), p.beta, p.delta)
    _check_no_blowup(s, sol.s_blowup, "W = k cos ϑ of (2.3)", p)
    return sol(s)


def crossing_time(W0: float, p: Params) -> float:
    """Time τ1 at which the averaged W = k cos ϑ reaches 0 (ϑ = π/2), §8.4; inf if never.

    Parameters
    ----------
    W0 : float
        Initial k0 cos ϑ0 [1].
    p : Params
        Model parameters.
    """
    s1 = _axial_solution(W0, float(p.a[2]), p.beta, p.delta).s_cross
    return math.inf if (math.isinf(s1) or p.eps == 0.0) else s1 / p.eps


def closed_form(p: Params, st: State, tau: ArrayLike) -> dict[str, FloatArray]:
    """Averaged motion in closed form: k, ϑ from (2.4)–(2.8) through W and V, ρ, σ constant.

    ϑ = atan2(V, W) (§8.6: no trouble at ϑ = π/2, no α/β division).

    Parameters
    ----------
    p : Params
        Model parameters.
    st : State
        Initial state (ψ, φ unused).
    tau : array_like
        Times τ ≥ 0 [1].

    Returns
    -------
    dict
        Columns ``k``, ``theta``, ``rho``, ``sigma`` at the requested times.
    """
    tau = np.asarray(tau, dtype=float)
    W = axial_momentum(tau, st.W, p)
    V = equatorial_momentum(tau, st.V, p)
    return plane_columns(st, np.hypot(W, V), np.arctan2(V, W))


def plane_columns(st: State, k: FloatArray, theta: FloatArray) -> dict[str, FloatArray]:
    """The columns of an averaged motion: its ``k`` [1] and ``theta`` [rad], with ρ and σ
    constant at their initial values in ``st`` (as (2.2) has them)."""
    return {
        "k": k,
        "theta": theta,
        "rho": np.full(np.shape(k), st.rho),
        "sigma": np.full(np.shape(k), st.sigma),
    }


# The paper's printed formulas, one per case, each valid only in its window (§8).


def _coeffs(p: Params) -> tuple[float, float, float, float]:
    if p.delta == 0.0:
        raise ParameterError("parameters.s[2][2] = 0: (2.5)–(2.8) need δ > 0; use axial_momentum")
    return float(p.a[2]), p.beta, p.delta, p.beta / (2.0 * p.delta)


def axial_upper_exp(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.5) with correction E3: k cos ϑ for W ≥ 0 when a3/δ > −h², h = β/(2δ).

    Parameters
    ----------
    tau : array_like
        Times τ [1], before any crossing of ϑ = π/2.
    W0 : float
        k0 cos ϑ0 ≥ 0 [1].
    p : Params
        Model parameters with δ > 0.
    """
    a3, be, de, h = _coeffs(p)
    nu1_sq = h * h + a3 / de
    if nu1_sq <= 0.0:
        raise ParameterError(f"(2.5) needs a3/δ > −(β/2δ)², got ν1² = {nu1_sq:g}")
    nu1 = math.sqrt(nu1_sq)
    c1 = (2 * de * W0 + be - 2 * de * nu1) / (2 * de * W0 + be + 2 * de * nu1)
    e = c1 * np.exp(-2 * p.eps * de * nu1 * np.asarray(tau, dtype=float))
    return (2 * de * nu1 - be + (2 * de * nu1 + be) * e) / (2 * de * (1 - e))


def axial_upper_tan(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.6): k cos ϑ for W ≥ 0 when a3/δ < −h² (μ1² = −h² − a3/δ > 0)."""
    a3, be, de, h = _coeffs(p)
    mu1_sq = -h * h - a3 / de
    if mu1_sq <= 0.0:
        raise ParameterError(f"(2.6) needs a3/δ < −(β/2δ)², got μ1² = {mu1_sq:g}")
    mu1 = math.sqrt(mu1_sq)
    arg = math.atan((2 * de * W0 + be) / (2 * de * mu1)) - p.eps * de * mu1 * np.asarray(
        tau, dtype=float
    )
    return (-be + 2 * de * mu1 * np.tan(arg)) / (2 * de)


def axial_upper_double_root(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """Double root a3/δ = −h² of the upper branch: W = −h + y0/(1 + εδ y0 τ), y0 = W0 + h."""
    _, _, de, h = _coeffs(p)
    y0 = W0 + h
    return -h + y0 / (1 + p.eps * de * y0 * np.asarray(tau, dtype=float))


def axial_lower_exp(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.7): k cos ϑ for W < 0 when a3/δ < h² (ν2² = h² − a3/δ > 0)."""
    a3, be, de, h = _coeffs(p)
    nu2_sq = h * h - a3 / de
    if nu2_sq <= 0.0:
        raise ParameterError(f"(2.7) needs a3/δ < (β/2δ)², got ν2² = {nu2_sq:g}")
    nu2 = math.sqrt(nu2_sq)
    c2 = (2 * de * (W0 - nu2) - be) / (2 * de * (W0 + nu2) - be)
    e = c2 * np.exp(2 * p.eps * de * nu2 * np.asarray(tau, dtype=float))
    return (2 * de * nu2 + be + (2 * de * nu2 - be) * e) / (2 * de * (1 - e))


def axial_lower_tan(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.8): k cos ϑ for W < 0 when a3/δ > h² (μ2² = a3/δ − h² > 0)."""
    a3, be, de, h = _coeffs(p)
    mu2_sq = a3 / de - h * h
    if mu2_sq <= 0.0:
        raise ParameterError(f"(2.8) needs a3/δ > (β/2δ)², got μ2² = {mu2_sq:g}")
    mu2 = math.sqrt(mu2_sq)
    arg = math.atan((2 * de * W0 - be) / (2 * de * mu2)) + p.eps * de * mu2 * np.asarray(
        tau, dtype=float
    )
    return (be + 2 * de * mu2 * np.tan(arg)) / (2 * de)


def axial_lower_double_root(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """Double root a3/δ = h² of the lower branch: W = h + y0/(1 − εδ y0 τ), y0 = W0 − h."""
    _, _, de, h = _coeffs(p)
    y0 = W0 - h
    return h + y0 / (1 - p.eps * de * y0 * np.asarray(tau, dtype=float))


def tan_theta_a3_zero_upper(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """(2.9): tan ϑ for a3 = 0, α, β > 0, 0 ≤ ϑ < π/2 (correction E7)."""
    t = np.asarray(tau, dtype=float)
    al, be, ga, de, e = p.alpha, p.beta, p.gamma, p.delta, p.eps
    num = be + de * k0 * math.cos(theta0) * (-np.expm1(-e * be * t))
    den = al + ga * k0 * math.sin(theta0) * (-np.expm1(-e * al * t))
    return al / be * math.tan(theta0) * num / den * np.exp(e * (be - al) * t)


def tan_theta_a3_zero_lower(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """(2.10): tan ϑ for a3 = 0, α, β > 0, π/2 < ϑ ≤ π (tan ϑ < 0; ϑ = π + arctan)."""
    t = np.asarray(tau, dtype=float)
    al, be, ga, de, e = p.alpha, p.beta, p.gamma, p.delta, p.eps
    w = de * k0 * math.cos(theta0)
    num = w - (w - be) * np.exp(e * be * t)
    den = al + ga * k0 * math.sin(theta0) * (-np.expm1(-e * al * t))
    return al / be * math.tan(theta0) * num / den * np.exp(-e * al * t)


def tan_theta_quadratic(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """Quadratic-only medium (a3 = α = β = 0), §8.7, both hemispheres (correction E8).

    tan ϑ = tan ϑ0 (1 + εδ k0 |cos ϑ0| τ)/(1 + εγ k0 sin ϑ0 τ).
    """
    t = np.asarray(tau, dtype=float)
    num = 1 + p.eps * p.delta * k0 * abs(math.cos(theta0)) * t
    den = 1 + p.eps * p.gamma * k0 * math.sin(theta0) * t
    return math.tan(theta0) * num / den
