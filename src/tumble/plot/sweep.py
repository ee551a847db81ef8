"""Figures of a sweep: heat maps over two grid axes, lines over one, histograms of Monte Carlo,
percentile bands of kept series against time.

Draws the Dataset of :func:`tumble.analysis.sweep.records_to_dataset`. Labels and units come
from its ``attrs``; failed points are marked, never hidden.
"""

from __future__ import annotations

import io
import textwrap
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from tumble.plot.labels import with_units
from tumble.plot.stability import _edges, _is_log, _label

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["default_variables", "plot_sweep_variable", "sweep_figure", "sweep_png"]

MAX_PANELS = 6


def default_variables(ds: xr.Dataset, slow: Sequence[str] = ()) -> list[str]:
    """The variables a sweep's figure shows: the final values of up to four slow variables
    (``slow``, else the first four), the leading real part of the stationary motion, the first
    verify order, and the wall time."""
    finals = [f"final_{v}" for v in slow if f"final_{v}" in ds] or [
        str(v) for v in ds.data_vars if str(v).startswith("final_")
    ]
    series = [str(v) for v in ds.data_vars if str(v).startswith("series_")][:2]
    finals = finals[: 4 - len(series)]
    extra = [v for v in ("max_real",) if v in ds]
    orders = [str(v) for v in ds.data_vars if str(v).startswith("verify_order_")][:1]
    return [*series, *finals, *extra, *orders, "wall_time"][:MAX_PANELS]


BANDS = ((5.0, 95.0, 0.2), (25.0, 75.0, 0.4))
"""Percentile bands of a kept series (low, high, opacity): 90 % and 50 % of the runs."""


def _plot_series(da: xr.DataArray, ax: Axes, name: str) -> str:
    """Median and percentile bands of a kept series over every point; the title."""
    time = da["time"]
    runs = da.transpose(..., "time").values.reshape(-1, time.size)
    runs = runs[np.all(np.isfinite(runs), axis=1)]
    t = np.asarray(time.values, dtype=float)
    unit = str(time.attrs.get("units", ""))
    if unit == "s" and t[-1] > 2 * 86400.0:
        t, unit = t / 86400.0, "d"
    if runs.size:
        for low, high, alpha in BANDS:
            lo, hi = np.percentile(runs, [low, high], axis=0)
            ax.fill_between(t, lo, hi, color="tab:blue", alpha=alpha, lw=0,
                            label=f"{low:g}–{high:g} %")  # fmt: skip
        ax.plot(t, np.median(runs, axis=0), color="tab:blue", lw=1.5, label="median")
        ax.legend(loc="best", fontsize="small")
    ax.set_xlabel(with_units("time", unit))
    ax.set_ylabel(with_units(name.removeprefix("series_"), str(da.attrs.get("units", ""))))
    ax.grid(True, alpha=0.3)
    return f"{da.attrs.get('long_name', name)}: median and bands of {runs.shape[0]} runs"


def _select(da: xr.DataArray, method: str | None) -> tuple[xr.DataArray, str]:
    """One method (averaged by default) and the first pair; a note of what was chosen."""
    note = ""
    if "method" in da.dims:
        methods = [str(m) for m in da["method"].values]
        pick = (
            method if method in methods else ("averaged" if "averaged" in methods else methods[0])
        )
        da, note = da.sel({"method": pick}), pick  # not sel(method=…): a keyword of sel
    if "pair" in da.dims:
        da, note = da.isel(pair=0), str(da["pair"].values[0])
    return da, note


def _log_axes(ax: Axes, x: bool, y: bool) -> None:
    """Log scales with labels at the decades only (minor labels overlap on short ranges)."""
    from matplotlib.ticker import NullFormatter

    for log, axis, scale in ((x, ax.xaxis, ax.set_xscale), (y, ax.yaxis, ax.set_yscale)):
        if log:
            scale("log")
            axis.set_minor_formatter(NullFormatter())


def plot_sweep_variable(
    ds: xr.Dataset, name: str, *, method: str | None = None, ax: Axes | None = None
) -> Axes:
    """One variable of a sweep, drawn by the shape of the sweep.

    Two or more grid axes: a heat map over the first two (further axes at their first value);
    one: a line; Monte Carlo only: a histogram. With both grid axes and samples, the mean over
    the samples is drawn. Failed points are marked with ×.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep's Dataset.
    name : str
        The variable.
    method : str, optional
        For per-method variables (default: ``averaged`` if run, else the first method).
    ax : Axes, optional

    Returns
    -------
    Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(5.0, 4.0))
    da, note = _select(ds[name], method)
    failed = ds["status"] == 1
    grid = [str(d) for d in ds["status"].dims if d != "sample"]
    title = str(da.attrs.get("long_name", name))
    if note and f"({note})" not in title:  # some long names already name their method
        title += f" ({note})"
    units = str(da.attrs.get("units", ""))
    short = with_units(name, units)  # the axis label; the title says the rest
    if "time" in da.dims:  # a kept series: bands over every point
        title = _plot_series(da, ax, name) + (f" ({note})" if note else "")
        ax.set_title(textwrap.fill(title, 60), fontsize="small")
        return ax
    for extra in grid[2:]:
        da, failed = da.isel({extra: 0}), failed.isel({extra: 0})
        title += f", {extra} = {float(ds[extra].values[0]):.4g}"
    if grid and "sample" in da.dims:
        da, failed = da.mean("sample", skipna=True), failed.any("sample")
        title = "mean over samples of " + title
    if not grid:
        title += _histogram(da, failed, ax, short)
    elif len(grid) == 1:
        _line(da, failed, ds[grid[0]], ax, short)
    else:
        _heat_map(da, failed, ds[grid[1]], ds[grid[0]], ax, short)
    ax.set_title("\n".join(textwrap.fill(line, 60) for line in title.split("\n")), fontsize="small")
    return ax


def _histogram(da: xr.DataArray, failed: xr.DataArray, ax: Axes, label: str) -> str:
    """A Monte Carlo sweep's values as a histogram; the title's line of how many samples are
    drawn and how many failed."""
    values = np.asarray(da.values, dtype=float).ravel()
    ok = values[np.isfinite(values)]
    ax.hist(ok, bins=max(5, min(40, int(np.sqrt(max(ok.size, 1))) * 2)), color="tab:blue")
    ax.set_xlabel(label)
    ax.set_ylabel("samples")
    return f"\n{ok.size} of {values.size} samples" + (
        f", {int(failed.sum())} failed" if int(failed.sum()) else ""
    )


def _line(da: xr.DataArray, failed: xr.DataArray, x: xr.DataArray, ax: Axes, label: str) -> None:
    """A sweep over one grid axis ``x`` as a line, its failed points marked × on zero."""
    ax.plot(x.values, da.values, marker="o", ms=3, color="tab:blue")
    bad = np.asarray(failed.values, dtype=bool)
    if bad.any():
        ax.plot(x.values[bad], np.zeros(bad.sum()), "x", color="tab:red", label="failed")
        ax.legend(loc="best", fontsize="small")
    ax.set_xlabel(_label(x))
    ax.set_ylabel(label)
    _log_axes(ax, _is_log(x), False)


def _heat_map(
    da: xr.DataArray,
    failed: xr.DataArray,
    x: xr.DataArray,
    y: xr.DataArray,
    ax: Axes,
    label: str,
) -> None:
    """A sweep over two grid axes ``x`` and ``y`` as a heat map, its failed points marked ×."""
    ydim, xdim = str(y.name), str(x.name)
    values = np.asarray(da.transpose(ydim, xdim).values, dtype=float)
    mesh = ax.pcolormesh(
        _edges(x.values, _is_log(x)), _edges(y.values, _is_log(y)), values, shading="flat"
    )
    ax.figure.colorbar(mesh, ax=ax, label=label)
    bad = np.asarray(failed.transpose(ydim, xdim).values, dtype=bool)
    if bad.any():
        yy, xx = np.nonzero(bad)
        ax.plot(x.values[xx], y.values[yy], "x", color="black", ms=4, label="failed")
        ax.legend(loc="upper right", fontsize="small")
    ax.set_xlabel(_label(x))
    ax.set_ylabel(_label(y))
    _log_axes(ax, _is_log(x), _is_log(y))


def sweep_figure(
    ds: xr.Dataset,
    variables: Sequence[str] | None = None,
    *,
    method: str | None = None,
    slow: Sequence[str] = (),
    title: str = "",
) -> Figure:
    """A figure with one panel per variable (default: :func:`default_variables` of ``slow``,
    the model's main slow variables)."""
    import matplotlib.pyplot as plt

    names = list(variables or default_variables(ds, slow))
    cols = 2 if len(names) == 4 else min(3, max(1, len(names)))
    rows = max(1, -(-len(names) // cols))
    fig, axes = plt.subplots(rows, cols, figsize=(4.6 * cols, 3.8 * rows), squeeze=False)
    for ax, name in zip(axes.ravel(), names, strict=False):
        if name in ds:
            plot_sweep_variable(ds, name, method=method, ax=ax)
        else:  # said on the figure rather than dropped: the sweep's results are on disk already
            ax.set_axis_off()
            ax.text(0.5, 0.5, f"no variable {name!r} in this sweep", ha="center", wrap=True)
    for ax in axes.ravel()[len(names) :]:
        ax.set_axis_off()
    done, total = int(ds.attrs.get("points_done", 0)), int(ds.attrs.get("points", 0))
    fig.suptitle(f"{title}  ({done} of {total} points)" if title else "")
    fig.tight_layout()
    return fig


def sweep_png(ds: xr.Dataset, **kwargs: Any) -> bytes:
    """:func:`sweep_figure` as PNG bytes."""
    import matplotlib.pyplot as plt

    fig = sweep_figure(ds, **kwargs)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    plt.close(fig)
    return buf.getvalue()
