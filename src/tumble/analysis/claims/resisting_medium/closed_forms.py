"""Claims rm-5 … rm-7: the closed forms (2.4)–(2.10) of the averaged system against its
integration."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.analysis.claims.base import Measurement, Series, claim
from tumble.analysis.claims.common import (
    Difference,
    Tolerances,
    by_convergence,
    converged,
    max_abs,
    quiet,
    time_panel,
    tolerances,
)
from tumble.analysis.claims.resisting_medium.cases import RM, RM_AXIAL_CASES, medium, state
from tumble.integrate import simulate
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions


def averaged_run(p: rm.Params, st: rm.State, tau: np.ndarray, tol: Tolerances | None = None) -> Any:
    """Averaged system (2.2) integrated tightly (the reference for the closed forms): the
    trajectory (``columns``, ``nfev``), at ``tol`` or the reference tolerances. The equations
    alone: no step across ϑ = π/2, which the closed forms do not take either."""
    alone = AveragingOptions(averaged_only=True)
    return quiet(simulate, rm.MODEL, p, st, tau, "averaged", averaging=alone,
                 **(tol or tolerances()))  # fmt: skip


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
            run = averaged_run(p, st, tau, tol)
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


@claim(
    "rm-5",
    RM,
    "equatorial component (2.4)",
    "(2.4): k sinϑ = αV0 e^{−εατ}/[α + γV0(1 − e^{−εατ})], in both hemispheres.",
    "docs/theory/resisting-medium.md §8.1; §13.5",
    name="equatorial_component_follows_closed_form_2_4",
)
def rm_5() -> Measurement:
    """Closed form (2.4) of the equatorial component against integration of (2.2) (§8.1).

    Returns
    -------
    Claim
        Measured: max |V of (2.4) − V of (2.2) integrated| [1] over ετ ≤ 10; holds if it falls
        with the tolerance.
    """
    cases = {
        "α, γ > 0": (medium(0.2, 0.3, 0.1, 0.2, a3=0.4), state(1.0, 1.0)),
        "α = 0 (limit)": (medium(0.0, 0.3, 0.2, 0.1, a3=0.2), state(1.0, 1.3)),
        "γ = 0": (medium(0.3, 0.2, 0.0, 0.1, a3=-0.2), state(1.2, 2.2)),
    }
    difference = against_averaged(
        {name: (p, st, f"(2.4) {name}", _equatorial) for name, (p, st) in cases.items()}, 10.0
    )

    # Criterion: (2.4) is exact for (2.2), so V agrees to integration accuracy of (2.2).
    conv, (per, series) = converged(difference)
    panels = (
        time_panel(
            series,
            "V = k sin ϑ",
            "lines (2.4), dots: (2.2) integrated",
            xlabel="ετ",
        ),
    )
    return by_convergence(
        conv,
        panels,
        "1",
        f"max |V(2.4) − V of (2.2) integrated (rtol {conv.rtol:.0e})| over ετ ≤ 10, three media",
        per_case=per,
    )


def _equatorial(
    p: rm.Params, st: rm.State, tau: FloatArray, avg: Mapping[str, FloatArray]
) -> tuple[FloatArray, FloatArray]:
    """V = k sin ϑ [1] by (2.4) and along the integrated (2.2)."""
    return rm.equatorial_momentum(tau, st.V, p), avg["k"] * np.sin(avg["theta"])


def _printed_2_5_at_zero(W0: float, p: rm.Params) -> float:
    """The paper's (2.5) with its printed exponent −1/(2δ) on the denominator, at τ = 0
    (correction E3 shows it does not even return W0)."""
    a3, be, de = float(p.a[2]), p.beta, p.delta
    nu1 = math.sqrt((be / (2 * de)) ** 2 + a3 / de)
    c1 = (2 * de * W0 + be - 2 * de * nu1) / (2 * de * W0 + be + 2 * de * nu1)
    return (2 * de * nu1 - be + (2 * de * nu1 + be) * c1) * (1.0 - c1) ** (-1.0 / (2 * de))


@claim(
    "rm-6",
    RM,
    "axial component (2.5)–(2.8)",
    "(2.5)/(2.6) give k cosϑ in the upper hemisphere for a3/δ ≷ −(β/2δ)², (2.7)/(2.8) in the "
    "lower one for a3/δ ≶ (β/2δ)².",
    "docs/theory/resisting-medium.md §8.2–§8.5; correction E3; §13.5",
    name="axial_component_follows_closed_forms_2_5_to_2_8",
)
def rm_6() -> Measurement:
    """Closed forms (2.5)–(2.8) with the branch switch at τ1 (§8.2–§8.5, E3).

    Returns
    -------
    Claim
        Measured: max |closed form − (2.2) integrated| of k [1] and ϑ [rad] over ten branch cases;
        holds if it falls with the tolerance in every case.
    """
    series: list[Series] = []
    crossings: list[tuple[float, str]] = []
    printed: dict[str, float] = {}

    def difference(tol: Tolerances) -> tuple[Difference, int, tuple[dict[str, float], list[Any]]]:
        per, nfev, avgs = {}, 0, []
        for name, (p, st, horizon, _) in RM_AXIAL_CASES.items():
            tau = np.linspace(0.0, horizon / p.eps, 401)
            run = averaged_run(p, st, tau, tol)
            avg, nfev = run.columns, nfev + run.nfev
            cf = rm.closed_form(p, st, tau)
            per[name] = max(max_abs(cf["k"] - avg["k"]), max_abs(cf["theta"] - avg["theta"]))
            avgs.append(avg)
        return per, nfev, (per, avgs)

    # Criterion: k, ϑ to integration accuracy of (2.2) for every branch.
    conv, (per, avgs) = converged(difference)
    for (name, (p, st, horizon, printed_name)), avg in zip(
        RM_AXIAL_CASES.items(), avgs, strict=True
    ):
        tau = np.linspace(0.0, horizon / p.eps, 401)
        cf = rm.closed_form(p, st, tau)
        tau1 = rm.crossing_time(st.W, p)
        if printed_name is not None:
            # The paper's own formula (with E3 applied) inside its window, before τ1.
            window = tau[tau < min(tau1, tau[-1])]
            W_printed = getattr(rm, printed_name)(window, st.W, p)
            printed[name] = max_abs(W_printed - rm.axial_momentum(window, st.W, p))
        W = cf["k"] * np.cos(cf["theta"])
        series.append(Series(p.eps * tau, W, name))
        series.append(
            Series(p.eps * tau[::25], (avg["k"] * np.cos(avg["theta"]))[::25], style="markers")
        )
        if math.isfinite(tau1) and tau1 <= tau[-1]:
            crossings.append((p.eps * tau1, ""))
    panels = (
        time_panel(
            series,
            "W = k cos ϑ",
            "closed forms (lines), (2.2) integrated (dots), τ1 (vertical)",
            xlabel="ετ",
            hlines=((0.0, ""),),
            vlines=tuple(crossings),
        ),
    )
    p0, st0 = RM_AXIAL_CASES["(2.5) a3 > 0, upper"][:2]
    e3 = abs(_printed_2_5_at_zero(st0.W, p0) - st0.W)
    worst_printed = max(printed.values())
    # The printed formulas equal the well-conditioned closed form inside their windows: two
    # closed forms, no integration tolerance enters (1e-8: far below an O(1) wrong exponent).
    return by_convergence(
        conv,
        panels,
        "1 (k), rad (ϑ)",
        "max |closed form − (2.2) integrated| of k and ϑ over 10 branch cases (ετ ≤ 10, "
        "through the ϑ = π/2 switch)",
        "E3: the denominator of (2.5) is [1 − c1 e^{−2εδν1τ}]⁻¹/(2δ) (printed: exponent −1/2δ); "
        "each formula holds only while W keeps its sign, the branch switches at τ1 (§8.4)",
        also="; printed (2.5)–(2.8) = closed form to 1e-8 before τ1",
        condition=worst_printed <= 1e-8,
        per_case=per,
        printed_formula_vs_closed_form=printed,
        printed_2_5_W0_error=e3,
    )


@claim(
    "rm-7",
    RM,
    "a3 = 0: tan ϑ (2.9), (2.10)",
    "(2.9), (2.10): for a3 = 0 the nutation angle follows tanϑ = (α/β) tanϑ0 … "
    "e^{ε(β−α)τ} (upper) and … e^{−εατ} (lower), obtained from (2.4), (2.5).",
    "docs/theory/resisting-medium.md §8.6; correction E7; §13.5",
    name="tan_theta_follows_2_9_and_2_10_when_a3_is_zero",
)
def rm_7() -> Measurement:
    """tan ϑ for a3 = 0, (2.9) and (2.10) (§8.6, E7).

    Returns
    -------
    Claim
        Measured: max |ϑ of (2.9)/(2.10) − ϑ of (2.2) integrated| [rad]; holds if it falls
        with the tolerance.
    """
    cases: dict[str, AveragedCase] = {
        "(2.9) upper": (
            medium(0.2, 0.3, 0.1, 0.2),
            state(1.0, 0.7),
            "(2.9) upper",
            theta_of_tan(rm.tan_theta_a3_zero_upper, 0.0),
        ),
        "(2.10) lower": (
            medium(0.3, 0.2, 0.1, 0.2),
            state(1.0, 2.3),
            "(2.10) lower",
            theta_of_tan(rm.tan_theta_a3_zero_lower, math.pi),
        ),
    }
    difference = against_averaged(cases, 10.0)

    # Criterion: (2.9)/(2.10) are exact for (2.2): ϑ to its integration accuracy.
    conv, (per, series) = converged(difference)
    panels = (
        time_panel(
            series,
            "ϑ [rad]",
            "lines: (2.9)/(2.10); dots: (2.2) integrated",
            xlabel="ετ",
        ),
    )
    return by_convergence(
        conv,
        panels,
        "rad",
        "max |ϑ from (2.9)/(2.10) − ϑ of (2.2) integrated| over ετ ≤ 10",
        "E7: (2.9) is (2.4)/(2.5) and (2.10) is (2.4)/(2.7) at a3 = 0 (the paper's 'inequality' "
        "is the condition of (2.7)); they are 0/0 for α = 0 or β = 0 (use W, V)",
        per_case=per,
    )
