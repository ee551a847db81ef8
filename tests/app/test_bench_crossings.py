"""The crossings study of the benchmark: a case scaled in ε keeps its slow horizon, one real
case measured end to end, and its verdicts and table read the figures."""

from __future__ import annotations

import math

import pytest

from tumble.app import bench_crossings as C
from tumble.app.bench_tables import _crossings_table
from tumble.app.bench_verdicts import TARGETS, verdicts


@pytest.mark.parametrize("name", list(C.CASES))
def test_a_case_at_eps_keeps_its_slow_horizon(name):
    example = C.CASES[name]
    req = C.request_at(name, 1e-4)
    if example["model"] == "orbiting_body":
        # Its ε is the spin period over the dissipation's time constant: the run spans as
        # many time constants as the example's.
        days = example["torques"]["dissipation_days"]
        horizon = example["run"]["t_end_days"] / days
        scaled = example["initial"]["spin_period"] / (1e-4 * 86400.0)
        assert math.isclose(req.params.T0 * float(req.tau[-1]) / 86400.0 / scaled, horizon,
                            rel_tol=1e-12)  # fmt: skip
    else:
        end = example["run"].get("tau_end", example["run"].get("t_end"))
        horizon = example["parameters"]["eps"] * end
        assert math.isclose(1e-4 * float(req.tau[-1]), horizon, rel_tol=1e-12)
    assert req.tau.size == C.SAMPLES


def test_one_case_measured(monkeypatch):
    # The rotating field's counter-rotating example at ε = 1e-2 (fast): the figures exist
    # and are consistent with one another.
    monkeypatch.setattr(C, "EPS", (1e-2,))
    monkeypatch.setattr(C, "CASES", {"rf_counter_rotating": C.CASES["rf_counter_rotating"]})
    result = C.crossing_study(1, lambda msg: None)
    r = result["rf_counter_rotating"]["0.01"]
    assert r["speedup"] == pytest.approx(r["full_s"] / r["averaged_s"])
    assert r["error_in_eps"] == pytest.approx(r["error"] / 1e-2)
    assert r["error"] == max(r["errors"].values()) and set(r["errors"]) == {"L", "rho", "T"}
    # Averaging's error at ε = 1e-2 through the separatrix: a few ε (1e-3 run: 6 ε).
    assert r["error_in_eps"] < 30.0


def test_the_verdicts_and_the_table_read_the_figures():
    figures = {"method": "vector", "eps": 1e-4, "full_s": 1.0, "averaged_s": 0.002,
               "speedup": 500.0, "error": 2e-3, "error_in_eps": 20.0, "errors": {"L": 2e-3},
               "t_end": 1.0, "full_nfev": 1, "averaged_nfev": 1}  # fmt: skip
    result = {"averaged_speedup": {}, "batch_throughput": {"threads": {}},
              "crossings": {"x": {"0.0001": figures}}}  # fmt: skip
    rows = {r["what"]: r for r in verdicts(result)}
    error = rows["crossing x ε = 0.0001 (vector): largest slow error over the run / ε"]
    speed = rows["crossing x ε = 0.0001 (vector): speed-up vs full"]
    assert (error["value"], error["met"]) == (20.0, False)
    assert (speed["value"], speed["met"]) == (500.0, True)
    table = _crossings_table({"crossings": result["crossings"], "targets": TARGETS})
    assert table is not None and table.row_count == 1
