"""Comparison figure of the methods of one run (k and ϑ against τ)."""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import xarray as xr
from matplotlib.ticker import LogFormatter

from tumble.plot.labels import with_units

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["mark_warnings", "plot_comparison", "plot_methods"]

_STYLE: dict[str, dict[str, Any]] = {
    "full": {"color": "0.35", "lw": 0.8, "label": "full"},
    "averaged": {"color": "tab:blue", "lw": 2.0, "ls": "-", "label": "averaged"},
    "closed_form": {"color": "tab:orange", "lw": 1.2, "ls": "--", "label": "closed form"},
}


def _label(da: xr.DataArray) -> str:
    units = da.attrs.get("units", "")
    eq = da.attrs.get("equation", "")
    name = da.attrs.get("long_name", da.name)
    # A dimensionless quantity has no unit to show; the paper's equation number, where the
    # column has one, follows the name (a reference to a theory page does not).
    text = with_units(name, units)
    if eq.startswith("(") and eq != "(1.3)":
        text += f"  {eq.split(';')[0].split(', docs/')[0]}"
    return textwrap.fill(text, 32)  # long names on two lines, so stacked panels do not collide


def mark_warnings(ax: Axes, marks: Sequence[Mapping[str, Any]]) -> None:
    """Draw each warning (``tau``, ``condition``) as a labelled vertical dotted line."""
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
    mark_warnings(ax, marks)
    if some is not None:
        tau = some["tau"].attrs
        ax.set_xlabel(with_units(tau.get("long_name", "τ"), tau.get("units", "")))
        ax.set_ylabel(_label(some[variable]))
    ax.grid(True, alpha=0.3)
    return ax


def plot_comparison(
    datasets: Mapping[str, xr.Dataset],
    *,
    variables: Sequence[str] = ("k", "theta"),
    diagnostics: xr.Dataset | None = None,
    marks: Sequence[Mapping[str, Any]] = (),
    title: str = "",
    log: Sequence[str] = (),
) -> Figure:
    """One panel per variable against τ for every method, warnings marked.

    Parameters
    ----------
    datasets : mapping
        Method name → Dataset.
    variables : sequence of str
        Variables to draw, one panel each.
    diagnostics : Dataset, optional
        Extra per-sample quantities of the averaged run (e.g. fast frequencies), drawn
        together in a last panel.
    marks : sequence of mappings
        Warnings with ``tau`` and ``condition``.
    title : str
        Figure title.
    log : sequence of str
        Variables drawn on a logarithmic axis (a spin period over years).
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    n = len(variables) + (diagnostics is not None)
    fig, axes = plt.subplots(
        n, 1, sharex=True, figsize=(8, 2.0 + 2.0 * n), layout="constrained", squeeze=False
    )
    axs = list(axes[:, 0])
    for ax, var in zip(axs, variables, strict=False):
        plot_methods(datasets, var, marks=marks, ax=ax)
        if var in log:
            ax.set_yscale("log")
            # Plain numbers (140, 1e-05) rather than matplotlib's 1.4×10² in mathtext, whose
            # parser costs a warm run 0.4 s the first time it draws one.
            ax.yaxis.set_major_formatter(LogFormatter())
            ax.yaxis.set_minor_formatter(LogFormatter(labelOnlyBase=False))
    if diagnostics is not None:
        ax = axs[-1]
        for name in diagnostics.data_vars:
            da = diagnostics[name]
            ax.plot(diagnostics["tau"].values, da.values, lw=1.2, label=da.attrs["long_name"])
        first = next(iter(diagnostics.data_vars.values()))
        ax.set_ylabel(with_units("averaged run", first.attrs["units"]))
        tau = diagnostics["tau"].attrs
        ax.set_xlabel(with_units(tau["long_name"], tau["units"]))
        ax.legend(loc="best", fontsize=8)
        ax.grid(True, alpha=0.3)
    for ax in axs[:-1]:
        ax.set_xlabel("")
    axs[0].legend(loc="best", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig
