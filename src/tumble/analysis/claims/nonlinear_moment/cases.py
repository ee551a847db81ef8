"""The nonlinear moment's cases shared by its claims: the orbits of theory §13, the
perturbation of §9 and the perturbed full runs (V. M. Serov 1991;
docs/theory/nonlinear-moment.md)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from tumble.analysis.claims.base import Measurement, Panel, Series
from tumble.analysis.claims.common import (
    Tolerances,
    cache_per_scale,
    quiet,
    threshold_panel,
    tolerances,
    within,
)
from tumble.integrate import simulate
from tumble.models import nonlinear_moment as nm

NM = "nonlinear_moment"

NM_CASES = {
    "double well b < 0 (case 1)": (
        nm.Params(mu=0.8, a=-1.0, b=-0.3),
        nm.State(1.0, 0.3, 0.2, -0.1, 0.4, 0.6),
    ),
    "b > 0 (case 1)": (nm.Params(mu=1.3, a=-2.0, b=0.4), nm.State(0.7, -0.5, 0.0, 0.3, 1.1, -0.4)),
    "overturning a > 0 (case 2)": (
        nm.Params(mu=0.5, a=0.8, b=-1.5),
        nm.State(2.0, 0.2, 0.0, 0.0, -0.3, 0.2),
    ),
    "heavy top b = 0, a > 0": (
        nm.Params(mu=0.6, a=1.0, b=0.0),
        nm.State(1.0, 0.2, 0.0, 0.0, 2.0, 1.5),
    ),
    "large swing (case 2)": (
        nm.Params(mu=0.8, a=-1.0, b=-0.3),
        nm.State(2.6, 0.0, 0.0, 0.0, 0.4, 0.6),
    ),
}
"""Theory §13: both root cases, a and b of both signs, a double well, b = 0 with a > 0 (the
alternative anchoring of §4.3), mid-swing starts (θ′0 ≠ 0, which exercises γ0 and its sign)."""

NM_PERTURBATION = {"d": 0.5, "nu": 0.2, "pressure": nm.Pressure("exp")}
"""The perturbation of §9 with pitch and roll damping and Q = e^τ (examples/nm_damped_exp)."""

NM_EPS = [0.1, 0.05, 0.02, 0.01, 0.005]


def perturbed(p: nm.Params, eps: float, **kw: Any) -> nm.Params:
    """The orbit's parameters ``p`` under the perturbation :data:`NM_PERTURBATION` at ``eps``
    [1], with ``kw`` replacing any of the perturbation's fields."""
    args: dict[str, Any] = {"mu": p.mu, "a": p.a, "b": p.b, "eps": eps, **NM_PERTURBATION}
    args.update(kw)
    return nm.Params(**args)


def case_ticks(names: Iterable[str]) -> tuple[tuple[float, str], ...]:
    """The x ticks of a figure of one bar or marker per orbit of :data:`NM_CASES`: each name
    without its parenthesis ("(case 1)"), at 0, 1, …"""
    return tuple((float(i), n.split(" (")[0]) for i, n in enumerate(names))


def per_case_within(
    value: float,
    threshold: float,
    series: Iterable[Series],
    ticks: tuple[tuple[float, str], ...],
    ylabel: str,
    units: str,
    what: str,
    qualification: str = "",
    **details: Any,
) -> Measurement:
    """:func:`~tumble.analysis.claims.common.within` for a check made case by case (an orbit or
    an average each): its figure is one bar or marker per case, at ``ticks``, on a logarithmic
    axis with the threshold [``units``]."""
    panel = threshold_panel(series, threshold, ylabel=ylabel, xticks=ticks)
    return within(value, threshold, (panel,), units, what, qualification, **details)


UNPERTURBED: Tolerances = {"rtol": 1e-13, "atol": 1e-14}
"""Tolerances of the unperturbed full runs that the closed forms are checked against."""

SWING: Tolerances = {"rtol": 1e-11, "atol": 1e-13}
"""Tolerances of the perturbed runs whose averaging error the claims measure (far below it)."""


@cache_per_scale
def full_run(name: str, eps: float) -> Any:
    """The full run of the orbit ``name`` of :data:`NM_CASES` under the perturbation of §9 at
    ``eps`` [1], over εt ≤ 1 (201 samples, dense), at the tolerances :data:`SWING`."""
    p0, st = NM_CASES[name]
    p = perturbed(p0, eps)
    tau = np.linspace(0.0, 1.0 / eps, 201)
    # Dense: the figure draws θ(t) between the samples (every swing).
    return quiet(
        simulate,
        nm.MODEL,
        p,
        st,
        tau,
        "full",
        **tolerances(SWING),
        dense=True,
    )


def swing(name: str, eps: float, **options: Any) -> tuple[Any, Any, dict[str, Any]]:
    """The full run of the orbit ``name`` at ``eps`` [1] (:func:`full_run`), the averaged run
    over the same samples (tolerances :data:`SWING`; ``options`` for
    :func:`~tumble.integrate.simulate`, e.g. its ``averaging``), and the discrepancy of the
    averaged θmax, θmin [rad] from the full run's extrema."""
    p0, st = NM_CASES[name]
    p = perturbed(p0, eps)
    full = full_run(name, eps)
    avg = quiet(simulate, nm.MODEL, p, st, full.tau, "averaged", **tolerances(SWING), **options)
    return full, avg, nm.envelope_discrepancy(nm.extrema(full, p), avg)


def swing_panel(full: Any, avg: Any, title: str) -> Panel:
    """θ(t) of a full run [deg] with the averaged θmax, θmin of the same run."""
    dense = np.linspace(0.0, float(full.tau[-1]), 4001)  # the dense output resolves each swing
    return Panel(
        series=(
            Series(dense, np.degrees(full.slow(dense)["theta"]), "full θ"),
            Series(avg.tau, np.degrees(avg.columns["theta_max"]), "averaged θmax"),
            Series(avg.tau, np.degrees(avg.columns["theta_min"]), "averaged θmin"),
        ),
        xlabel="t",
        ylabel="θ [deg]",
        title=title,
    )
