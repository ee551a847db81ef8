"""Output files of a run rendered as bytes: CSV per method, summary.json, verify files.

Rendering is apart from writing: every text is ready before the first file is written, and
:mod:`tumble.io.fileset` writes a run's files as one set. :func:`atomic_write` replaces a
single file (a figure, a benchmark report) through a temporary file and ``os.replace``, so a
reader never sees half a file.
"""

from __future__ import annotations

import io
import json
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

from tumble._version import __version__
from tumble.analysis import RunResult, VerifyResult
from tumble.analysis.json_values import plain  # numpy → JSON values, shared with the claims
from tumble.analysis.run import on_tau
from tumble.errors import IntegrationError
from tumble.io.fileset import atomic_write
from tumble.models.schema import si_column, si_columns

__all__ = [
    "NonFiniteOutput",
    "atomic_write",
    "csv_text",
    "render_outputs",
    "summary",
    "table_text",
    "verify_outputs",
]


def _time_name(ds: xr.Dataset) -> str:
    """The paper's name of the time coordinate (``tau`` or ``t``)."""
    return str(ds["tau"].attrs.get("name", "tau"))


class NonFiniteOutput(IntegrationError):
    """A run whose outputs hold a value that is not finite (an overflow, a NaN): it fails
    with one line naming the file, the column and the first time, exit 3, instead of writing
    ``inf`` with exit 0. ``files`` are its outputs, rendered all the same and marked as failed
    in ``summary.json``, for the caller to keep."""

    def __init__(self, message: str, files: dict[str, bytes]) -> None:
        super().__init__(message)
        self.files = files


def first_non_finite(
    file: str,
    names: list[str],
    cols: list[np.ndarray],
    times: np.ndarray,
    no_mean: np.ndarray | None = None,
) -> str | None:
    """Where the first value that is not finite of an output's columns is, in words (the
    file, the column, the value and the time [the first column's unit]); None if every value
    is finite. ``no_mean`` marks the rows where a hybrid run was on the full equations: there
    its mean columns (``*_mean``) have no value, and NaN is what they hold."""
    for name, col in zip(names, cols, strict=True):
        values = np.asarray(col)
        if values.dtype.kind not in "fc":
            continue
        bad = ~np.isfinite(values)
        if no_mean is not None and "_mean" in name:
            bad &= ~(no_mean & np.isnan(values))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            return (
                f"{file}: column {name} is {values[i]} at {names[0]} = {float(times[i]):.6g} "
                f"(row {i + 1} of {values.size}): the run overflowed; nothing is written with "
                "a value that is not finite"
            )
    return None


def csv_text(ds: xr.Dataset, extra: dict[str, np.ndarray] | None = None) -> str:
    """CSV with header ``<time>,<variables in dataset order>``, values to full precision."""
    names = [_time_name(ds), *(str(v) for v in ds.data_vars)]
    cols = [ds["tau"].values, *(ds[v].values for v in ds.data_vars)]
    if extra:
        names, cols = list(extra), list(extra.values())
    buf = io.StringIO()
    np.savetxt(
        buf, np.column_stack(cols), fmt="%.17g", delimiter=",", header=",".join(names), comments=""
    )
    return buf.getvalue()


def table_text(header: tuple[str, ...], rows: list[tuple[Any, ...]]) -> str:
    """CSV of a table with mixed columns: strings as given, floats to full precision."""

    def cell(v: Any) -> str:
        if isinstance(v, float | np.floating):
            return f"{float(v):.17g}"
        return str(v)

    lines = [",".join(header), *(",".join(cell(v) for v in row) for row in rows)]
    return "\n".join(lines) + "\n"


def _legs(ds: xr.Dataset) -> dict[str, Any]:
    """A hybrid run's legs, or an averaged run's around its asymptotic steps, for its summary:
    each leg's kind, start and end (model time)."""
    if "legs" not in ds.attrs:
        return {}
    legs = json.loads(ds.attrs["legs"])
    return {"legs": [{"kind": k, "start": a, "end": b} for k, a, b in legs]}


def _on_full_legs(ds: xr.Dataset) -> np.ndarray | None:
    """The rows of a hybrid run's samples on its full legs (their ends included), or None for
    a run without one."""
    full = [(a, b) for kind, a, b in json.loads(ds.attrs.get("legs", "[]")) if kind == "full"]
    if not full:
        return None
    tau = ds["tau"].values
    rows = np.zeros(tau.shape, dtype=bool)
    for a, b in full:
        rows |= (tau >= a) & (tau <= b)
    return rows


def _verify_in_si(
    block: dict[str, Any], si: Callable[[str, Any], tuple[str, Any]], scaling: Any,
    units: dict[str, str],
) -> dict[str, Any]:  # fmt: skip
    """``[run] verify``'s figures of a physical run in SI: each variable's errors under its SI
    column name (``si``, which records the unit), its fitted slopes as ``<name>_slope`` (no
    unit), each variable's verdict under its SI name with its errors' keys carrying the
    unit's suffix, times (the horizon, the issues') in seconds and days."""

    def seconds(tau: float) -> float:
        return float(np.asarray(scaling.time_from_tau(np.array([tau])))[0])

    out = dict(block)
    t_s = seconds(out.pop("slow_horizon"))
    out["slow_horizon_s"], out["slow_horizon_days"] = t_s, t_s / DAY
    out["max_errors"] = {}
    per: dict[str, Any] = {}
    for v, errors in block["max_errors"].items():
        si_name, factor = si(v, 1.0)
        out["max_errors"][si_name] = [None if e is None else e * factor for e in errors]
    for v, figures in block["per_variable"].items():
        si_name, factor = si(v, 1.0)
        per[si_name] = {}
        for key, x in figures.items():
            if key.startswith("error"):
                per[si_name][key + si_name[len(v) :]] = None if x is None else x * factor
            else:
                per[si_name][key] = x
                units[key] = "1"
    out["per_variable"] = per
    out["orders"] = {f"{v}_slope": slope for v, slope in block["orders"].items()}
    units.update({f"{v}_slope": "1" for v in block["orders"]})

    def timed(issue: dict[str, Any]) -> dict[str, Any]:
        t = seconds(issue["tau"])
        return {**{k: x for k, x in issue.items() if k != "tau"}, "t_s": t, "t_days": t / DAY}

    out["issues"] = [[timed(i) for i in run] for run in block["issues"]]
    return out


def _final_state(ds: xr.Dataset) -> dict[str, float]:
    return {
        _time_name(ds): float(ds["tau"].values[-1]),
        **{str(v): float(ds[v].values[-1]) for v in ds.data_vars},
    }


def summary(
    result: RunResult,
    inputs: dict[str, Any],
    source: str,
    verification: VerifyResult | None = None,
) -> dict[str, Any]:
    """The run summary: inputs, final states, differences, wall times, limits, warnings, and
    the verdict of ``[run] verify``."""
    req = result.request
    p = req.params
    out: dict[str, Any] = {
        "tumble_version": __version__,
        "model": req.model.name,
        "paper": str(req.model.paper) if req.model.paper is not None else None,
        "scenario": source,
        "inputs": inputs,
        "derived": p.derived() if hasattr(p, "derived") else {},
        "methods": {
            m: {
                "form": ds.attrs["form"],
                "wall_time_s": ds.attrs["wall_time_s"],
                "nfev": ds.attrs["nfev"],
                "integrator": ds.attrs["integrator"],
                "final": _final_state(ds),
                **_legs(ds),
            }
            for m, ds in result.datasets.items()
        },
        "max_differences": result.differences,
        "predicted_limits": result.limits,
        "warnings": result.issues,
    }
    if result.ended_early is not None:
        out["ended_early"] = dict(result.ended_early)
    if result.diagnostics:
        out["diagnostics"] = {
            m: {
                str(v): {
                    "min": float(np.min(ds[v].values)),
                    "max": float(np.max(ds[v].values)),
                    "long_name": ds[v].attrs.get("long_name", ""),
                }
                for v in ds.data_vars
            }
            for m, ds in result.diagnostics.items()
        }
    if req.scaling is not None:
        out["scaling"] = req.scaling.summary()
    if "averaged" in req.methods:
        # The run's choices for the averaged equations, as the scenario keys name them.
        opts = req.averaging
        out["averaging"] = opts.averaging
        out["averaged_form"] = opts.coordinates or None
        out["averaged_init"] = opts.start
        out["averaging_order"] = opts.order
        out["initial"] = opts.initial if opts.order == 2 else None
        out["averaged_method"] = "hybrid" if opts.hybrid else "plain"
        out["averaged_only"] = opts.averaged_only
    out.update(result.report.summary)
    if verification is not None:
        out["verify"] = verification.summary()
    if req.scaling is not None:
        out = _in_si(out, result)
    return plain(out)


UNIT_SUFFIXES = (
    ("_kgm2_s", "kg m²/s"),
    ("_rad_s", "rad/s"),
    ("_deg_s", "deg/s"),
    ("_kgm2", "kg m²"),
    ("_days", "d"),
    ("_rad", "rad"),
    ("_deg", "deg"),
    ("_Nms", "N m s"),
    ("_Nm", "N m"),
    ("_J", "J"),
    ("_s", "s"),
)
"""The unit a key's name ends with, longest first: ``T0_s`` is in seconds, ``L_kgm2_s`` in
kg m²/s."""

_COUNTS = {"nfev": "1", "averaging_order": "1", "eps": "1"}  # numbers without a unit


def _si_final(ds: xr.Dataset, scaling: Any) -> tuple[dict[str, float], dict[str, str]]:
    """The last sample of a run in SI, under the SI files' column names, and their units."""
    cols = {str(v): ds[v].values[-1:] for v in ds.data_vars}
    units = {str(v): _units(ds, v) for v in ds.data_vars}
    si = si_columns(scaling, cols, ds["tau"].values[-1:], units)
    names = {n: u or "1" for v in ds.data_vars
             for n, _, u in si_column(scaling, str(v), units[str(v)])}  # fmt: skip
    return {k: float(v[0]) for k, v in si.items()}, {"t_s": "s", "t_days": "d", **names}


def _in_si(out: dict[str, Any], result: RunResult) -> dict[str, Any]:
    """A physical run's summary in its scenario's units: the final states, the differences,
    the predicted limits and the warnings' times in SI under the SI files' column names (the
    normalised values stay in the ``.csv`` and ``.nc`` files), each input's unit under
    ``input_units``, and the unit of every other number under ``units``, by its key."""
    scaling = result.request.scaling
    units: dict[str, str] = {}
    for m, ds in result.datasets.items():
        out["methods"][m]["final"], found = _si_final(ds, scaling)
        units.update(found)
        for leg in out["methods"][m].get("legs", ()):  # the legs' times in SI
            for key in ("start", "end"):
                t_s = float(np.asarray(scaling.time_from_tau(np.array([leg.pop(key)])))[0])
                leg[f"{key}_s"], leg[f"{key}_days"] = t_s, t_s / DAY
    first = next(iter(result.datasets.values()))

    def si(name: str, value: Any) -> tuple[str, Any]:
        unit = _units(first, name) if name in first else ""
        si_name, factor, si_unit = si_column(scaling, name, unit)[0]
        units[si_name] = si_unit or "1"
        return si_name, value * factor if isinstance(value, float | int) else value

    out["max_differences"] = {
        pair: dict(si(k, v) for k, v in diffs.items()) for pair, diffs in result.differences.items()
    }

    def limit(k: str, v: Any) -> tuple[str, Any]:
        if isinstance(v, float):
            return si(k, v)
        if isinstance(v, list | tuple) and v and all(isinstance(x, float) for x in v):
            name, factor = si(k, 1.0)  # a range: both ends in the same unit
            return name, [x * factor for x in v]
        return k, v

    out["predicted_limits"] = dict(limit(k, v) for k, v in result.limits.items())
    for m, diag in result.diagnostics.items():  # e.g. the fast frequencies along the run
        figures: dict[str, Any] = {"long_names": {}}
        for v in diag.data_vars:
            name, factor, si_unit = si_column(scaling, str(v), _units(diag, v))[0]
            values = diag[v].values * factor
            for end, x in (("min", np.min(values)), ("max", np.max(values))):
                figures[f"{end}_{name}"] = float(x)
                units[f"{end}_{name}"] = si_unit or "1"
            figures["long_names"][name] = diag[v].attrs.get("long_name", "")
        out["diagnostics"][m] = figures
    if out.get("forcing_period") is not None:  # a model time
        t = out.pop("forcing_period")
        out["forcing_period_s"] = float(np.asarray(scaling.time_from_tau(np.array([t])))[0])
    # The derived parameters are the model's normalised ones (t = T0 τ, inertia over I0):
    # pure numbers.
    units.update({k: "1" for k, v in out.get("derived", {}).items() if isinstance(v, float | int)})
    out["warnings"] = [
        {**{k: v for k, v in w.items() if k != "tau"}, "t_s": w["t_s"], "t_days": w["t_s"] / DAY}
        for w in result.issues
    ]
    if "ended_early" in out:
        stop = dict(out["ended_early"])
        t_s = float(np.asarray(scaling.time_from_tau(np.array([stop.pop("t")])))[0])
        out["ended_early"] = {**stop, "t_s": t_s, "t_days": t_s / DAY}
    if "verify" in out:
        out["verify"] = _verify_in_si(out["verify"], si, scaling, units)
    out["input_units"] = _input_units(result, out["inputs"])
    units.update({k: u for k, u in _COUNTS.items()})
    for key in _number_keys({k: v for k, v in out.items() if k not in ("inputs", "input_units")}):
        if key not in units:
            unit = next((u for suffix, u in UNIT_SUFFIXES if key.endswith(suffix)), None)
            if unit is not None:
                units[key] = unit
    out["units"] = dict(sorted(units.items()))
    return out


DAY = 86400.0  # [s]


def _numeric(v: Any) -> bool:
    """A number, or a non-empty list (of lists) of numbers: a vector, a matrix."""
    return _is_number(v) or (isinstance(v, list) and bool(v) and all(map(_numeric, v)))


def _number_keys(data: Any) -> set[str]:
    """The keys of ``data`` (nested tables and lists) whose values are numbers or lists of
    numbers."""
    found: set[str] = set()
    if isinstance(data, dict):
        for k, v in data.items():
            if _numeric(v):
                found.add(str(k))
            else:
                found |= _number_keys(v)
    elif isinstance(data, list):
        for v in data:
            found |= _number_keys(v)
    return found


def _is_number(v: Any) -> bool:
    return isinstance(v, int | float | np.number) and not isinstance(v, bool)


def _input_units(result: RunResult, inputs: dict[str, Any]) -> dict[str, dict[str, str]]:
    """The unit of each number of a physical scenario's inputs, by table and key, from its
    schema (an angle given in degrees is echoed in radians; "1" for a number without one)."""
    from tumble.io.scenario import run_keys  # the scenario's [run] keys, by its declaration
    from tumble.models.base import Declaration

    model = result.request.model
    schema = model.scenario
    if schema is None:
        return {}
    variant = next((v for v in schema.variants if v.physical), schema.variants[0])
    tables = {s.name: s.keys for s in variant.sections}
    tables["run"] = run_keys(Declaration.of(model), variant)
    found: dict[str, dict[str, str]] = {}
    for name, keys in tables.items():
        values = inputs.get(name) if name else inputs
        if not isinstance(values, dict):
            continue
        numbers = _number_keys(values)
        table = {k.name: ("rad" if k.angle else k.units or "1") for k in keys if k.name in numbers}
        if table:
            found[name] = table
    terms = inputs.get("torque")
    if isinstance(terms, list) and model.name in ("torqued_body",):  # its [[torque]] tables
        from tumble.models.torqued_body.inputs import PHYSICAL_TERMS

        table = {}
        for term in terms:
            section = PHYSICAL_TERMS.get(term.get("kind", "")) if isinstance(term, dict) else None
            for k in section.keys if section is not None else ():
                table[k.name] = "rad" if k.angle else k.units or "1"
                if k.angle:
                    table[f"{k.name}_deg"] = "deg"
        if table:
            found["torque"] = table
    return found


def _with_si(ds: xr.Dataset, scaling: Any, si: dict[str, Any]) -> xr.Dataset:
    """``ds`` with the SI columns of a physical run beside the normalised ones: ``t_s`` [s],
    ``t_days`` [d] and each column under its SI names, with its unit (:func:`si_column`)."""
    extra = {
        "t_s": on_tau(si["t_s"], {"units": "s", "long_name": "time t"}),
        "t_days": on_tau(si["t_days"], {"units": "d", "long_name": "time t in days"}),
    }
    for name in ds.data_vars:
        for si_name, _factor, unit in si_column(scaling, str(name), _units(ds, name)):
            if si_name not in ds:
                extra[si_name] = on_tau(si[si_name], {**ds[name].attrs, "units": unit})
    return ds.assign(extra)


def _units(ds: xr.Dataset, name: Any) -> str:
    """The unit of the column ``name`` of ``ds`` ("" for none)."""
    return str(ds[name].attrs.get("units", ""))


def render_outputs(
    result: RunResult,
    inputs: dict[str, Any],
    source: str,
    verification: VerifyResult | None = None,
) -> dict[str, bytes]:
    """File name → content of every output of a run but its figure (per method CSV and NetCDF,
    summary.json; with a verification, its files of :func:`verify_outputs` too).

    Raises
    ------
    NonFiniteOutput
        If a column of a method's CSV holds a value that is not finite; its ``files`` are
        the outputs all the same, ``summary.json`` marked with ``"failed"``.
    """
    files: dict[str, bytes] = {}
    scaling = result.request.scaling
    problems: list[str] = []
    for method, ds in result.datasets.items():
        files[f"{method}.csv"] = csv_text(ds).encode()
        names = [_time_name(ds), *(str(v) for v in ds.data_vars)]
        tau = ds["tau"].values
        no_mean = _on_full_legs(ds)
        problems.append(first_non_finite(f"{method}.csv", names, [tau, *(ds[v].values
                                         for v in ds.data_vars)], tau, no_mean) or "")  # fmt: skip
        nc = ds
        if scaling is not None:
            cols = {str(v): ds[v].values for v in ds.data_vars}
            units = {str(v): _units(ds, v) for v in ds.data_vars}
            si = si_columns(scaling, cols, ds["tau"].values, units)
            files[f"{method}_si.csv"] = csv_text(ds, si).encode()
            first = next(iter(si.values()))
            problems.append(first_non_finite(f"{method}_si.csv", list(si), list(si.values()),
                                             first, no_mean) or "")  # fmt: skip
            nc = _with_si(ds, scaling, si)
        # The same columns with their units, long names and equations as attributes (NetCDF 3,
        # which needs no library beyond scipy); a physical run's SI columns beside them.
        files[f"{method}.nc"] = bytes(nc.to_netcdf(engine="scipy"))
    for method, ds in result.diagnostics.items():
        files[f"{method}_diagnostics.csv"] = csv_text(ds).encode()
    for name, (header, rows) in result.report.tables.items():
        files[f"{name}.csv"] = table_text(header, rows).encode()
    data = summary(result, inputs, source, verification)
    problem = next((p for p in problems if p), None)
    if problem is not None:
        data["failed"] = problem  # the mark of outputs kept from a failed run
    text = json.dumps(plain(data), indent=2, ensure_ascii=False)
    files["summary.json"] = (text + "\n").encode()
    if verification is not None:
        files.update(verify_outputs(verification, source))
    if problem is not None:
        raise NonFiniteOutput(problem, files)
    return files


def verify_outputs(result: VerifyResult, source: str) -> dict[str, bytes]:
    """Text outputs of ``tumble verify``.

    ``verify.csv``: one row per order of averaging measured, slow variable and ε
    (``averaging_order, variable, eps, max_error, order``, the last the fitted order);
    ``verify_curves.csv``: the error curves of the scenario's order (``eps, slow_time,
    variable, error``); ``verify.json``: verdict, orders, errors, per variable the slopes and
    errors of both orders (``per_variable``), the validity issues met and any failed run.
    """
    time_name = result.time_name
    fits = result.by_order or {1: {v: (result.errors[v], result.orders[v]) for v in result.errors}}
    rows = [
        (order, v, float(e), float(err), "" if o is None else float(o))
        for order, fit in sorted(fits.items())
        for v, (errors, o) in fit.items()
        for e, err in zip(result.eps, errors, strict=True)
    ]
    curves = [
        (float(e), float(s), v, float(d))
        for e, run in zip(result.eps, result.curves, strict=True)
        for v, (slow, err) in run.items()
        for s, d in zip(slow, err, strict=True)
    ]
    doc = {
        "tumble_version": __version__,
        "model": result.model,
        "scenario": source,
        "time": time_name,
        **result.summary(),
    }
    text = json.dumps(plain(doc), indent=2, ensure_ascii=False)
    return {
        "verify.csv": table_text(
            ("averaging_order", "variable", "eps", "max_error", "order"), rows
        ).encode(),
        "verify_curves.csv": table_text(("eps", "slow_time", "variable", "error"), curves).encode(),
        "verify.json": (text + "\n").encode(),
    }
