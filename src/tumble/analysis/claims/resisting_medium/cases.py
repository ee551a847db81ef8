"""The resisting medium's cases shared by its claims: the media and states of theory §13 and
the branch cases of the closed forms (A. V. Medvedev 1987; docs/theory/resisting-medium.md)."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.analysis.claims.base import Series
from tumble.analysis.claims.common import Difference, Tolerances, max_abs, quiet, tolerances
from tumble.integrate import simulate
from tumble.models import resisting_medium as rm

RM = "resisting_medium"
RM_KAPPA = 0.5
"""κ of the closed-form cases (an oblate body, as in §13 checks and tumble's tests)."""

RM_GENERAL = rm.Params(
    eps=0.01,
    kappa=0.5,
    a=np.array([0.1, -0.05, 0.3]),
    b=np.array([[0.2, 0.01, 0.02], [0.0, 0.25, 0.0], [0.03, 0.0, 0.1]]),
    s=np.array([[0.1, 0.0, 0.01], [0.0, 0.12, 0.0], [0.0, 0.02, 0.05]]),
)
"""Theory §13.2/§13.6: full (non-diagonal) B and S, a1, a2 ≠ 0, oblate body."""

RM_START = rm.State(k=1.0, rho=1.2, sigma=0.3, psi=0.2, theta=1.0, phi=0.1)
"""ϑ and ρ away from 0 and π (§13.2), upper hemisphere, a3 > 0: no crossing of π/2 (§13.6)."""

RM_PROLATE = (
    rm.Params(
        eps=0.01,
        kappa=-0.4,
        a=np.array([0.05, 0.1, -0.2]),
        b=np.array([[0.15, -0.02, 0.0], [0.03, 0.1, 0.01], [0.0, 0.02, 0.2]]),
        s=np.array([[0.05, 0.01, 0.0], [0.0, 0.08, 0.0], [0.01, 0.0, 0.1]]),
    ),
    rm.State(1.2, 2.0, -1.0, 1.0, 2.2, -0.5),
)
"""Theory §13.6: the other hemisphere and a prolate body (a3 < 0 keeps ϑ > π/2)."""


def _rm_medium(
    alpha: float = 0.0,
    beta: float = 0.0,
    gamma: float = 0.0,
    delta: float = 0.0,
    a3: float = 0.0,
    eps: float = 0.01,
    a12: tuple[float, float] = (0.0, 0.0),
) -> rm.Params:
    """Params with the given α, β, γ, δ of (2.2): diagonal b, s inverting the definitions of
    §6 (α = (b11+b22)/2, β = b33/(1+κ), γ = 4(s11+s22)/(3π), δ = s33/(1+κ)²)."""
    k1 = 1.0 + RM_KAPPA
    b = np.diag([alpha, alpha, beta * k1])
    s = np.diag([gamma * 3.0 * math.pi / 8.0, gamma * 3.0 * math.pi / 8.0, delta * k1 * k1])
    return rm.Params(eps=eps, kappa=RM_KAPPA, a=np.array([*a12, a3]), b=b, s=s)


def _rm_state(k: float, theta: float, phi: float = 0.0) -> rm.State:
    return rm.State(k=k, rho=1.0, sigma=0.2, psi=0.0, theta=theta, phi=phi)


def _rm_averaged(p: rm.Params, st: rm.State, tau: np.ndarray, tol: Tolerances | None = None) -> Any:
    """Averaged system (2.2) integrated tightly (the reference for the closed forms): the
    trajectory (``columns``, ``nfev``), at ``tol`` or the reference tolerances."""
    return quiet(simulate, rm.MODEL, p, st, tau, "averaged", **(tol or tolerances()))


Prediction = Callable[
    [rm.Params, rm.State, FloatArray, Mapping[str, FloatArray]], tuple[FloatArray, FloatArray]
]
"""``predict(p, st, tau, averaged columns)``: a closed form of (2.2) along ``tau`` and the same
quantity from the integrated (2.2)."""

AveragedCase = tuple[rm.Params, rm.State, str, Prediction]
"""A closed form checked against (2.2): params, initial state, the label of its curve, and its
:data:`Prediction`."""


def against_averaged(
    cases: Mapping[str, AveragedCase], slow_time: float
) -> Callable[[Tolerances], tuple[Difference, int, tuple[dict[str, float], list[Series]]]]:
    """The ``difference`` of :func:`~tumble.analysis.claims.common.converged` for closed forms
    of the averaged system (2.2), case by case.

    Parameters
    ----------
    cases : mapping
        Case name → :data:`AveragedCase`.
    slow_time : float
        The horizon ετ of each run [1], sampled at 401 points.

    Returns
    -------
    callable
        ``difference(tolerances)``: max |closed form − (2.2) integrated| per case, the
        right-hand-side evaluations, and (that per-case record, the figure's series: each closed
        form as a line against ετ, every 20th sample of its integration as markers).
    """

    def difference(
        tol: Tolerances,
    ) -> tuple[Difference, int, tuple[dict[str, float], list[Series]]]:
        series: list[Series] = []
        per, nfev = {}, 0
        for name, (p, st, label, predict) in cases.items():
            tau = np.linspace(0.0, slow_time / p.eps, 401)
            run = _rm_averaged(p, st, tau, tol)
            avg, nfev = run.columns, nfev + run.nfev
            closed, integrated = predict(p, st, tau, avg)
            per[name] = max_abs(closed - integrated)
            series.append(Series(p.eps * tau, closed, label))
            series.append(Series(p.eps * tau[::20], integrated[::20], style="markers"))
        return per, nfev, (per, series)

    return difference


def theta_of_tan(formula: Callable[..., FloatArray], shift: float) -> Prediction:
    """The :data:`Prediction` of ϑ [rad] by a closed form of tan ϑ, ``formula(tau, k0, ϑ0, p)``:
    ``shift`` + arctan, ``shift`` = π in the lower hemisphere (§8.6: π + arctan of (2.10))."""

    def predict(
        p: rm.Params, st: rm.State, tau: FloatArray, avg: Mapping[str, FloatArray]
    ) -> tuple[FloatArray, FloatArray]:
        return shift + np.arctan(formula(tau, st.k, st.theta, p)), avg["theta"]

    return predict


def _rm_random_states(n: int, seed: int) -> list[tuple[rm.Params, float, float, float]]:
    """Random media (full B, S, a1, a2 ≠ 0) and states for the pointwise checks of §13.3–4."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        kappa = float(rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 0.9))
        p = rm.Params(
            eps=0.01,
            kappa=kappa,
            a=rng.uniform(-0.5, 0.5, 3),
            b=rng.uniform(-0.3, 0.5, (3, 3)),
            s=rng.uniform(-0.2, 0.4, (3, 3)),
        )
        out.append((p, rng.uniform(0.5, 2.0), rng.uniform(0.3, 2.8), rng.uniform(0.2, 2.9)))
    return out


RM_AXIAL_CASES = {
    # name: (params, initial state, slow-time horizon, printed formula checked before τ1)
    "(2.5) a3 > 0, upper": (
        _rm_medium(0.2, 0.3, 0.1, 0.2, a3=0.4),
        _rm_state(1.0, 1.0),
        10.0,
        "axial_upper_exp",
    ),
    "(2.6) → (2.7)": (
        _rm_medium(0.1, 0.2, 0.1, 0.3, a3=-0.5),
        _rm_state(1.0, 0.8),
        10.0,
        "axial_upper_tan",
    ),
    "(2.7) a3 > 0 → (2.5)": (
        _rm_medium(0.1, 0.5, 0.1, 0.1, a3=0.2),
        _rm_state(1.5, 2.5),
        10.0,
        "axial_lower_exp",
    ),
    "(2.8) → (2.5)": (
        _rm_medium(0.2, 0.1, 0.1, 0.2, a3=0.6),
        _rm_state(1.0, 2.6),
        10.0,
        "axial_lower_tan",
    ),
    "(2.5) small a3 < 0 → (2.7)": (
        _rm_medium(0.1, 0.6, 0.1, 0.1, a3=-0.05),
        _rm_state(1.0, 1.2),
        10.0,
        "axial_upper_exp",
    ),
    "upper double root": (
        _rm_medium(0.1, 0.2, 0.1, 0.1, a3=-0.1),
        _rm_state(1.0, 1.0),
        10.0,
        "axial_upper_double_root",
    ),
    "lower double root": (
        _rm_medium(0.1, 0.2, 0.1, 0.1, a3=0.1),
        _rm_state(1.0, 2.0),
        10.0,
        "axial_lower_double_root",
    ),
    "δ = 0": (_rm_medium(0.2, 0.3, 0.1, 0.0, a3=-0.2), _rm_state(1.0, 1.0), 10.0, None),
    "β = δ = 0": (_rm_medium(0.2, 0.0, 0.1, 0.0, a3=0.2), _rm_state(1.0, 2.0), 10.0, None),
    "β = 0, δ > 0": (
        _rm_medium(0.2, 0.0, 0.1, 0.2, a3=-0.3),
        _rm_state(1.0, 0.9),
        10.0,
        "axial_upper_tan",
    ),
}
"""Theory §13.5: every branch of (2.5)–(2.8), the switches of §8.4, the double roots, δ = 0."""
