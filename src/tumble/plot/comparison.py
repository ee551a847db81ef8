"""Comparison figure of the methods of one run (k and ϑ against τ)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import xarray as xr

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_comparison", "plot_methods"]

_STYLE: dict[str, dict[str, Any]] = {
    "full": {"color": "0.35", "lw": 0.8, "label": "full"},
    "averaged": {"color": "tab:blue", "lw": 2.0, "ls": "-", "label": "averaged"},
    "closed_form": {"color": "tab:orange", "lw": 1.2, "ls": "--", "label": "closed form"},
}


def _label(da: xr.DataArray) -> str:
    units = da.attrs.get("units", "")
    eq = da.attrs.get("equation", "")
    name = da.attrs.get("long_name", da.name)
    return f"{name} [{units}]" + (f"  {eq}" if eq and eq != "(1.3)" else "")


def plot_methods(
    datasets: Mapping[str, xr.Dataset],
    variable: str,
    *,
    marks: Sequence[Mapping[str, Any]] = (),
    ax: Axes | None = None,
) -> Axes:
    """Plot one variable of every method against τ on one Axes.

    Parameters
    ----------
    datasets : mapping
        Method name → Dataset with coordinate ``tau``.
    variable : str
        Variable to plot (labels come from its ``attrs``).
    marks : sequence of mappings
        Warnings with ``tau`` and ``condition``; each is drawn as a vertical dotted line.
    ax : Axes, optional
        Where to draw (a new figure if omitted).
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    some = None
    for method, ds in datasets.items():
        if variable in ds:
            some = ds
            style: dict[str, Any] = _STYLE.get(method, {"label": method})
            ax.plot(ds["tau"].values, ds[variable].values, **style)
    for mark in marks:
        ax.axvline(float(mark["tau"]), color="tab:red", ls=":", lw=1.0)
        ax.annotate(
            str(mark["condition"]),
            (float(mark["tau"]), 1.0),
            xycoords=("data", "axes fraction"),
            rotation=90,
            va="top",
            ha="right",
            fontsize=7,
            color="tab:red",
        )
    if some is not None:
        ax.set_xlabel(
            f"{some['tau'].attrs.get('long_name', 'τ')} [{some['tau'].attrs.get('units', '')}]"
        )
        ax.set_ylabel(_label(some[variable]))
    ax.grid(True, alpha=0.3)
    return ax


def plot_comparison(
    datasets: Mapping[str, xr.Dataset],
    *,
    marks: Sequence[Mapping[str, Any]] = (),
    title: str = "",
) -> Figure:
    """Two-panel figure: k and ϑ against τ for every method, warnings marked."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, (ax_k, ax_t) = plt.subplots(2, 1, sharex=True, figsize=(8, 6), layout="constrained")
    plot_methods(datasets, "k", marks=marks, ax=ax_k)
    plot_methods(datasets, "theta", marks=marks, ax=ax_t)
    ax_k.set_xlabel("")
    ax_k.legend(loc="best", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig
