"""What ``tumble run`` prints after a run: the table of final values, and the lines of the
differences between methods, the predicted limits and the model's own summary figures, as its
package declares them (:func:`tumble.models.display.summary_lines`).

A scenario given in SI is shown in SI (the files hold both).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
from rich.markup import escape
from rich.table import Table

from tumble.analysis import RunResult
from tumble.analysis.run import si_time
from tumble.app.runner import in_si
from tumble.models.display import summary_lines
from tumble.models.schema import si_column
from tumble.plot.labels import with_units

__all__ = ["run_lines", "run_table"]


def run_table(
    result: RunResult, shown: tuple[str, ...], title: str, width: int | None = None
) -> Table:
    """One row per method: form, integrator, wall time [s] and the final value of each
    variable in ``shown`` (in SI for a scenario given in SI). Where that is wider than
    ``width`` (a terminal's columns), the same table transposed, one column per method, so
    that no heading or number is cut."""
    datasets = in_si(result).datasets
    first = next(iter(datasets.values()))
    finals = [with_units(f"final {v}", first[v].attrs.get("units", "")) if v in first
              else f"final {v}" for v in shown]  # fmt: skip
    heads = ["method", "form", "integrator", "wall time [s]", *finals]
    rows = [
        [m, ds.attrs["form"], ds.attrs["integrator"], f"{ds.attrs['wall_time_s']:.3g}",
         *(f"{ds[v].values[-1]:.6g}" if v in ds else "—" for v in shown)]
        for m, ds in datasets.items()
    ]  # fmt: skip
    # Each column as wide as its longest cell or heading, with the borders and padding.
    natural = sum(max(len(h), *(len(r[i]) for r in rows)) + 3 for i, h in enumerate(heads)) + 1
    if width is not None and natural > width:
        heads, rows = (
            ["", *(r[0] for r in rows)],
            [[h, *(r[i] for r in rows)] for i, h in enumerate(heads) if i > 0],
        )
    table = Table(title=title, title_justify="left")
    for col in heads:
        table.add_column(escape(col), no_wrap=True)  # "[s]" is a unit, not rich markup
    for row in rows:
        table.add_row(*(escape(cell) for cell in row))  # a unit in a row's label too
    return table


def run_lines(result: RunResult, shown: tuple[str, ...]) -> list[str]:
    """The lines under the table: the largest difference of each pair of methods, the
    predicted limits of the variables in ``shown``, and the model's own summary figures (the
    lines its package declares)."""
    scaling = result.request.scaling
    first = next(iter(result.datasets.values()), None)

    def value(name: str, x: Any, fmt: str) -> str:
        # In SI, with its unit (an angle's: rad), for a scenario given in SI: the value
        # summary.json gives under the column's SI name (si_column).
        if scaling is None:
            return f"{x:{fmt}}"
        units = (
            str(first[name].attrs.get("units", "")) if first is not None and name in first else ""
        )
        _, factor, unit = si_column(scaling, name, units)[0]
        return f"{x * factor:{fmt}}" + (f" {unit}" if unit not in ("", "1") else "")

    lines = []
    for pair, diffs in result.differences.items():
        text = ", ".join(f"{k} {value(k, v, '.2e')}" for k, v in diffs.items())
        lines.append(f"max |difference| {pair}: {text}")
    lim = result.limits
    if lim:
        text = ", ".join(
            f"{v} → {'undefined' if lim[v] is None else value(v, lim[v], '.6g')}"
            for v in shown
            if v in lim
        )
        note = lim.get("statement") or lim.get("end_state")
        lines.append(f"predicted limits: {text}" + (f" ({note})" if note else ""))
    for method, ds in result.datasets.items():
        if "legs" in ds.attrs:  # a hybrid run or one with asymptotic steps: its legs, at the
            # times summary.json gives
            legs = json.loads(ds.attrs["legs"])
            ends = np.array([t for _, a, b in legs for t in (a, b)])
            if scaling is not None:
                times, unit = si_time(scaling, ends, float(ds["tau"].values[-1]))
                unit = " " + unit
            else:
                times, unit = ends, ""
            text = ", ".join(f"{kind} {times[2 * i]:.6g}–{times[2 * i + 1]:.6g}{unit}"
                             for i, (kind, _, _) in enumerate(legs))  # fmt: skip
            lines.append(f"{method}: legs {text}")
    summary = result.report.summary
    declared = (line.render(summary) for line in summary_lines(result.request.model.name))
    return lines + [text for text in declared if text is not None]
