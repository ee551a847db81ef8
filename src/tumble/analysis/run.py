"""Run a scenario's methods, compare them, and collect the warnings and predicted limits."""

from __future__ import annotations

import itertools
import json
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from tumble._progress import stage
from tumble._typing import ArrayLike, FloatArray
from tumble.analysis.compare import max_differences
from tumble.errors import TumbleError, warn
from tumble.integrate import DEFAULT_ATOL, DEFAULT_RTOL, MAX_STEPS, Trajectory, simulate
from tumble.models import AnyModel
from tumble.models.base import AveragingOptions, Column, Json, Report, ValidityIssue
from tumble.models.schema import Scaling

__all__ = ["RunRequest", "RunResult", "on_tau", "run", "si_dataset", "si_time", "to_dataset"]


@dataclass(frozen=True)
class RunRequest:
    """Everything a run needs, as plain values (built from a scenario by :mod:`tumble.io`).

    Attributes
    ----------
    model : Model
        The model.
    params, initial : model Params and State
        Normalized parameters and initial state.
    tau : ndarray
        Sample times [model time unit].
    methods : tuple of str
        Methods to run, in order.
    rtol, atol : float
        Integration tolerances.
    scaling : object, optional
        Physical scaling (for physical-units scenarios), kept for the outputs.
    verify : bool
        Also measure the averaging error at ε, ε/2, ε/4 (``[run] verify``).
    integrator : {"auto", "numba", "scipy"}
        How the full equations are integrated (``[run] integrator``).
    averaging : AveragingOptions
        How the averaged equations are formed and started (``[run] averaging``,
        ``averaged_form``, ``averaged_init``).
    max_steps : int
        Step budget of a full run (``[run] max_steps``).
    family : dict, optional
        How ``tumble verify`` scales the parameters with ε (``[run] verify_scaling``):
        parameter → exponent of ε/ε₀; None for the model's default
        (:func:`tumble.models.base.scaling_family`).
    """

    model: AnyModel
    params: Any
    initial: Any
    tau: FloatArray
    methods: tuple[str, ...]
    rtol: float = DEFAULT_RTOL
    atol: float = DEFAULT_ATOL
    scaling: Any = None
    verify: bool = False
    integrator: str = "auto"
    averaging: AveragingOptions = field(default_factory=AveragingOptions)
    max_steps: int = MAX_STEPS
    family: Mapping[str, float] | None = None


@dataclass(frozen=True)
class RunResult:
    """Datasets of every method, their differences, warnings and the predicted limits.

    ``diagnostics`` holds, per averaged method, the model's extra per-sample quantities (e.g.
    the fast frequencies of the rotating-field model); ``report`` the model's extra tables and
    summary keys (e.g. the extrema of the nonlinear-moment model); ``verification`` the
    :class:`~tumble.analysis.verify.VerifyResult` of ``[run] verify``, when asked for;
    ``ended_early`` says which method stopped before the end, where and why (its dataset then
    holds what it computed until then, and the methods after it did not run), None when every
    method ran to the end.
    """

    request: RunRequest
    datasets: dict[str, xr.Dataset]
    trajectories: dict[str, Trajectory]
    differences: dict[str, dict[str, float]]
    issues: list[dict[str, Any]] = field(default_factory=list)
    limits: Mapping[str, Json] = field(default_factory=dict)
    diagnostics: dict[str, xr.Dataset] = field(default_factory=dict)
    report: Report = field(default_factory=Report)
    verification: Any = None
    ended_early: Mapping[str, Json] | None = None


def _columns_dataset(
    columns: tuple[Column, ...],
    values: dict[str, FloatArray],
    tau: FloatArray,
    time_name: str,
    time_units: str = "1",
) -> xr.Dataset:
    """Columns as a Dataset on ``tau``, with units, long names and equations in ``attrs``
    (a declared column the run did not produce, such as the mean variables of a run of order
    1, is left out)."""
    data_vars = {
        col.name: on_tau(
            values[col.name],
            {
                "units": col.units,
                "long_name": col.long_name,
                "equation": col.equation,
                "angle": int(col.angle),
            },
        )
        for col in columns
        if col.name in values
    }
    # The coordinate is "tau" for every model; its attrs carry the paper's own time name.
    symbol = {"tau": "τ"}.get(time_name, time_name)
    time_attrs = {"units": time_units, "long_name": f"time {symbol}", "name": time_name}
    return xr.Dataset(data_vars, coords={"tau": on_tau(tau, time_attrs)})


def on_tau(values: ArrayLike, attrs: dict[str, Any]) -> xr.Variable:
    """A column on the time axis, as an xarray Variable of a float array made here. (Built
    directly: xarray's general constructor asks whether the data is a dask array, which
    imports dask.array, 0.4 s of a run that never uses it.)"""
    data = np.array(values, dtype=float)
    return xr.Variable(("tau",), data, attrs, fastpath=True)


DAY = 86400.0
"""Seconds in a day: a physical run longer than two days is shown in days."""


def si_time(scaling: Scaling, tau: FloatArray, t_end: float) -> tuple[FloatArray, str]:
    """Model times ``tau`` as physical times, in seconds, or in days for a run whose end
    ``t_end`` (model time) lies beyond two days; and that unit ("s" or "d")."""
    end = float(np.asarray(scaling.time_from_tau(np.array([t_end])))[0])
    t = np.asarray(scaling.time_from_tau(np.asarray(tau, dtype=float)), dtype=float)
    return (t / DAY, "d") if end > 2.0 * DAY else (t, "s")


def si_dataset(ds: xr.Dataset, scaling: Scaling) -> xr.Dataset:
    """A run's Dataset in SI for figures and tables (:meth:`Scaling.si`): the time in seconds
    or days, each convertible column in its SI unit under its own name, the others (angles,
    k², q) unchanged. The files keep the normalised columns with the SI ones beside them."""
    tau = ds["tau"].values
    t, unit = si_time(scaling, tau, float(tau[-1]))
    data = {}
    for name, da in ds.data_vars.items():
        conv = scaling.si(str(name))
        if conv is None:
            data[name] = on_tau(da.values, dict(da.attrs))
        else:
            factor, si_unit, _ = conv
            data[name] = on_tau(da.values * factor, {**da.attrs, "units": si_unit})
    coord = on_tau(t, {"units": unit, "long_name": "time t", "name": "t"})
    return xr.Dataset(data, coords={"tau": coord}, attrs=ds.attrs)


def to_dataset(model: AnyModel, traj: Trajectory, p: Any) -> xr.Dataset:
    """Trajectory as an ``xarray.Dataset`` with units, long names and equations in ``attrs``."""
    ds = _columns_dataset(
        model.columns(p, traj.method), traj.columns, traj.tau, model.time.name, model.time.units
    )
    ds.attrs.update(
        model=model.name,
        method=traj.method,
        form=traj.form,
        wall_time_s=traj.wall_time,
        nfev=traj.nfev,
        integrator=traj.integrator or "closed form",
    )
    if traj.legs:  # a hybrid or stepped run's legs (kind, start, end), as text: a NetCDF attribute
        ds.attrs["legs"] = json.dumps([list(leg) for leg in traj.legs])
    return ds


def issue_in_si(issue: dict[str, Any], scaling: Scaling, t_end: float) -> dict[str, Any]:
    """A merged warning of a physical run (:func:`_merge_issues`) with its time in SI: the
    message's "t = …" or "τ ≈ …" at the issue's time written in seconds or in days as the run
    shows its time (:func:`si_time`), and ``t_s`` [s] beside ``tau`` (the model's time). The
    numerics keep the model's time; this converts at the edge, for the user."""
    tau = float(issue["tau"])
    t_s = float(np.asarray(scaling.time_from_tau(np.array([tau])))[0])
    t, unit = si_time(scaling, np.array([tau]), t_end)
    pattern = rf"\b[tτ] ([=≈]) {re.escape(f'{tau:.6g}')}(?![\d.e])"
    text = re.sub(pattern, lambda m: f"t {m.group(1)} {float(t[0]):.6g} {unit}", issue["message"])
    return {**issue, "message": text, "t_s": t_s}


def unbridged(
    issues: list[ValidityIssue], legs: tuple[tuple[str, float, float], ...]
) -> list[ValidityIssue]:
    """``issues`` less those that begin inside an asymptotic leg of the run (kind
    "asymptotic"): the band where averaging fails that the step's theory bridges, its inner
    solution in the run's columns."""
    spans = [(a, b) for kind, a, b in legs if kind == "asymptotic"]
    return [i for i in issues if not any(a <= i.tau <= b for a, b in spans)]


def _merge_issues(found: dict[str, list[ValidityIssue]]) -> list[dict[str, Any]]:
    """One entry per condition: its earliest time, and the methods that entered it."""
    merged: dict[str, dict[str, Any]] = {}
    for method, issues in found.items():
        for issue in issues:
            entry = merged.get(issue.condition)
            if entry is None or issue.tau < entry["tau"]:
                methods = entry["methods"] if entry else []
                merged[issue.condition] = {
                    "condition": issue.condition,
                    "tau": issue.tau,
                    "message": issue.message,
                    "label": issue.label,
                    "methods": methods,
                }
            merged[issue.condition]["methods"].append(method)
    return sorted(merged.values(), key=lambda e: e["tau"])


def run(request: RunRequest, precomputed: Mapping[str, Trajectory] | None = None) -> RunResult:
    """Run every requested method and compare them.

    Emits one :class:`~tumble.errors.TumbleWarning` per validity condition that an averaged or
    closed-form trajectory enters (the same list goes to ``RunResult.issues``).

    Parameters
    ----------
    request : RunRequest
    precomputed : mapping, optional
        Method → Trajectory of this request already computed (e.g. by
        :func:`~tumble.integrate.simulate_batch` for many points at once); those methods are
        not run again.

    Returns
    -------
    RunResult

    Raises
    ------
    TumbleError
        A method that failed; where it kept what it computed before it stopped (a full run on
        the compiled integrator), the error's ``partial`` is this function's
        :class:`RunResult` of everything run until then, its ``ended_early`` set.
    """
    for method in request.methods:  # refuse before any work is done
        request.model.check(request.params, method)
        if request.model.check_initial is not None:
            request.model.check_initial(request.params, request.initial, method)
    done = precomputed or {}
    trajectories: dict[str, Trajectory] = {}
    for m in request.methods:
        try:
            trajectories[m] = done[m] if m in done else _simulated(request, m)
        except TumbleError as exc:
            if not isinstance(exc.partial, Trajectory):  # nothing kept (or not a run)
                raise
            # What the method computed before it stopped: kept, and the error raised again
            # with the whole result attached, for the runner to write (marked).
            trajectories[m] = exc.partial
            stopped: dict[str, Json] = {
                "method": m,
                "t": float(exc.partial.tau[-1]),
                "reason": str(exc),
            }
            exc.partial = _result(request, trajectories, stopped)
            raise
    return _result(request, trajectories, None)


def _simulated(request: RunRequest, method: str) -> Trajectory:
    """One method of the request, run."""
    with stage(method):
        return simulate(
            request.model,
            request.params,
            request.initial,
            request.tau,
            method,
            rtol=request.rtol,
            atol=request.atol,
            integrator=request.integrator,
            averaging=request.averaging,
            max_steps=request.max_steps,
        )


def _result(
    request: RunRequest, trajectories: dict[str, Trajectory], stopped: Mapping[str, Json] | None
) -> RunResult:
    """The comparison, checks and reports of the trajectories run; with ``stopped`` (a method
    that ended early), only what holds for a trajectory cut short: its samples, and the
    differences of the methods that ran to the end."""
    model, p, st = request.model, request.params, request.initial
    datasets = {m: to_dataset(model, t, p) for m, t in trajectories.items()}
    whole = [m for m in trajectories if stopped is None or m != stopped["method"]]
    differences = {
        f"{b}_vs_{a}": max_differences(datasets[b], datasets[a])
        for a, b in itertools.combinations(whole, 2)
    }
    tau_end = float(request.tau[-1])
    validity = model.validity
    found = {
        m: unbridged(validity.check(p, st, trajectories[m].slow, tau_end), trajectories[m].legs)
        for m in whole
        if m in ("averaged", "closed_form") and validity is not None
    }
    issues = _merge_issues(found)
    if request.scaling is not None:  # a physical run's warnings give their time in SI
        issues = [issue_in_si(issue, request.scaling, tau_end) for issue in issues]
    for issue in issues:
        warn(issue["message"])
    limits = validity.limits(p, st) if validity is not None and validity.limits else {}
    diagnostics = {}
    extra = model.averaged.diagnostics if model.averaged is not None else None
    if extra is not None and "averaged" in whole:
        traj = trajectories["averaged"]
        values = extra.compute(p, st, traj.columns)
        diagnostics["averaged"] = _columns_dataset(
            extra.columns, values, traj.tau, model.time.name, model.time.units
        )
    # (a model's tables want whole runs)
    whole_run = stopped is None and model.report is not None
    report = model.report(p, st, trajectories) if whole_run and model.report else Report()
    return RunResult(
        request, datasets, trajectories, differences, issues, limits, diagnostics, report,
        ended_early=stopped,
    )  # fmt: skip
