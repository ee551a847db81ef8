"""Figures of the checked claims: draw a :class:`~tumble.analysis.claims.base.FigureSpec`.

The claim functions of :mod:`tumble.analysis.claims` describe their figures as data (panels of
series, reference lines, scales, ticks); this module turns such a description into a
matplotlib figure. Nothing here computes physics.

Each panel is drawn in its own sub-figure of a grid of ``layout.ncols`` columns. A panel of kind
``"envelope"`` is drawn by :func:`tumble.plot.plot_envelope` into the panel's axes, and one of
kind ``"stability_map"`` by :func:`tumble.plot.plot_stability_map` into two axes side by side
(the classification and max Re λ), both with ``panel.data`` as their keyword arguments; both
functions accept the axes to draw into, so a delegated panel can share a figure with others.
"""

from __future__ import annotations

import io
from typing import TYPE_CHECKING, Any

from tumble.plot.envelope import plot_envelope
from tumble.plot.stability import plot_stability_map

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure, SubFigure

    from tumble.analysis.claims.base import FigureSpec, Panel, Series

__all__ = ["claim_figure", "claim_png"]

_STYLES: dict[str, dict[str, Any]] = {
    "line": {"ls": "-", "lw": 1.2},
    "dashed": {"ls": "--", "lw": 1.2},
    "dotted": {"ls": ":", "lw": 1.2},
    "markers": {"ls": "none", "marker": "o", "ms": 3.5},
    "line+markers": {"ls": "-", "lw": 1.0, "marker": "o", "ms": 4.0},
}
_REFERENCE_COLOURS = ("k", "tab:red", "tab:green", "tab:purple", "tab:brown")
"""Colours of labelled reference lines, in turn (unlabelled ones are grey)."""

PNG_DPI = 110


def _draw_series(ax: Axes, series: Series, colour: Any) -> Any:
    """Draw one series; return the colour it got."""
    label = series.label or None
    if series.style == "bar":
        bars = ax.bar(series.x, series.y, label=label, color=colour)
        return bars.patches[0].get_facecolor() if bars.patches else colour
    kwargs = dict(_STYLES[series.style])
    if colour is not None:
        kwargs["color"] = colour
    (line,) = ax.plot(series.x, series.y, label=label, **kwargs)
    return line.get_color()


def _draw_lines(ax: Axes, panel: Panel) -> None:
    """A panel of kind "lines": series, reference lines, scales, ticks, legend."""
    previous: Any = None  # colour of the last labelled series
    for s in panel.series:
        # An unlabelled series drawn right after a labelled one belongs to it (the dots of an
        # integration over a closed-form curve, the averaged curve of a full run): same colour.
        colour = _draw_series(ax, s, None if s.label else previous)
        previous = colour if s.label else None
    turn = 0
    for values, draw in ((panel.hlines, ax.axhline), (panel.vlines, ax.axvline)):
        for value, label in values:
            if label:
                colour = _REFERENCE_COLOURS[turn % len(_REFERENCE_COLOURS)]
                turn += 1
                draw(value, color=colour, ls=":", lw=1.0, label=label)
            else:
                draw(value, color="0.35", ls=":", lw=0.8)
    ax.set_xscale(panel.xscale)
    ax.set_yscale(panel.yscale)
    if panel.xticks is not None:
        positions = [float(v) for v, _ in panel.xticks]
        labels = [text for _, text in panel.xticks]
        long = max((len(text) for text in labels), default=0) > 6
        ax.set_xticks(positions, labels, rotation=20 if long else 0, fontsize=7)
    ax.set(xlabel=panel.xlabel, ylabel=panel.ylabel)
    if panel.title:
        ax.set_title(panel.title, fontsize=9)
    if any(s.label for s in panel.series) or any(
        label for _, label in (*panel.hlines, *panel.vlines)
    ):
        ax.legend(fontsize=7)


def _draw_panel(sub: SubFigure, panel: Panel) -> None:
    if panel.kind == "lines":
        _draw_lines(sub.subplots(), panel)
    elif panel.kind == "envelope":
        ax = sub.subplots()
        plot_envelope(**panel.data, ax=ax)
        if panel.title:
            ax.set_title(panel.title, fontsize=9)
    elif panel.kind == "stability_map":
        ax0, ax1 = sub.subplots(1, 2)
        plot_stability_map(**panel.data, axes=(ax0, ax1))
        if panel.title:
            sub.suptitle(panel.title, fontsize=9)
    else:
        raise ValueError(
            f"panel.kind = {panel.kind!r} is not one of 'lines', 'envelope', 'stability_map'"
        )


def claim_figure(layout: FigureSpec) -> Figure:
    """Draw the figure of a claim.

    Parameters
    ----------
    layout : FigureSpec
        Panels (in rows of ``layout.ncols``) and the figure title.

    Returns
    -------
    matplotlib.figure.Figure
        A figure not registered with pyplot (it is freed with the object; nothing to close).

    Notes
    -----
    Series styles: ``line``, ``dashed``, ``dotted``, ``markers``, ``line+markers``, ``bar``.
    Each labelled series takes the next colour of the cycle; an unlabelled series right after
    a labelled one takes that one's colour, other unlabelled series the next colour.
    Reference lines (``hlines``, ``vlines``) are dotted: labelled ones black, red, green … in
    turn and listed in the legend, unlabelled ones grey. A legend is drawn only when the panel
    has a label. ``"envelope"`` and ``"stability_map"`` panels are drawn by
    :func:`tumble.plot.plot_envelope` and :func:`tumble.plot.plot_stability_map` (two axes)
    with ``panel.data`` as keyword arguments.
    """
    from matplotlib.figure import Figure

    if not layout.panels:
        raise ValueError("layout.panels is empty: a figure needs at least one panel")
    ncols = max(1, min(layout.ncols, len(layout.panels)))
    nrows = -(-len(layout.panels) // ncols)
    # A stability map is two maps with a colour bar: give its column the room of two panels.
    wide = any(p.kind == "stability_map" for p in layout.panels)
    width = 11.0 if wide else (7.0 if ncols == 1 else 5.0)
    height = 4.6 if ncols == 1 else 4.2
    fig = Figure(figsize=(width * ncols, height * nrows), layout="constrained")
    subs = fig.subfigures(nrows, ncols, squeeze=False).ravel()
    for sub, panel in zip(subs, layout.panels, strict=False):
        _draw_panel(sub, panel)
    if layout.title:
        fig.suptitle(layout.title, fontsize=10)
    return fig


def claim_png(layout: FigureSpec) -> bytes:
    """The figure of :func:`claim_figure` as PNG bytes (110 dpi).

    Parameters
    ----------
    layout : FigureSpec
        The figure to draw.

    Returns
    -------
    bytes
        The PNG file.
    """
    buf = io.BytesIO()
    claim_figure(layout).savefig(buf, format="png", dpi=PNG_DPI)
    return buf.getvalue()
