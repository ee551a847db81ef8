"""The second-order targets over the whole range ε = 1e-2 … 3e-4 (a study: marked slow; the
fast tests hold the same on shorter ranges)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _study():
    found = importlib.util.spec_from_file_location(
        "second_order", ROOT / "benchmarks" / "second_order.py"
    )
    module = importlib.util.module_from_spec(found)
    found.loader.exec_module(module)
    return module.measure()


@pytest.mark.slow
def test_slopes_and_errors_over_the_issue_range():
    data = _study()
    for name, case in data.items():
        at = case["eps"].index(1e-3)
        for v, row in case["variables"].items():
            if row["slope_order1"] is None:  # exact for the averaged equations (R)
                continue
            # Measured (rtol 1e-12): order 1 at 1.00–1.05 (±0.25: the uncorrected equations are
            # first order, no better); order 2 at 1.94–2.06, and 2.2–2.5 for the rotating
            # field's triaxial setting over ε = 3e-3 … 1e-4, whose ε³ terms still show at the
            # larger ε (its errors fall faster than ε²): at least second order, −0.25.
            assert abs(row["slope_order1"] - 1.0) <= 0.25, (name, v, row)
            assert row["slope_order2"] >= 2.0 - 0.25, (name, v, row)
            # Absolute, so relative to max(1, |x|) at most this: 9.7e-6 (σ) at ε = 1e-3.
            assert row["errors_order2"][at] <= 1e-5, (name, v, row)
