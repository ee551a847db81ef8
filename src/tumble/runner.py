"""Scenario in, files out: the library function behind ``tumble run``.

Usable from a notebook::

    from tumble.runner import run_scenario
    result = run_scenario("examples/a3_positive.toml", "out/a3_positive")
"""

from __future__ import annotations

import io
from pathlib import Path

from tumble.analysis import RunResult, run
from tumble.io import load_scenario, render_outputs, write_outputs
from tumble.plot import plot_comparison

__all__ = ["run_scenario"]


def _comparison_png(result: RunResult, title: str) -> bytes:
    import matplotlib.pyplot as plt

    model = result.request.model
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
    files[sc.request.model.figure] = _comparison_png(result, title)
    write_outputs(out_dir, files)
    return result
