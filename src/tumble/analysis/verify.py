"""Accuracy with every run: averaged against full at ε, ε/2, ε/4 over one slow horizon.

First-order averaging promises |full − averaged| = O(ε) on slow times εt = O(1) (the theory
pages docs/theory/resisting-medium.md §10, rotating-field.md §12, nonlinear-moment.md §7).
:func:`verify` measures it: the scenario runs again with ε halved and quartered, over the same slow
horizon ε·t_end (so the fast time grows as 1/ε), the error of each slow variable is its maximum
over the run, and the order is the least-squares slope of log error against log ε. The verdict
reads the orders together with the model's validity checks (the regions where the papers'
conclusions fail: ϑ = π/2, resonances, separatrices), e.g. "first-order accurate", "degraded: slope
0.5 near ϑ = π/2 (τ ≈ 53.2)" or "invalid: the averaged run stops at the separatrix (t ≈ 210)".

For a scenario of averaging order 2 the orders of both are fitted, per slow variable, and
"second-order accurate" needs a slope of at least 1.75. The parameters scale
with ε along the scenario's family (``[run] verify_scaling``; by default ε alone, or the
model's physical family: docs/second-order-averaging.md).
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from tumble._progress import stage
from tumble._typing import FloatArray
from tumble.analysis.compare import angle_difference, fitted_order
from tumble.analysis.run import RunRequest, _merge_issues, unbridged
from tumble.errors import IntegrationError, ParameterError, TumbleError, TumbleWarning
from tumble.integrate import Trajectory, simulate
from tumble.models import AnyModel
from tumble.models.base import family_params, scaling_family

__all__ = [
    "DEGRADED_ORDER",
    "FIRST_ORDER",
    "SECOND_ORDER",
    "VERIFY_FACTORS",
    "VerifyResult",
    "slow_errors",
    "verify",
]

VERIFY_FACTORS = (1.0, 0.5, 0.25)
"""ε of the three runs, as fractions of the scenario's ε (ε, ε/2, ε/4)."""

FIRST_ORDER = 0.75
"""A fitted order at or above this is first order: the band ±0.25 of the three paper models'
error studies (docs/accuracy.md: three points of an O(ε) error with an O(ε²) term and the
phase of the O(ε) oscillation at the sampled maxima scatter by up to ±0.2)."""

SECOND_ORDER = 1.75
"""A fitted order at or above this is second order (the same band, 2 − 0.25), for runs of
averaging order 2."""

DEGRADED_ORDER = 0.25
"""Below this order the error does not shrink with ε at all: the averaged model is invalid
on this horizon (between the two, e.g. the O(√ε) across ϑ = π/2 of
docs/theory/resisting-medium.md §10.2, it is degraded)."""

FLOOR = 100.0
"""An error below FLOOR·rtol times the variable's scale at every ε is at the integration
tolerance: the averaged model is exact there (e.g. L_ξ under a torque fixed in inertial
space) and no order can be fitted."""


@dataclass(frozen=True)
class VerifyResult:
    """Errors, orders and the verdict of :func:`verify`.

    Attributes
    ----------
    model : str
        The model's name.
    eps : ndarray, shape (3,)
        The ε of the runs [1].
    horizon : float
        The common slow horizon ε·t_end [1].
    time_name : str
        The model's time variable ("tau" or "t").
    variables : tuple of str
        The slow variables compared.
    errors : dict
        Variable → max |full − averaged| at each ε (NaN where the averaged run failed).
    curves : list of dict
        Per ε: variable → (slow times εt, |full − averaged|) for the figure.
    orders : dict
        Variable → fitted order, or None when the errors are at the tolerance floor or a run
        failed.
    issues : list of list of dict
        Per ε: the validity issues the averaged run entered (condition, tau, message, label).
    failures : list of str or None
        Per ε: why the averaged run stopped, if it did.
    status : {"second-order", "first-order", "degraded", "invalid"}
    verdict : str
        One line for the user, on the scenario's own order of averaging.
    by_order : dict
        Averaging order → variable → (max errors at each ε, fitted order or None): order 1,
        and order 2 for a scenario of that order.
    variable_verdicts : dict
        Variable → its verdict on the scenario's order ("second-order accurate", …).
    family : dict
        How the parameters scaled with ε: parameter → exponent of ε/ε₀ (``eps`` 1 and
        nothing else: ε alone).
    """

    model: str
    eps: FloatArray
    horizon: float
    time_name: str
    variables: tuple[str, ...]
    errors: dict[str, FloatArray]
    curves: list[dict[str, tuple[FloatArray, FloatArray]]]
    orders: dict[str, float | None]
    issues: list[list[dict[str, Any]]] = field(default_factory=list)
    failures: list[str | None] = field(default_factory=list)
    status: str = "first-order"
    verdict: str = "first-order accurate"
    by_order: dict[int, dict[str, tuple[FloatArray, float | None]]] = field(default_factory=dict)
    variable_verdicts: dict[str, str] = field(default_factory=dict)
    family: dict[str, float] = field(default_factory=lambda: {"eps": 1.0})

    def per_variable(self) -> dict[str, dict[str, Any]]:
        """Per slow variable: ``slope_order1``, ``slope_order2`` (fitted orders; None where
        not measured — order 2 is measured for a scenario of that order — or at the tolerance
        floor) and ``error_order1``, ``error_order2`` (the max error at the scenario's own ε),
        and its verdict."""
        out: dict[str, dict[str, Any]] = {}
        for v in self.variables:
            entry: dict[str, Any] = {}
            for order in (1, 2):
                errors, slope = self.by_order.get(order, {}).get(v, (np.array([math.nan]), None))
                first = float(errors[0])
                entry[f"slope_order{order}"] = slope
                entry[f"error_order{order}"] = first if math.isfinite(first) else None
            entry["verdict"] = self.variable_verdicts.get(v, "")
            out[v] = entry
        return out

    def summary(self) -> dict[str, Any]:
        """Plain values for ``verify.json`` and ``summary.json``."""
        return {
            "verdict": self.verdict,
            "status": self.status,
            "eps": self.eps.tolist(),
            "scaling": self.family,
            "slow_horizon": self.horizon,
            "variables": list(self.variables),
            "max_errors": {v: _floats(e) for v, e in self.errors.items()},
            "orders": self.orders,
            "issues": [
                [{k: i[k] for k in ("condition", "tau", "label", "message")} for i in run]
                for run in self.issues
            ],
            "failures": self.failures,
            "per_variable": self.per_variable(),
        }


def _floats(values: FloatArray) -> list[float | None]:
    return [None if not math.isfinite(v) else float(v) for v in np.asarray(values)]


def slow_errors(
    model: AnyModel, p: Any, full: Trajectory, averaged: Trajectory
) -> dict[str, tuple[FloatArray, FloatArray]]:
    """|full − averaged| of each slow variable over the run: the model's own measure
    (``Averaged.errors``) or its ``Averaged.compare`` columns compared at the sample times,
    angles modulo 2π.

    Returns
    -------
    dict
        Variable → (times [model time], absolute errors).
    """
    avg = model.averaged
    if avg is None:
        raise ParameterError(f"{model.name} has no averaged method to verify")
    if avg.errors is not None:
        return dict(avg.errors(p, full, averaged))
    if not avg.compare:
        raise ParameterError(f"{model.name} has no slow variables to verify")
    angles = {c.name for c in avg.columns(p) if c.angle}
    out = {}
    for v in avg.compare:
        a, b = full.columns[v], averaged.columns[v]
        d = angle_difference(a, b) if v in angles else a - b
        out[v] = (full.tau, np.abs(d))
    return out


_AT_TIME = re.compile(r"at [tτ] = ([-+0-9.eE]+)")


def _failure_time(message: str) -> float | None:
    m = _AT_TIME.search(message)
    return float(m.group(1)) if m else None


_LABELS = {
    "phi_not_fast": "ϑ ≈ π/2 (φ no longer fast)",
    "spin_not_fast": "k → 0 (spin no longer fast)",
    "through_k_zero": "k = 0",
    "separatrix": "the separatrix",
    "near_separatrix": "a separatrix",
    "momentum_small": "L → 0",
    "co_rotation": "co-rotation with the field",
    "eps_not_small": "a large ε",
    "not_fast": "slow fast phases",
}
"""Words for the validity conditions of the models, where an issue carries no label."""


def _phrase(issue: dict[str, Any], time_symbol: str) -> str:
    condition = issue["condition"]
    label = issue.get("label") or _LABELS.get(condition, condition.replace("_", " "))
    return f"{label} ({time_symbol} ≈ {issue['tau']:.4g})"


def _blamed(
    issues: list[dict[str, Any]],
    orders: dict[str, float | None],
    curves: list[dict[str, tuple[FloatArray, FloatArray]]],
    eps0: float,
) -> list[dict[str, Any]]:
    """``issues`` with the one to blame first: the last one entered before the slowest-
    converging variable reaches its largest error in the smallest-ε run (where a loss of
    order shows most), or the first one if that error comes before all of them."""
    fitted = {v: o for v, o in orders.items() if o is not None}
    last = next((c for c in reversed(curves) if c), None)
    if not issues or not fitted or last is None:
        return issues
    worst = min(fitted, key=lambda v: fitted[v])
    if worst not in last:
        return issues
    s, d = last[worst]
    peak = float(s[int(np.argmax(d))])
    before = [i for i in issues if eps0 * float(i["tau"]) <= peak]
    if not before:
        return issues
    culprit = max(before, key=lambda i: float(i["tau"]))
    return [culprit, *(i for i in issues if i is not culprit)]


def _variable_verdict(order: float | None, target: int) -> str:
    """One slow variable's verdict from its fitted order."""
    if order is None:
        return "at the integration tolerance"
    if target == 2 and order >= SECOND_ORDER:
        return "second-order accurate"
    if order >= FIRST_ORDER:
        return "first-order accurate"
    return "degraded" if order >= DEGRADED_ORDER else "invalid"


def _verdict(
    orders: dict[str, float | None],
    issues: list[dict[str, Any]],
    failures: list[str | None],
    eps: FloatArray,
    time_symbol: str,
    target: int = 1,
) -> tuple[str, str]:
    for e, failure in zip(eps, failures, strict=True):
        if failure is not None:
            t = _failure_time(failure)
            where = f" at {time_symbol} ≈ {t:.4g}" if t is not None else ""
            reason = failure.split(": ", 1)[-1].split(";")[0]
            return "invalid", f"invalid: the averaged run at ε = {e:.4g} stops{where}: {reason}"
    fitted = {v: o for v, o in orders.items() if o is not None}
    name = "second" if target == 2 else "first"
    if not fitted:
        return f"{name}-order", f"{name}-order accurate (every error at the integration tolerance)"
    worst = min(fitted, key=lambda v: fitted[v])
    order = fitted[worst]
    issue = issues[0] if issues else None
    if target == 2 and order >= SECOND_ORDER:
        verdict = f"second-order accurate (slowest order {order:.2f}, in {worst})"
        if issue is not None:
            verdict += f"; passes {_phrase(issue, time_symbol)} without losing order"
        return "second-order", verdict
    if order >= FIRST_ORDER:
        if target == 2:
            verdict = f"first-order only: slope {order:.2f} in {worst} (averaging of order 2)"
            if issue is not None:
                verdict += f" near {_phrase(issue, time_symbol)}"
            return "first-order", verdict
        verdict = f"first-order accurate (slowest order {order:.2f}, in {worst})"
        if issue is not None:
            verdict += f"; passes {_phrase(issue, time_symbol)} without losing order"
        return "first-order", verdict
    status = "degraded" if order >= DEGRADED_ORDER else "invalid"
    if status == "invalid":
        verdict = f"invalid: the error of {worst} does not shrink with ε (slope {order:.2f})"
    else:
        verdict = f"degraded: slope {order:.2f} in {worst}"
    if issue is not None:
        verdict += f" near {_phrase(issue, time_symbol)}"
    return status, verdict


EXACT_RTOL = 1e-6
"""An unperturbed closed form agrees with the full integration when every column is within
this of it, relative to max(1, |column|): far above the integration error at the default
tolerance (rtol 1e-10 over thousands of periods), far below any error of a wrong formula."""


def _full(request: RunRequest, p: Any, tau: FloatArray) -> Trajectory:
    """The full run of ``request`` with parameters ``p``, at its tolerances and integrator."""
    return simulate(
        request.model,
        p,
        request.initial,
        tau,
        "full",
        rtol=request.rtol,
        atol=request.atol,
        integrator=request.integrator,
        max_steps=request.max_steps,
    )


def _verify_closed_form(request: RunRequest) -> VerifyResult:
    """ε = 0: the exact unperturbed motion in closed form against the full integration."""
    model, p, st = request.model, request.params, request.initial
    model.check(p, "closed_form")
    tau = np.asarray(request.tau, dtype=float)
    full = _full(request, p, tau)
    closed = simulate(model, p, st, tau, "closed_form")
    shared = [c for c in model.columns(p, "closed_form") if c.name in full.columns]
    curves, errors, worst = {}, {}, 0.0
    for c in shared:
        a, b = full.columns[c.name], closed.columns[c.name]
        d = np.abs(angle_difference(a, b) if c.angle else a - b)
        curves[c.name] = (tau, d)
        errors[c.name] = np.array([float(np.max(d))])
        worst = max(worst, float(np.max(d)) / max(1.0, float(np.max(np.abs(a)))))
    detail = ", ".join(f"{v} {e[0]:.2e}" for v, e in errors.items())
    if worst <= EXACT_RTOL:
        status = "exact"
        verdict = f"exact: unperturbed (ε = 0), closed form = full integration to {detail}"
    else:
        status = "invalid"
        verdict = f"invalid: the closed form departs from the full integration ({detail})"
    orders: dict[str, float | None] = dict.fromkeys(errors)
    return VerifyResult(
        model.name,
        np.array([0.0]),
        float(tau[-1]),
        model.time.name,
        tuple(errors),
        errors,
        [curves],
        orders,
        [[]],
        [None],
        status,
        verdict,
    )


def verify(request: RunRequest, factors: Sequence[float] = VERIFY_FACTORS) -> VerifyResult:
    """Run full and averaged at ε·factors over the same slow horizon; errors, orders, verdict.

    Parameters
    ----------
    request : RunRequest
        The scenario's run; its parameters need ``eps > 0`` and ``with_eps``. Its sample
        times are stretched by 1/factor (same number of samples, same slow times εt).
    factors : sequence of float
        ε of the runs as fractions of the scenario's ε, largest first.

    Returns
    -------
    VerifyResult

    Raises
    ------
    ParameterError
        If the model has no averaged method or the scenario has ε = 0.
    """
    model, p = request.model, request.params
    eps0 = float(getattr(p, "eps", 0.0))
    if eps0 == 0.0 and "closed_form" in model.methods:
        return _verify_closed_form(request)
    if "averaged" not in model.methods:
        raise ParameterError(f"{model.name} has no averaged method to verify")
    if not eps0 > 0.0 or not hasattr(p, "with_eps"):
        raise ParameterError(
            "parameters.eps = 0: verify compares the averaged with the full model, which "
            "needs a perturbation (eps > 0)"
        )
    model.check(p, "averaged")
    family = scaling_family(p, request.family)
    eps = eps0 * np.asarray(factors, dtype=float)
    symbol = {"tau": "τ"}.get(model.time.name, model.time.name)
    target = request.averaging.order
    assert model.averaged is not None
    # Order 1 always (it is cheap); order 2 where the scenario asks for it (its rates are
    # Python on a torus grid: seconds to tens of seconds a run).
    measured = sorted({1, target})
    runs = [_one_epsilon(request, family, float(f), measured) for f in factors]
    fits = {order: _fit(request, eps, [r.curves.get(order, {}) for r in runs], runs)
            for order in measured}  # fmt: skip
    curves = [r.curves.get(target, {}) for r in runs]
    issues = [r.issues for r in runs]
    failures = [r.failures.get(target) for r in runs]
    errors = {v: e for v, (e, _) in fits[target].items()}
    orders = {v: o for v, (_, o) in fits[target].items()}
    # The scenario's own run (the first) says where its averaged trajectory goes; the others
    # follow the same slow path.
    seen = next((run for run in issues if run), [])
    status, verdict = _verdict(
        orders, _blamed(seen, orders, curves, eps0), failures, eps, symbol, target
    )
    return VerifyResult(
        model.name,
        eps,
        eps0 * float(request.tau[-1]),
        model.time.name,
        tuple(errors),
        errors,
        curves,
        orders,
        issues,
        failures,
        status,
        verdict,
        fits,
        {v: _variable_verdict(o, target) for v, o in orders.items()},
        family,
    )


def _fit(
    request: RunRequest,
    eps: FloatArray,
    curves: list[dict[str, tuple[FloatArray, FloatArray]]],
    runs: list[_Run],
) -> dict[str, tuple[FloatArray, float | None]]:
    """Per variable: the max error at each ε and the fitted order (None at the tolerance
    floor or where a run failed)."""
    variables = list(dict.fromkeys(v for c in curves for v in c))
    scales: dict[str, float] = {}
    for r in runs:
        for v, scale in r.scales.items():
            scales[v] = max(scales.get(v, 0.0), scale)
    out: dict[str, tuple[FloatArray, float | None]] = {}
    for v in variables:
        err = np.array(
            [float(np.max(c[v][1])) if v in c and c[v][1].size else math.nan for c in curves]
        )
        floor = FLOOR * request.rtol * max(scales.get(v, 1.0), 1.0)
        if not np.all(np.isfinite(err)) or np.all(err <= floor):
            out[v] = (err, None)
        else:
            out[v] = (err, fitted_order(eps, np.maximum(err, 1e-300)))
    return out


@dataclass(frozen=True)
class _Run:
    """Full against averaged at one ε, for each order of averaging measured: the error curves
    (slow time εt, |error|), why an averaged run stopped (None: it did not); the validity
    issues of the scenario's averaged run, and the size of each compared variable in the full
    run."""

    curves: dict[int, dict[str, tuple[FloatArray, FloatArray]]]
    issues: list[dict[str, Any]]
    failures: dict[int, str | None]
    scales: dict[str, float]


def _one_epsilon(
    request: RunRequest, family: dict[str, float], factor: float, orders: Sequence[int]
) -> _Run:
    """The averaged runs at ε₀·factor along ``family``, first: where they all stop, the
    verdict needs no full run."""
    model, st = request.model, request.initial
    e = float(request.params.eps) * factor
    pe = family_params(request.params, factor, family)
    tau = np.asarray(request.tau, dtype=float) / factor
    averaged: dict[int, Trajectory] = {}
    failures: dict[int, str | None] = {}
    for order in orders:
        options = replace(request.averaging, order=order)
        try:
            with warnings.catch_warnings(), stage(f"ε = {e:.3g}: averaged (order {order})"):
                warnings.simplefilter("ignore", TumbleWarning)
                averaged[order] = simulate(model, pe, st, tau, "averaged", rtol=request.rtol,
                                           atol=request.atol, averaging=options)  # fmt: skip
            failures[order] = None
        except IntegrationError as exc:
            failures[order] = str(exc)
        except TumbleError as exc:  # e.g. a state the second-order map cannot take
            if order == request.averaging.order:
                raise
            failures[order] = str(exc)
    if not averaged:
        return _Run({}, [], failures, {})
    with stage(f"ε = {e:.3g}: full"):
        full = _full(request, pe, tau)
    curves: dict[int, dict[str, tuple[FloatArray, FloatArray]]] = {}
    scales: dict[str, float] = {}
    for order, avg in averaged.items():
        errs = slow_errors(model, pe, full, avg)
        scales |= {v: float(np.max(np.abs(full.columns[v]))) for v in errs if v in full.columns}
        curves[order] = {v: (e * t, d) for v, (t, d) in errs.items()}
    own = averaged.get(request.averaging.order, next(iter(averaged.values())))
    found = (
        unbridged(model.validity.check(pe, st, own.slow, tau[-1]), own.legs)
        if model.validity
        else []
    )
    return _Run(curves, _merge_issues({"averaged": found}), failures, scales)
