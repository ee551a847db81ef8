"""The figure of ``tumble verify``: error curves of each slow variable at ε, ε/2, ε/4 against
the slow time, and the maximum errors against ε with their fitted order."""

from __future__ import annotations

import math
import textwrap
from typing import TYPE_CHECKING

import numpy as np

from tumble.analysis.verify import VerifyResult

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot_verify"]

_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown")


def plot_verify(result: VerifyResult, *, title: str = "") -> Figure:
    """One panel per slow variable (|full − averaged| against εt, log scale, one curve per ε)
    and a last panel of max error against ε (log–log) with the fitted orders and a slope-1
    guide; validity issues of the scenario's run are dotted lines at their slow time.

    Parameters
    ----------
    result : VerifyResult
    title : str
        Figure title; the verdict is printed below it.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    names = list(result.variables)
    slow = bool(result.eps[0] > 0.0)  # ε = 0: a closed form against time, no ε axis
    n = len(names) + int(slow)
    ncols = min(3, n)
    nrows = math.ceil(n / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.2 * nrows), squeeze=False)
    flat = axes.ravel()
    symbol = {"tau": "τ"}.get(result.time_name, result.time_name)
    marks = result.issues[0] if result.issues else []
    for ax, v in zip(flat, names, strict=False):
        for i, (e, curves) in enumerate(zip(result.eps, result.curves, strict=True)):
            if v not in curves:
                continue
            s, d = curves[v]
            d = np.where(d > 0.0, d, np.nan)  # exact zeros (samples at t = 0) off the log axis
            label = f"ε = {e:.3g}" if slow else "|full − closed form|"
            ax.semilogy(s, d, color=_COLOURS[i % len(_COLOURS)], lw=0.8, label=label)
        for mark in marks:
            ax.axvline(result.eps[0] * float(mark["tau"]), color="tab:red", ls=":", lw=1.0)
        ax.set_title(f"|Δ{v}|", fontsize=10)
        ax.set_xlabel(f"slow time ε{symbol}" if slow else f"time {symbol}")
        ax.grid(True, which="both", alpha=0.3)
    flat[0].legend(fontsize=8)
    if slow:
        _orders_panel(flat[len(names)], result)
    for extra in flat[n:]:
        extra.set_visible(False)
    head = title + ("\n" if title else "") + textwrap.fill(result.verdict, 110)
    fig.suptitle(head, fontsize=10)
    fig.tight_layout()
    return fig


def _orders_panel(ax: Axes, result: VerifyResult) -> None:
    """Max error against ε on log–log axes, the fitted orders, and a slope-1 guide."""
    names = list(result.variables)
    for i, v in enumerate(names):
        err = result.errors[v]
        ok = np.isfinite(err) & (err > 0.0)
        if not np.any(ok):
            continue
        order = result.orders.get(v)
        label = f"{v}: order {order:.2f}" if order is not None else f"{v}: at tolerance"
        ax.loglog(result.eps[ok], err[ok], "o-", color=_COLOURS[i % len(_COLOURS)], label=label)
    finite = [e for e in result.errors.values() if np.any(np.isfinite(e) & (e > 0))]
    if finite:
        top = max(float(np.nanmax(e)) for e in finite)
        guide = top * result.eps / result.eps[0]
        ax.loglog(result.eps, guide, "k--", lw=0.8, label="slope 1")
    ax.set_xlabel("ε")
    ax.set_title("max error against ε", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
