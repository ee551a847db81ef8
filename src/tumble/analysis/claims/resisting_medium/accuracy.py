"""Claims rm-13 … rm-16: the full model against the averaged one (first-order accuracy, the
passage through ϑ = π/2, the final tilt)."""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from tumble.analysis import averaging_error_study, fitted_order
from tumble.analysis.claims.base import Measurement, Panel, Series, claim
from tumble.analysis.claims.common import (
    by_order,
    cache_per_scale,
    eps_panel,
    judged,
    max_abs,
    time_panel,
    tolerances,
)
from tumble.analysis.claims.resisting_medium.cases import (
    RM,
    RM_GENERAL,
    RM_PROLATE,
    RM_START,
    medium,
    state,
)
from tumble.integrate import simulate
from tumble.models import resisting_medium as rm

RM_STUDY_CASES = {"oblate upper (GENERAL)": (RM_GENERAL, RM_START), "prolate lower": RM_PROLATE}
"""The two media of the averaged-vs-full error study of §13.6."""


@cache_per_scale
def _rm_accuracy_study() -> dict[str, Any]:
    """Averaged-vs-full error study of §13.6 (shared by rm-13 and rm-14): ε halved four times
    (0.02 … 0.00125), so that the fitted order is not decided by the phase of one resonance
    passage (§10.5) at one ε."""
    eps = [0.02, 0.01, 0.005, 0.0025, 0.00125]
    out = {}
    for name, (p, st) in RM_STUDY_CASES.items():
        assert rm.crossing_time(st.W, p) > 2.0 / min(eps)  # stays in its hemisphere (§10.1)
        out[name] = averaging_error_study(
            rm.MODEL, p, st, eps, slow_time=2.0, variables=("k", "theta", "rho", "sigma")
        )
    return out


def _study_orders(
    variables: tuple[str, ...], label: str, guide: float, ylabel: str
) -> tuple[dict[str, float], Panel]:
    """The fitted orders [1] of the §13.6 study for ``variables``, keyed "<case>: <variable>",
    and their figure: each error against ε (``label`` formatted with the case ``name`` and the
    variable ``v``) and the slope-1 line ``guide`` × ε."""
    series: list[Series] = []
    slopes = {}
    for name, s in _rm_accuracy_study().items():
        for v in variables:
            slopes[f"{name}: {v}"] = s.slopes[v]
            series.append(
                Series(np.asarray(s.eps), s.errors[v], label.format(name=name, v=v), "line+markers")
            )
    e = np.array([0.00125, 0.02])
    series.append(Series(e, guide * e, "slope 1", "dotted"))
    return slopes, eps_panel(series, ylabel)


@claim(
    "rm-13",
    RM,
    "direction of K fixed (ρ, σ constant)",
    "(2.2): k dρ/dτ = 0, k sinρ dσ/dτ = 0 — the angular momentum keeps its direction in "
    "inertial space.",
    "docs/theory/resisting-medium.md §6, §9 item 5, §10.1",
    name="angular_momentum_keeps_its_direction",
)
def rm_13() -> Measurement:
    """ρ, σ constant: the direction of K is fixed to first order (§9 item 5).

    Returns
    -------
    Claim
        Measured: the slowest fitted order [1] of the full model's ρ, σ excursions against ε; holds
        at ≥ 0.75.
    """
    slopes, panel = _study_orders(
        ("rho", "sigma"), "{name}: max|{v} − {v}0|", 0.5, "max excursion over ετ ≤ 2 [rad]"
    )
    ratio = {
        f"{name}: {v}": (s.errors[v] / s.eps).tolist()
        for name, s in _rm_accuracy_study().items()
        for v in ("rho", "sigma")
    }
    worst = min(slopes.values())
    # Constant to first order = the full excursions are O(ε): fitted order ≥ 0.75.
    return by_order(
        worst,
        (panel,),
        "slowest fitted order of max|ρ − ρ0|, max|σ − σ0| of the full model against ε "
        "(0.02 … 0.00125, halved four times) over ετ ≤ 2",
        "constant only to first order: the full model has O(ε) excursions of ρ, σ over "
        "τ ~ 1/ε (and a tilt of the steady axis, §10.4)",
        criterion="order ≥ 0.75 (O(ε) excursions)",
        slopes=slopes,
        excursion_over_eps=ratio,
        resonances_passed={
            name: [
                (i.tau, i.label)
                for i in rm.validity(p, st, functools.partial(rm.closed_form, p, st), 2.0 / p.eps)
                if i.condition == "resonance"
            ]
            for name, (p, st) in RM_STUDY_CASES.items()
        },
    )


@claim(
    "rm-14",
    RM,
    "averaged model is first-order accurate",
    "§2: the averaged system (2.2) describes the evolution of k, ϑ to first order in ε on "
    "τ ~ 1/ε (Volosov–Morgunov averaging).",
    "docs/theory/resisting-medium.md §10.1, §13.6",
    name="averaged_system_2_2_is_first_order_accurate",
)
def rm_14() -> Measurement:
    """Averaged-vs-full accuracy O(ε) away from ϑ = π/2 (§10.1, §13.6).

    Returns
    -------
    Claim
        Measured: the slowest fitted order [1] of max |full − closed form| of k, ϑ against ε; holds
        at ≥ 0.75.
    """
    studies = _rm_accuracy_study()
    slopes, panel = _study_orders(
        ("k", "theta"), "{name}: {v}", 1.0, "max |full − closed form| over ετ ≤ 2"
    )
    worst = min(slopes.values())
    return by_order(
        worst,
        (panel,),
        "slowest fitted order of max|Δk|, max|Δϑ| (full − closed form) against ε = 0.02 … "
        "0.00125 (halved four times) over ετ ≤ 2, two media with full B, S",
        "O(ε) only for trajectories that stay in one hemisphere with |κ cos ϑ| bounded away "
        "from 0 (κ ≠ 0); through ϑ = π/2 see rm-15",
        slopes=slopes,
        errors={n: {v: s.errors[v].tolist() for v in ("k", "theta")} for n, s in studies.items()},
    )


@claim(
    "rm-15",
    RM,
    "φ fast everywhere: averaging valid through ϑ = π/2",
    "§2: k, ρ, σ, ϑ are slow and ψ, φ fast; the averaged solution is used through ϑ = π/2 "
    "(worked example, branch switch).",
    "docs/theory/resisting-medium.md §10.2, §11; correction E10; §13.7",
    name="averaging_holds_through_theta_pi_over_2",
)
def rm_15() -> Measurement:
    """φ is a fast variable everywhere (E10): through ϑ = π/2 averaging is only O(√ε) (§10.2).

    Returns
    -------
    Claim
        Measured: the fitted order [1] of the error after a passage through ϑ = π/2 against ε; the
        claim holds at ≥ 0.75.
    """
    p0 = rm.Params(eps=0.01, kappa=0.5, a=np.array([0.2, 0.1, 0.3]), b=np.diag([0.1, 0.1, 0.1]))
    eps_values = [0.02, 0.01, 0.005, 0.0025]
    worst_by_eps = []
    for eps in eps_values:
        p = p0.with_eps(eps)
        worst = 0.0
        # The jump at the passage oscillates with the phase of φ there (§10.2): take the worst
        # of six initial phases at each ε.
        for phi0 in np.linspace(0.0, 2 * np.pi, 6, endpoint=False):
            st = rm.State(1.0, 1.0, 0.0, 0.0, 2.0, float(phi0))
            tau1 = rm.crossing_time(st.W, p)
            tau = np.linspace(0.0, tau1 + 1.0 / eps, 1001)
            full = simulate(rm.MODEL, p, st, tau, "full").columns
            cf = rm.closed_form(p, st, tau)
            after = tau > tau1 + 0.5 / eps
            for v in ("k", "theta"):
                worst = max(worst, max_abs((full[v] - cf[v])[after]))
        worst_by_eps.append(worst)
    errors = np.array(worst_by_eps)
    order = fitted_order(eps_values, errors)
    bound = math.hypot(0.2, 0.1) * np.sqrt(2 * math.pi * np.array(eps_values) * 1.5 / (0.5 * 0.3))
    e = np.array(eps_values)
    series = (
        Series(e, errors, f"post-passage error (order {order:.2f})", "line+markers"),
        Series(e, bound, "stationary-phase bound |a⊥|√(2πε(1+κ)/(|κ|a3))", "dashed"),
        Series(e, errors[0] * e / eps_values[0], "slope 1", "dotted"),
    )
    panels = (eps_panel(series, "max |full − closed form| after τ1 + 0.5/ε"),)
    # The paper treats φ as fast everywhere, i.e. (2.2) first-order accurate through the
    # passage: that holds only if the fitted order stays ≥ 0.75 (cf. rm-14).
    return by_order(
        order,
        panels,
        "fitted order of the post-passage error max|Δk|, |Δϑ| (worst of 6 phases φ0) against "
        "ε = 0.02 … 0.0025, a1, a2 ≠ 0, crossing ϑ = π/2",
        "E10: Ω_φ = −kκ cosϑ/(1+κ) vanishes at ϑ = π/2 (and for κ = 0): after a passage the "
        "averaged model is only O(√ε) accurate; exact only for a φ-independent moment",
        criterion="the claim holds if order ≥ 0.75",
        # Judged as printed: the verdict is confirmed or refuted, never qualified.
        qualified=False,
        errors=errors.tolist(),
        eps=eps_values,
        error_over_sqrt_eps=(errors / np.sqrt(eps_values)).tolist(),
        stationary_phase_bound=bound.tolist(),
    )


@claim(
    "rm-16",
    RM,
    "full model: ϑ → 0 is a steady O(ε) tilt",
    "§2: for a3 > 0 the symmetry axis tends to the angular momentum (ϑ → 0).",
    "docs/theory/resisting-medium.md §9 item 1, §10.4; §13.8",
    name="symmetry_axis_tends_to_angular_momentum_in_full_model",
)
def rm_16() -> Measurement:
    """The final state of the full model: ϑ → O(ε), a steady tilt (§10.4).

    Returns
    -------
    Claim
        Measured: ϑ of the full model at τ = 600 [rad]; holds at ≤ 3ε, qualified if it stays above
        1e-6 rad.
    """
    p = medium(0.3, 0.3, 0.1, 0.2, a3=0.4, eps=0.05, a12=(0.05, 0.03))
    st = state(1.0, 2.4)
    tau = np.linspace(0.0, 600.0, 601)
    full = simulate(
        rm.MODEL, p, st, tau, "full", **tolerances({"rtol": 1e-10, "atol": 1e-12})
    ).columns
    k_inf = rm.predicted_limits(p, st)["k"]
    # §10.4 with diagonal B, S: m⊥ = (a1, a2).
    tilt = p.eps * (1 + p.kappa) * math.hypot(0.05, 0.03) / (abs(p.kappa) * k_inf**2)
    theta_end = float(full["theta"][-1])
    panels = (
        time_panel(
            (Series(tau, full["theta"], "full model ϑ"),),
            "ϑ [rad]",
            "a3 > 0, a1, a2 ≠ 0, ε = 0.05",
            yscale="log",
            hlines=((tilt, "§10.4 tilt ε(1+κ)|m⊥|/(|κ|k∞²)"),),
        ),
    )
    rel = abs(theta_end / tilt - 1.0)
    # ϑ → 0 in the qualified sense: the final ϑ is O(ε) (≤ 3ε). The qualification is measured:
    # the axis stays tilted (ϑ_end far above the integration error, 1e-6 rad). Whether the tilt
    # is the §10.4 value (first order: within 5 % = O(ε) relative at ε = 0.05) checks §10.4.
    holds = theta_end <= 3 * p.eps
    qualified = theta_end > 1e-6
    return judged(
        holds,
        panels,
        theta_end,
        "rad",
        "ϑ of the full model at τ = 600 (a3 > 0, a1 = 0.05, a2 = 0.03, ε = 0.05)",
        3 * p.eps,
        "ϑ_end ≤ 3ε (axis within O(ε) of K); qualification if ϑ_end equals the §10.4 tilt "
        "within 5 %",
        "in the full model the final state is a steady rotation whose axis is tilted from K by "
        "O(ε) when a1, a2 or off-diagonal B, S entries are present: 'ϑ → 0' means ϑ → O(ε)",
        qualified=qualified,
        theory_consistent=rel <= 0.05,
        tilt_formula=tilt,
        relative_difference_from_tilt=rel,
    )
