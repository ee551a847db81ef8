"""Stability maps: the classification and the leading real part over a parameter grid.

Draws datasets of :func:`tumble.analysis.stability.stability_grid` (e.g. the maps of
:mod:`tumble.analysis.stability_maps`). Labels, class names and the title come from the
dataset's ``attrs``; nothing is computed here but colour scales.
"""

from __future__ import annotations

import io
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from tumble.plot.labels import with_units

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = [
    "plot_classification",
    "plot_leading_real_part",
    "plot_stability_map",
    "stability_map_bytes",
]

_CLASS_COLOURS = {
    "asymptotically stable": "#2ca25f",
    "critical": "#fdae3b",
    "unstable": "#de2d26",
}
_OUTSIDE_COLOUR = "#d9d9d9"


def _label(da: xr.DataArray) -> str:
    name = da.attrs.get("long_name", da.name)
    units = da.attrs.get("units", "")
    return with_units(name, units)


def _is_log(da: xr.DataArray) -> bool:
    return da.attrs.get("scale") == "log"


def _edges(values: np.ndarray, log: bool) -> np.ndarray:
    """Cell edges around grid points: midpoints, in log space for a log axis."""
    v = np.log(values) if log else np.asarray(values, dtype=float)
    if v.size == 1:
        e = np.array([v[0] - 0.5, v[0] + 0.5])
    else:
        mid = 0.5 * (v[1:] + v[:-1])
        e = np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])
    return np.exp(e) if log else e


def _grid(ds: xr.Dataset, name: str) -> tuple[xr.DataArray, xr.DataArray, xr.DataArray]:
    da = ds[name]
    ydim, xdim = da.dims
    return da, ds[xdim], ds[ydim]


def _class_legend(ds: xr.Dataset) -> list[tuple[int, str, str]]:
    """(code, label, colour) of every class, from the flag attributes of ``classification``."""
    da = ds["classification"]
    flags = da.attrs["flag_values"]
    codes = [int(v) for v in (flags.split() if isinstance(flags, str) else np.ravel(flags))]
    meanings = str(da.attrs["flag_meanings"]).split()
    out = []
    for code, meaning in zip(codes, meanings, strict=True):
        text = meaning.replace("_", " ")
        if code < 0:
            out.append((code, str(ds.attrs.get("outside_domain_label", text)), _OUTSIDE_COLOUR))
        else:
            out.append((code, text, _CLASS_COLOURS.get(text, "tab:blue")))
    return out


def _axes_labels(ax: Axes, x: xr.DataArray, y: xr.DataArray) -> None:
    ax.set_xlabel(_label(x))
    ax.set_ylabel(_label(y))
    if _is_log(x):
        ax.set_xscale("log")
    if _is_log(y):
        ax.set_yscale("log")


def plot_classification(ds: xr.Dataset, *, ax: Axes | None = None) -> Axes:
    """Categorical map of ``classification`` with a legend of the classes.

    Parameters
    ----------
    ds : xarray.Dataset
        A stability grid (``classification`` with ``flag_values``/``flag_meanings``).
    ax : Axes, optional
        Where to draw (a new figure if omitted).
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    if ax is None:
        _, ax = plt.subplots()
    da, x, y = _grid(ds, "classification")
    legend = _class_legend(ds)
    codes = [c for c, _, _ in legend]
    cmap = ListedColormap([colour for _, _, colour in legend])
    bounds = [codes[0] - 0.5, *(c + 0.5 for c in codes)]
    ax.pcolormesh(
        _edges(x.values, _is_log(x)),
        _edges(y.values, _is_log(y)),
        np.asarray(da.values, dtype=float),
        cmap=cmap,
        norm=BoundaryNorm(bounds, cmap.N),
    )
    _axes_labels(ax, x, y)
    ax.set_title(str(da.attrs.get("long_name", "classification")), fontsize=9)
    ax.legend(
        handles=[
            Patch(facecolor=colour, edgecolor="0.4", label=text) for _, text, colour in legend
        ],
        loc="upper center",
        bbox_to_anchor=(0.5, -0.14),
        ncol=2,
        fontsize=8,
        frameon=False,
    )
    return ax


def _linthresh(values: np.ndarray, floor: float) -> float:
    """Linear band of the symmetric-log scale: about the smallest non-critical |Re λ|."""
    mag = np.abs(values[np.isfinite(values)])
    mag = mag[mag > floor]
    if mag.size == 0:
        return 1e-3
    return float(10.0 ** np.floor(np.log10(np.percentile(mag, 5))))


def plot_leading_real_part(ds: xr.Dataset, *, ax: Axes | None = None) -> Axes:
    """Map of ``max_real`` on a symmetric-log diverging scale centred on 0.

    The values range from −O(ε) (stable) to +O(1) (middle axis); the linear band of the scale
    is set near the smallest non-critical |value|, so both ends stay readable.

    Parameters
    ----------
    ds : xarray.Dataset
        A stability grid with ``max_real`` (NaN outside the domain).
    ax : Axes, optional
        Where to draw (a new figure if omitted).
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import SymLogNorm

    if ax is None:
        _, ax = plt.subplots()
    da, x, y = _grid(ds, "max_real")
    values = np.asarray(da.values, dtype=float)
    finite = values[np.isfinite(values)]
    top = float(np.max(np.abs(finite))) if finite.size else 1.0
    lin = _linthresh(values, float(ds.attrs.get("critical_tol", 0.0)))
    top = max(top, 10.0 * lin)
    cmap = plt.get_cmap("RdBu_r").with_extremes(bad=_OUTSIDE_COLOUR)
    mesh = ax.pcolormesh(
        _edges(x.values, _is_log(x)),
        _edges(y.values, _is_log(y)),
        np.ma.masked_invalid(values),
        cmap=cmap,
        norm=SymLogNorm(linthresh=lin, linscale=0.5, vmin=-top, vmax=top, base=10),
    )
    ax.figure.colorbar(mesh, ax=ax, label=_label(da), shrink=0.9)
    _axes_labels(ax, x, y)
    ax.set_title(str(da.attrs.get("long_name", "max_real")), fontsize=9)
    return ax


def _title(ds: xr.Dataset) -> str:
    parts = [str(ds.attrs.get("model", "")), str(ds.attrs.get("motion", ""))]
    head = ": ".join(p for p in parts if p)
    fixed = ds.attrs.get("fixed_parameters")
    return f"{head} — {fixed}" if fixed else head


def plot_stability_map(
    ds: xr.Dataset, *, axes: tuple[Axes, Axes] | None = None, title: str | None = None
) -> Figure:
    """Two panels: the classification and the leading real part max Re λ.

    Parameters
    ----------
    ds : xarray.Dataset
        A stability grid (``classification``, ``max_real`` on two coordinates whose ``attrs``
        give ``long_name``, ``units`` and optionally ``scale = "log"``).
    axes : (Axes, Axes), optional
        Where to draw (a new figure if omitted).
    title : str, optional
        Figure title (default: the model, the motion and ``attrs["fixed_parameters"]``).

    Returns
    -------
    Figure
    """
    if axes is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11.5, 5.2), layout="constrained")
    else:
        ax0, ax1 = axes
        fig = ax0.figure  # type: ignore[assignment]
    plot_classification(ds, ax=ax0)
    plot_leading_real_part(ds, ax=ax1)
    fig.suptitle(_title(ds) if title is None else title, fontsize=10)
    return fig


def stability_map_bytes(ds: xr.Dataset, fmt: str = "png", **savefig: Any) -> bytes:
    """The figure of :func:`plot_stability_map`, rendered to bytes (``fmt``: png, pdf, svg)."""
    import matplotlib.pyplot as plt

    fig = plot_stability_map(ds)
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format=fmt, dpi=savefig.pop("dpi", 130), **savefig)
    finally:
        plt.close(fig)
    return buf.getvalue()
