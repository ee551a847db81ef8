"""Scenario in, files out: the library function behind ``tumble run``.

Usable from a notebook::

    from tumble.runner import run_scenario
    result = run_scenario("examples/a3_positive.toml", "out/a3_positive")
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import numpy as np

from tumble.analysis import RunResult, run
from tumble.io import load_scenario, render_outputs, write_outputs
from tumble.plot import plot_comparison, plot_envelope

__all__ = ["run_scenario"]


def _pressure_curve(result: RunResult) -> tuple[Any, Any, str] | None:
    """a(t)/a(0) = Q(εt)/Q(0) of a perturbed nonlinear-moment run whose pressure varies."""
    for ds in result.datasets.values():
        if "a" in ds and ds["a"].values[0] != 0.0 and np.ptp(ds["a"].values) > 0.0:
            return ds["tau"].values, ds["a"].values / ds["a"].values[0], "Q(εt)/Q(0) = a(t)/a(0)"
    return None


def _figure_png(result: RunResult, title: str) -> bytes:
    import matplotlib.pyplot as plt

    model = result.request.model
    if model.plot_kind == "envelope":
        _header, rows = result.report.tables.get("full_extrema", ((), []))
        fig = plot_envelope(
            result.datasets,
            extrema=rows,
            pressure=_pressure_curve(result),
            marks=result.issues,
            title=title,
        )
    else:
        fig = plot_comparison(
            result.datasets,
            variables=model.plot_variables,
            diagnostics=result.diagnostics.get("averaged"),
            marks=result.issues,
            title=title,
        )
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=130)
    plt.close(fig)
    return buf.getvalue()


def run_scenario(scenario: str | Path, out_dir: str | Path) -> RunResult:
    """Validate a scenario file, run it, and write its outputs to ``out_dir``.

    Writes ``<method>.csv`` for every method (plus ``<method>_si.csv`` for physical-units
    scenarios and ``averaged_diagnostics.csv`` where the model has diagnostics),
    ``summary.json`` and the model's figure (``comparison.png``, ``evolution.png``). Nothing is
    written unless the whole run succeeds; each file is replaced atomically.

    Parameters
    ----------
    scenario : str or Path
        TOML scenario file.
    out_dir : str or Path
        Output directory (created if needed).

    Returns
    -------
    RunResult
    """
    sc = load_scenario(scenario)
    result = run(sc.request)
    files = render_outputs(result, sc.inputs, sc.source)
    title = f"{sc.request.model.name}: {Path(sc.source).name}"
    files[sc.request.model.figure] = _figure_png(result, title)
    write_outputs(out_dir, files)
    return result
