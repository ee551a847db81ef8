"""Envelope figure of the nonlinear-moment model: θ(t) of the full motion, its extrema, the
averaged envelope θmax(t), θmin(t), and the pressure profile on a second axis."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from tumble.plot.comparison import mark_warnings
from tumble.plot.labels import with_units

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_envelope"]


def plot_envelope(
    datasets: Mapping[str, xr.Dataset],
    *,
    extrema: Sequence[Sequence[Any]] = (),
    pressure: tuple[np.ndarray, np.ndarray, str] | None = None,
    marks: Sequence[Mapping[str, Any]] = (),
    title: str = "",
    ax: Axes | None = None,
) -> Figure:
    """θ(t) of the full motion with its extrema, and the averaged (or closed-form) envelope.

    Angles are drawn in degrees.

    Parameters
    ----------
    datasets : mapping
        Method → Dataset (``full`` and ``closed_form`` with ``theta``; ``averaged`` with
        ``theta_max``, ``theta_min``), coordinate ``tau`` whose ``attrs['name']`` is the time.
    extrema : sequence of rows
        ``(kind, k, t, theta, ...)`` of the full motion (the ``full_extrema`` table).
    pressure : (t, values, label), optional
        Drawn on a second y axis (e.g. the dynamic pressure q(t) [Pa] or Q(τ)/Q(0)).
    marks : sequence of mappings
        Warnings with ``tau`` and ``condition``: vertical dotted lines.
    title : str
        Figure title.
    ax : Axes, optional
        Where to draw (a new figure if omitted).

    Returns
    -------
    Figure
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(9, 4.8), layout="constrained")
    fig: Any = ax.figure
    time_attrs = _draw_theta(ax, datasets, extrema)
    mark_warnings(ax, marks)
    ax.set_xlabel(with_units(f"time {time_attrs.get('name', 't')}", time_attrs.get("units", "")))
    ax.set_ylabel("nutation angle θ [deg]")
    ax.grid(True, alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    if pressure is not None:
        t, values, label = pressure
        ax2 = ax.twinx()
        (line,) = ax2.plot(t, values, color="tab:green", lw=1.2, label=label)
        ax2.set_ylabel(label, color="tab:green")
        handles.append(line)
        labels.append(label)
    ax.legend(
        handles,
        labels,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.14),
        ncol=3,
        fontsize=8,
        frameon=False,
    )
    if title:
        ax.set_title(title, fontsize=10)
    return fig


def _draw_theta(
    ax: Axes, datasets: Mapping[str, xr.Dataset], extrema: Sequence[Sequence[Any]]
) -> dict[str, Any]:
    """θ(t) full and closed form, the full extrema and the averaged envelope, in degrees;
    the attrs of the time coordinate."""
    deg = 180.0 / np.pi
    time_attrs: dict[str, Any] = {}
    if "full" in datasets:
        ds = datasets["full"]
        time_attrs = dict(ds["tau"].attrs)
        ax.plot(
            ds["tau"].values, deg * ds["theta"].values, color="0.55", lw=0.6, label="θ(t), full"
        )
    if "closed_form" in datasets:
        ds = datasets["closed_form"]
        time_attrs = dict(ds["tau"].attrs)
        ax.plot(
            ds["tau"].values,
            deg * ds["theta"].values,
            color="tab:orange",
            lw=1.0,
            ls="--",
            label="θ(t), closed form (1.9)",
        )
    for kind, marker in (("max", "v"), ("min", "^")):
        pts = [(float(r[2]), float(r[3])) for r in extrema if r[0] == kind]
        if pts:
            t, th = np.array(pts).T
            ax.plot(t, deg * th, marker, ms=3, color="k", ls="none", label=f"θ{kind}, full")
    if "averaged" in datasets:
        ds = datasets["averaged"]
        time_attrs = dict(ds["tau"].attrs)
        for name, ls in (("theta_max", "-"), ("theta_min", "--")):
            ax.plot(
                ds["tau"].values,
                deg * ds[name].values,
                color="tab:blue",
                lw=1.8,
                ls=ls,
                label=f"θ{name[-3:]}, averaged (2.2)",
            )
    return time_attrs
