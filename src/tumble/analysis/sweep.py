"""Parameter sweeps: the grid and Monte Carlo points, what is kept of each run, the Dataset.

A sweep varies scenario keys over grid axes (one dimension each) and Monte Carlo draws (one
``sample`` dimension), runs every point like ``tumble run`` would, and keeps from each run
plain values (a *record*): its status and the reason of a failure, wall time, the final slow
state of every method, the largest differences between methods, the model's predicted
limits, the stability of its stationary motion and the figures of ``tumble verify``.
Records are assembled into an :class:`xarray.Dataset` with one dimension per grid axis (then
``sample``), units and long names in ``attrs``.

This module holds the numerics only; files, Dask and the scenario keys live in
:mod:`tumble.io.sweep` and :mod:`tumble.app.sweep`.
"""

from __future__ import annotations

import math
import time
import traceback
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from tumble.analysis.plan import (
    MAX_POINTS,
    PENDING,
    STATUS,
    Axis,
    Draw,
    Keep,
    Record,
    SweepPlan,
)
from tumble.analysis.run import RunRequest, run
from tumble.analysis.stability import CLASSES, analyze
from tumble.analysis.verify import verify
from tumble.errors import TumbleError, TumbleWarning, shorten

__all__ = [
    "MAX_POINTS",
    "STATUS",
    "Axis",
    "Draw",
    "Keep",
    "SweepPlan",
    "column_attrs",
    "failed_record",
    "internal_reason",
    "records_to_dataset",
    "run_point",
]


def _si_factor(request: RunRequest, name: str) -> float:
    """The factor taking column ``name`` to SI in a physical scenario (1 otherwise): a sweep
    keeps physical values, whose points may each have their own time scale T0."""
    conv = None if request.scaling is None else request.scaling.si(name)
    return 1.0 if conv is None else float(conv[0])


def _final_values(
    request: RunRequest, result: Any, slow: Sequence[str]
) -> dict[str, dict[str, float]]:
    return {
        m: {v: _si_factor(request, v) * float(ds[v].values[-1]) for v in slow if v in ds}
        for m, ds in result.datasets.items()
    }


def _series(request: RunRequest, result: Any, names: Sequence[str]) -> Record:
    """The kept variables at every sample time, per method: ``series`` (method → variable →
    values), ``series_time`` and ``series_units`` (variable → unit). A physical scenario's in
    SI against seconds, so that points of different time scales T0 share their times."""
    scaling = request.scaling
    times = request.tau if scaling is None else scaling.time_from_tau(request.tau)
    series: dict[str, dict[str, list[float]]] = {}
    units: dict[str, str] = {}
    for method, ds in result.datasets.items():
        kept = {}
        for name in names:
            if name not in ds:
                continue
            values = np.asarray(ds[name].values, dtype=float)
            conv = None if scaling is None else scaling.si(name)
            units[name] = str(ds[name].attrs.get("units", "")) if conv is None else conv[1]
            kept[name] = (values if conv is None else conv[0] * values).tolist()
        series[method] = kept
    time_units = request.model.time.units if scaling is None else "s"
    return {"series": series, "series_time": np.asarray(times, dtype=float).tolist(),
            "series_units": {**units, "time": time_units}}  # fmt: skip


def _slow_variables(request: RunRequest) -> tuple[str, ...]:
    """Slow variables: the columns of the averaged description (else of the first method)."""
    model, p = request.model, request.params
    for method in ("averaged", "closed_form", request.methods[0]):
        if method in model.methods:
            return tuple(c.name for c in model.columns(p, method))
    return ()


def _limits(limits: Mapping[str, Any]) -> dict[str, Any]:
    """The scalar predicted limits (numbers and statements); lists and tables are skipped."""
    out: dict[str, Any] = {}
    for k, v in limits.items():
        if isinstance(v, bool):
            out[k] = int(v)
        elif isinstance(v, int | float | np.floating | np.integer):
            out[k] = float(v)
        elif isinstance(v, str):
            out[k] = v
    return out


def column_attrs(request: RunRequest) -> dict[str, dict[str, str]]:
    """Units, long names and equations of the columns of a run's methods (the attrs of the
    sweep's variables, taken once from the base scenario rather than from every point); in SI
    for a physical scenario, whose points keep SI values."""
    model, p, scaling = request.model, request.params, request.scaling
    meta: dict[str, dict[str, str]] = {}
    for method in request.methods:
        for c in model.columns(p, method):
            conv = None if scaling is None else scaling.si(c.name)
            units = c.units if conv is None else conv[1]  # a physical scenario's are in SI
            meta.setdefault(
                c.name, {"units": units, "long_name": c.long_name, "equation": c.equation}
            )
    return meta


def run_point(
    request: RunRequest,
    keep: Keep,
    precomputed: Mapping[str, Any] | None = None,
) -> Record:
    """Run one point of a sweep and keep what ``keep`` asks for.

    A :class:`~tumble.errors.TumbleError` (an integration that fails, averaging that becomes
    invalid, a parameter out of range) does not propagate: the record says ``status`` 1 and
    the reason. The validity warnings the run emits are kept as ``issues``.

    Parameters
    ----------
    request : RunRequest
        The point's run.
    keep : Keep
        What to keep.
    precomputed : mapping, optional
        Method → Trajectory already integrated (the batch path), passed on to
        :func:`~tumble.analysis.run.run`.

    Returns
    -------
    dict
        ``status``, ``reason``, ``wall_time`` [s], ``issues``, ``first_issue_time`` and, as
        asked, ``final`` (method → variable → value), ``nfev`` (method → count),
        ``differences`` (pair → variable → value), ``limits``, ``stability``,
        ``max_real`` and ``verify``.
    """
    start = time.perf_counter()
    record: Record = {"status": 0, "reason": "", "issues": "", "first_issue_time": math.nan}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", TumbleWarning)  # kept below, from result.issues
            result = run(request, precomputed=precomputed)
            verification = verify(request) if keep.verify else None
        if result.issues:
            record["issues"] = "; ".join(
                f"{i['condition']} at {request.model.time.name} = {i['tau']:.6g}"
                for i in result.issues
            )
            record["first_issue_time"] = float(result.issues[0]["tau"])
        record["nfev"] = {m: int(t.nfev) for m, t in result.trajectories.items()}
        if keep.final:
            record["final"] = _final_values(request, result, _slow_variables(request))
        if keep.series:
            record.update(_series(request, result, keep.series))
        if keep.differences:
            record["differences"] = {
                k: {name: _si_factor(request, name) * d for name, d in v.items()}
                for k, v in result.differences.items()
            }
        if keep.limits:
            record["limits"] = _limits(result.limits)
        if keep.stability:
            rep = analyze(request.model, request.params, family=False)
            record["stability"] = CLASSES.index(rep.classification)
            record["max_real"] = rep.max_real
        if verification is not None:
            s = verification.summary()
            record["verify"] = {
                "status": verification.status,
                "order": {v: (math.nan if o is None else float(o)) for v, o in s["orders"].items()},
                "error": {
                    v: (math.nan if e[0] is None else float(e[0]))
                    for v, e in s["max_errors"].items()
                },
            }
    except TumbleError as exc:
        record = {**record, "status": 1, "reason": f"{type(exc).__name__}: {shorten(str(exc))}"}
    except Exception as exc:  # a defect met by this point alone: recorded, never its chunk's
        record = {**record, "status": 1, "reason": internal_reason(exc)}
    record["wall_time"] = time.perf_counter() - start
    return record


def internal_reason(exc: BaseException) -> str:
    """The reason recorded for a point that met an error tumble did not anticipate: the
    exception and where it arose, in one line (no traceback reaches the user)."""
    frames = traceback.extract_tb(exc.__traceback__)
    where = f" (at {Path(frames[-1].filename).name}:{frames[-1].lineno})" if frames else ""
    return f"internal error: {type(exc).__name__}: {shorten(str(exc))}{where}"


def failed_record(reason: str) -> Record:
    """The record of a point that could not run at all (e.g. its scenario is invalid)."""
    return {
        "status": 1,
        "reason": reason,
        "issues": "",
        "first_issue_time": math.nan,
        "wall_time": 0.0,
    }


def _attrs(units: str, long_name: str, **extra: Any) -> dict[str, Any]:
    return {"units": units, "long_name": long_name, **extra}


def _lookup(record: Record, path: tuple[str, ...]) -> Any:
    """``record[path[0]][path[1]]…``, or None where a key is missing."""
    node: Any = record
    for key in path:
        if not isinstance(node, dict) or key not in node:
            return None
        node = node[key]
    return node


def _fill(
    plan: SweepPlan,
    records: Mapping[int, Record],
    path: tuple[str, ...],
    *,
    text: bool = False,
    integer: bool = False,
    pending: Any = None,
) -> np.ndarray:
    """One value per point from ``records`` (NaN, "" or ``pending`` where none)."""
    if text:
        out = np.full(plan.size, "", dtype=object)
    elif integer:
        out = np.full(plan.size, PENDING if pending is None else pending, dtype=np.int32)
    else:
        out = np.full(plan.size, np.nan)
    for i, rec in records.items():
        v = _lookup(rec, path)
        if v is not None:
            out[i] = v
    return out.reshape(plan.shape)


def _union(records: Mapping[int, Record], key: str) -> list[str]:
    """Second-level keys of ``key`` over all records, in order of first appearance."""
    seen: dict[str, None] = {}
    for rec in records.values():
        for k in rec.get(key, {}):
            seen.setdefault(k, None)
    return list(seen)


def _union2(records: Mapping[int, Record], key: str) -> list[str]:
    """Third-level keys of ``key`` (the variables under each method or pair)."""
    seen: dict[str, None] = {}
    for rec in records.values():
        for inner in rec.get(key, {}).values():
            for k in inner:
                seen.setdefault(k, None)
    return list(seen)


def records_to_dataset(
    plan: SweepPlan,
    records: Mapping[int, Record],
    *,
    model: str,
    time_name: str,
    columns: Mapping[str, Mapping[str, str]] | None = None,
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """Assemble the records of a sweep (flat point index → record) into a Dataset.

    Points without a record (not computed yet) have ``status`` −1 and NaN values, so a partial
    sweep is a valid Dataset too.

    Parameters
    ----------
    plan : SweepPlan
    records : mapping
        Flat point index → record of :func:`run_point`.
    model, time_name : str
        The model's name and time variable (``tau`` or ``t``), for the attrs.
    columns : mapping, optional
        Column name → ``units``, ``long_name``, ``equation`` (:func:`column_attrs` of the base
        scenario); a column not in it gets its name as long name and no unit.
    attrs : mapping, optional
        More Dataset attributes (the sweep file, its hash).

    Returns
    -------
    xarray.Dataset
        Dims: one per grid axis, then ``sample``; ``method`` and ``pair`` for the final
        values and differences.
    """
    parts = _Parts(plan, records, columns or {}, time_name)
    data: dict[str, Any] = {}
    extra_coords: dict[str, Any] = {}
    for build in (parts.status, parts.methods, parts.series, parts.limits, parts.stability,
                  parts.verify):  # fmt: skip
        more, coords = build()
        data.update(more)
        extra_coords.update(coords)
    ds = xr.Dataset(data, coords={**_coords(plan), **extra_coords})
    ds.attrs.update(
        model=model,
        time=time_name,
        points=plan.size,
        points_done=len(records),
        points_failed=sum(1 for r in records.values() if r["status"] == 1),
        monte_carlo_seed=plan.seed if plan.samples else -1,
        **(attrs or {}),
    )
    return ds


def _coords(plan: SweepPlan) -> dict[str, Any]:
    """The grid axes, and the Monte Carlo samples with their draws."""
    coords: dict[str, Any] = {
        a.name: (a.name, a.values, _attrs(a.units, a.long_name, key=a.key, scale=a.scale))
        for a in plan.axes
    }
    if plan.samples:
        coords["sample"] = ("sample", np.arange(plan.samples), _attrs("1", "Monte Carlo sample"))
        for j, d in enumerate(plan.draws):
            meta = _attrs(
                d.units, d.long_name, key=d.key, distribution=d.distribution, parameters=[d.a, d.b]
            )
            coords[d.name] = ("sample", plan.drawn[:, j], meta)
    return coords


Variables = tuple[dict[str, Any], dict[str, Any]]  # data variables, extra coordinates


@dataclass(frozen=True)
class _Parts:
    """The data variables of a sweep's Dataset, group by group."""

    plan: SweepPlan
    records: Mapping[int, Record]
    meta: Mapping[str, Mapping[str, str]]
    time_name: str

    @property
    def symbol(self) -> str:
        return {"tau": "τ"}.get(self.time_name, self.time_name)

    def fill(self, path: tuple[str, ...], **kw: Any) -> Any:
        return _fill(self.plan, self.records, path, **kw)

    def var_attrs(self, name: str, prefix: str) -> dict[str, Any]:
        m = self.meta.get(name, {"units": "", "long_name": name, "equation": ""})
        return _attrs(m["units"], f"{prefix}{m['long_name']}", equation=m.get("equation", ""))

    def status(self) -> Variables:
        dims, fill = self.plan.dims, self.fill
        flags = {"flag_values": [-1, 0, 1], "flag_meanings": "pending ok failed"}
        first = f"first time {self.symbol} an averaged run leaves its validity"
        return {
            "status": (
                dims,
                fill(("status",), integer=True),
                _attrs("1", "status of the run", **flags),
            ),
            "reason": (dims, fill(("reason",), text=True), _attrs("", "why the run failed")),
            "wall_time": (dims, fill(("wall_time",)), _attrs("s", "wall time of the point")),
            "issues": (
                dims,
                fill(("issues",), text=True),
                _attrs("", "validity conditions entered by an averaged run, with their times"),
            ),
            "first_issue_time": (dims, fill(("first_issue_time",)), _attrs(self.time_name, first)),
        }, {}

    def methods(self) -> Variables:
        """Evaluations, final values per method and differences per pair of methods."""
        dims, records = self.plan.dims, self.records
        data: dict[str, Any] = {}
        coords: dict[str, Any] = {}
        methods = _union(records, "nfev")
        if methods:
            coords["method"] = ("method", np.array(methods, dtype=object))
            stack = [self.fill(("nfev", m), integer=True, pending=0) for m in methods]
            attrs = _attrs("1", "right-hand-side evaluations")
            data["nfev"] = ((*dims, "method"), np.stack(stack, axis=-1), attrs)
        data |= self.stacked("final", "method", methods, "final_", "final ")
        pairs = _union(records, "differences")
        if pairs:
            coords["pair"] = ("pair", np.array(pairs, dtype=object))
        label = "max |difference| between two methods, "
        data |= self.stacked("differences", "pair", pairs, "difference_", label)
        return data, coords

    def stacked(
        self, section: str, dim: str, keys: list[str], prefix: str, label: str
    ) -> dict[str, Any]:
        """One variable per name of the records' ``section`` (``section → key → name →
        value``), called ``prefix + name``, its ``keys`` (methods or pairs of methods) stacked
        along ``dim`` after the grid's; ``label`` starts its long name."""
        data: dict[str, Any] = {}
        for v in _union2(self.records, section):
            stack = [self.fill((section, k, v)) for k in keys]
            data[f"{prefix}{v}"] = (
                (*self.plan.dims, dim),
                np.stack(stack, axis=-1),
                self.var_attrs(v, label),
            )
        return data

    def series(self) -> Variables:
        """The kept variables against time, per method: dims (*grid, sample, method, time)."""
        first = next((r for r in self.records.values() if "series_time" in r), None)
        if first is None:
            return {}, {}
        times = np.asarray(first["series_time"], dtype=float)
        units = first["series_units"]
        methods = _union(self.records, "nfev")  # the method coordinate of :meth:`methods`
        data: dict[str, Any] = {}
        for v in _union2(self.records, "series"):
            out = np.full((self.plan.size, len(methods), times.size), np.nan)
            for i, rec in self.records.items():
                for k, m in enumerate(methods):
                    values = _lookup(rec, ("series", m, v))
                    if values is not None and len(values) == times.size:
                        out[i, k] = values
            attrs = {**self.var_attrs(v, ""), "units": units.get(v, "")}
            data[f"series_{v}"] = (
                (*self.plan.dims, "method", "time"),
                out.reshape(*self.plan.shape, len(methods), times.size),
                attrs,
            )
        time_attrs = _attrs(units.get("time", ""), "time of the kept series")
        return data, {"time": ("time", times, time_attrs)}

    def limits(self) -> Variables:
        data: dict[str, Any] = {}
        for k in _union(self.records, "limits"):
            text = any(isinstance(r.get("limits", {}).get(k), str) for r in self.records.values())
            units = self.meta.get(k, {}).get("units", "")
            attrs = {**self.var_attrs(k, "predicted limit of "), "units": units}
            data[f"limit_{k}"] = (self.plan.dims, self.fill(("limits", k), text=text), attrs)
        return data, {}

    def stability(self) -> Variables:
        if not any("stability" in r for r in self.records.values()):
            return {}, {}
        dims = self.plan.dims
        meanings = " ".join(["pending_or_failed", *(c.replace(" ", "_") for c in CLASSES)])
        classes = _attrs(
            "1",
            "classification of the stationary motion",
            flag_values=list(range(-1, len(CLASSES))),
            flag_meanings=meanings,
        )
        leading = _attrs(f"1/{self.symbol}", "leading real part max Re λ of the stationary motion")
        return {
            "stability": (dims, self.fill(("stability",), integer=True), classes),
            "max_real": (dims, self.fill(("max_real",)), leading),
        }, {}

    def verify(self) -> Variables:
        if not any("verify" in r for r in self.records.values()):
            return {}, {}
        dims = self.plan.dims
        verdict = _attrs("", "verdict of tumble verify (first-order, degraded, invalid, exact)")
        data: dict[str, Any] = {
            "verify_status": (dims, self.fill(("verify", "status"), text=True), verdict)
        }
        for what, prefix, unit in (
            ("order", "fitted order in ε of ", "1"),
            ("error", "max |full − averaged| at ε of ", None),
        ):
            names: dict[str, None] = {}
            for r in self.records.values():
                names.update(dict.fromkeys(r.get("verify", {}).get(what, {})))
            for v in names:
                a = self.var_attrs(v, prefix)
                if unit is not None:
                    a["units"] = unit
                data[f"verify_{what}_{v}"] = (dims, self.fill(("verify", what, v)), a)
        return data, {}
