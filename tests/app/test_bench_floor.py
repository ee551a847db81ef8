"""The floor study of the averaged runs: its integration alone is the run's integration, one
case is measured end to end, and its table and verdict read the figures."""

from __future__ import annotations

import numpy as np
import pytest

from tumble.app import bench_floor as F
from tumble.integrate import simulate
from tumble.integrate.simulate import integrator_named


@pytest.mark.parametrize(
    ("source", "name", "eps", "tol"),
    [
        # Time breakpoints with the passage's restart maps: the two integrations start their
        # pieces from different first steps, each at rtol 1e-10 (5.7e-11 measured).
        ("crossing", "a3_negative", 1e-4, 1e-9),
        # A terminal surface and its restart: k² near the separatrix magnifies a difference in
        # the energy by 1/(1 − k²) (6.8e-7 measured).
        ("template", "rotating_field", 1e-3, 1e-5),
        # One piece, the same steps: round-off (1.6e-14 measured).
        ("template", "nonlinear_moment", 1e-3, 1e-12),
    ],
)
def test_the_integration_alone_is_the_runs(source, name, eps, tol):
    req = F._request(source, name, eps)
    model, p, st, tau = req.model, req.params, req.initial, req.tau
    avg = model.averaged.form(p, st, model.averaged.check(req.averaging))
    kernel = integrator_named("auto").averaged_kernel(avg, p)
    y0 = np.asarray(avg.initial_state(p, st), dtype=float)
    Y, nfev = F._pieces(avg, kernel, y0, tau)()
    assert np.all(np.isfinite(Y))  # every sample filled, across the stops and restarts
    cols = avg.to_columns(p, st, tau, Y)
    run = simulate(model, p, st, tau, "averaged", rtol=F.RTOL, atol=F.ATOL,
                   averaging=req.averaging)  # fmt: skip
    assert abs(nfev - run.nfev) <= 0.05 * run.nfev  # the same run, up to its pieces' starts
    for key, values in run.columns.items():
        if key == "sigma":  # an azimuth: the run takes it within π of the start
            continue
        scale = max(1.0, float(np.max(np.abs(values))))
        assert np.max(np.abs(cols[key] - values)) <= tol * scale, key


def test_one_case_measured_and_tabled(monkeypatch):
    monkeypatch.setattr(F, "CASES", (("template", "nonlinear_moment", 1e-2, 100.0),))
    result = F.floor_study(1, lambda msg: None)
    r = result["nonlinear_moment"]["0.01"]
    assert r["budget_s"] == pytest.approx(r["full_s"] / 100.0)
    assert r["evaluations_s"] == pytest.approx(r["run_nfev"] * r["eval_us"] * 1e-6)
    assert r["floor_s"] == pytest.approx(r["evaluations_s"] + r["columns_s"])
    assert r["floor_over_budget"] == pytest.approx(r["floor_s"] / r["budget_s"])
    assert 0.0 < r["evaluations_s"] < r["integration_s"]  # the integrator does more than evaluate
    table = F.markdown(result)
    assert table.count("\n") == 2 and "nonlinear_moment (template) | 0.01 | 100×" in table
    over = {"nonlinear_moment": {"0.01": {**r, "floor_over_budget": 1.5}}}
    assert F.over_budget(over) == ["nonlinear_moment at ε = 0.01"]
    assert F.over_budget({"nonlinear_moment": {"0.01": {**r, "floor_over_budget": 0.5}}}) == []
