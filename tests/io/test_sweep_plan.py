"""Sweep files, points and records without a cluster: keys, grids, draws, failed
points, the Dataset, and that a sweep point is exactly the run ``tumble run`` makes."""

import math
import tomllib
import warnings

import numpy as np
import pytest
import xarray as xr
from files import EXAMPLES
from hypothesis import given
from hypothesis import strategies as st

from tumble.analysis import run
from tumble.analysis.sweep import Axis, Draw, Keep, SweepPlan, records_to_dataset
from tumble.app.sweep import compute_chunk
from tumble.errors import ParameterError, ScenarioError, TumbleWarning
from tumble.io.scenario import parse_scenario, template
from tumble.io.sweep import SweepStore, load_sweep, parse_key, point_scenario, set_key
from tumble.plot.sweep import sweep_png

RM_BASE = (
    template("resisting_medium")
    .replace("tau_end = 400.0", "tau_end = 40.0")
    .replace("samples = 401", "samples = 21")
)


def _write_sweep(tmp_path, body, base=RM_BASE):
    (tmp_path / "base.toml").write_text(base)
    path = tmp_path / "sweep.toml"
    path.write_text('base = "base.toml"\n' + body)
    return path


def test_parse_key_splits_names_and_indices():
    assert parse_key("parameters.b[2][2]") == ("parameters", "b", 2, 2)
    assert parse_key("initial.theta_deg") == ("initial", "theta_deg")
    for bad in ("parameters..eps", "parameters.b[x]", "a b", "parameters.b[2]x"):
        with pytest.raises(ScenarioError, match="not a scenario key"):
            parse_key(bad)


def test_set_key_nested_and_typed():
    data = tomllib.loads(RM_BASE)
    set_key(data, "parameters.b[2][2]", 0.7)
    set_key(data, "run.samples", 11.0)
    assert data["parameters"]["b"][2][2] == 0.7
    assert data["run"]["samples"] == 11 and isinstance(data["run"]["samples"], int)
    with pytest.raises(ScenarioError, match="takes integers"):
        set_key(data, "run.samples", 11.5)
    with pytest.raises(ScenarioError, match="index 3 is outside"):
        set_key(data, "parameters.b[3][0]", 1.0)
    with pytest.raises(ScenarioError, match="has no 'physical'"):
        set_key(data, "physical.k_f", 1.0)


def test_point_scenario_leaves_the_base_alone():
    base = tomllib.loads(RM_BASE)
    point = point_scenario(base, {"parameters.b[0][0]": 0.9, "initial.theta": 0.3})
    assert point["parameters"]["b"][0][0] == 0.9 and base["parameters"]["b"][0][0] == 0.2
    assert point["initial"]["theta"] == 0.3 and base["initial"]["theta"] == 1.0


def test_axis_spacings():
    lin = Axis.spaced("x", "k", "linspace", [0.0, 1.0, 5])
    log = Axis.spaced("x", "k", "logspace", [1e-3, 1e-1, 3])
    np.testing.assert_array_equal(lin.values, np.linspace(0.0, 1.0, 5))
    # logspace takes the end points themselves (numpy's geomspace), not their exponents.
    np.testing.assert_allclose(log.values, [1e-3, 1e-2, 1e-1], rtol=1e-15)
    assert log.scale == "log" and lin.scale == "linear"
    with pytest.raises(ParameterError, match="end points must be > 0"):
        Axis.spaced("x", "k", "logspace", [0.0, 1.0, 3])
    for num in (2.5, 0, math.inf, math.nan, 1e20):  # a grid that cannot be built: one line
        with pytest.raises(ParameterError, match=r"must be an integer in \[1, 1e7\]"):
            Axis.spaced("x", "k", "linspace", [0.0, 1.0, num])


@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 50))
def test_draws_are_reproducible_and_in_range(seed, n):
    draws = (
        Draw("u", "a.u", "uniform", -1.0, 2.0),
        Draw("g", "a.g", "normal", 3.0, 0.5),
        Draw("l", "a.l", "log_uniform", 1e-3, 1e-1),
    )
    a = SweepPlan((), draws, n, seed)
    b = SweepPlan((), draws, n, seed)
    np.testing.assert_array_equal(a.drawn, b.drawn)  # the seed fixes every draw
    assert np.all((a.drawn[:, 0] >= -1.0) & (a.drawn[:, 0] <= 2.0))
    assert np.all((a.drawn[:, 2] >= 1e-3) & (a.drawn[:, 2] <= 1e-1))
    # Adding a variable leaves the draws of the earlier ones unchanged.
    c = SweepPlan((), draws[:1], n, seed)
    np.testing.assert_array_equal(c.drawn[:, 0], a.drawn[:, 0])


def test_normal_draws_have_the_asked_moments():
    plan = SweepPlan((), (Draw("g", "a.g", "normal", 3.0, 0.5),), 20000, 7)
    x = plan.drawn[:, 0]
    # 20000 draws: the standard error of the mean is 0.5/√20000 ≈ 3.5e-3; allow 4 of them.
    assert abs(x.mean() - 3.0) < 4 * 0.5 / math.sqrt(x.size)
    # The standard error of the standard deviation is ≈ σ/√(2n) ≈ 2.5e-3; allow 4.
    assert abs(x.std() - 0.5) < 4 * 0.5 / math.sqrt(2 * x.size)


def test_points_in_c_order_with_samples_last():
    ax1 = Axis("a", "parameters.eps", np.array([1.0, 2.0]))
    ax2 = Axis("b", "parameters.kappa", np.array([10.0, 20.0, 30.0]))
    plan = SweepPlan((ax1, ax2), (Draw("t", "initial.theta", "uniform", 0.0, 1.0),), 4, 3)
    assert plan.dims == ("a", "b", "sample") and plan.shape == (2, 3, 4) and plan.size == 24
    p = plan.assignments(1 * 12 + 2 * 4 + 3)
    assert p["parameters.eps"] == 2.0 and p["parameters.kappa"] == 30.0
    assert p["initial.theta"] == plan.drawn[3, 0]


def test_sweep_file_errors_name_the_key(tmp_path):
    cases = {
        '[[axis]]\nkey = "parameters.eps"\nlinspace = [0.0, 1.0]\n': "expected \\[start",
        '[[axis]]\nkey = "parameters.eps"\n': "exactly one of values",
        '[[axis]]\nkey = "parameters.nope[1]"\nvalues = [1.0]\n': "no 'nope'",
        '[[axis]]\nkey = "parameters.eps"\nvalues = [1.0]\nspacing = 2\n': (
            r"axis\[0\]\.spacing: unknown key"
        ),
        '[keep]\nstability = true\n[[axis]]\nkey = "parameters.eps"\nvalues = [1.0]\n': (
            "declares no stationary motion"
        ),
        "[keep]\nfinal = true\n": "at least one axis",
        '[monte_carlo]\nsamples = 3\nseed = 1\n[[monte_carlo.draw]]\nkey = "initial.k"\n'
        "log_uniform = [0.0, 1.0]\n": "0 < low",
        '[[axis]]\nkey = "parameters.eps"\nvalues = [1.0]\n[[axis]]\nkey = "parameters.eps"\n'
        "values = [2.0]\n": "swept twice",
    }
    for body, message in cases.items():
        with pytest.raises(ScenarioError, match=message):
            load_sweep(_write_sweep(tmp_path, body))
    bad_base = RM_BASE.replace("kappa = 0.5", "kappa = 7.0")
    with pytest.raises(ScenarioError, match=r"base scenario .*kappa"):
        load_sweep(
            _write_sweep(tmp_path, '[[axis]]\nkey = "parameters.eps"\nvalues = [1]\n', bad_base)
        )


def test_a_sweep_point_is_the_run_tumble_run_makes(tmp_path):
    """The batch path and the Dask task change nothing: each record equals a plain run()."""
    sweep = load_sweep(
        _write_sweep(tmp_path, '[[axis]]\nkey = "parameters.b[2][2]"\nvalues = [0.05, 0.3]\n')
    )
    points = [sweep.plan.assignments(i) for i in range(sweep.plan.size)]
    batched = compute_chunk(sweep.base, sweep.source, points, sweep.keep, batch=True)
    single = compute_chunk(sweep.base, sweep.source, points, sweep.keep, batch=False)
    assert [r.get("batch") for r in batched] == [1, 1]
    for p, rb, rs in zip(points, batched, single, strict=True):
        data = point_scenario(sweep.base, p)
        ref = run(parse_scenario(data, sweep.source).request)
        for method, ds in ref.datasets.items():
            for v, value in rb["final"][method].items():
                # Same compiled integrator, same steps: equal to the bit.
                assert value == float(ds[v].values[-1]) == rs["final"][method][v]
        assert rb["differences"] == rs["differences"] == ref.differences
        assert rb["nfev"] == rs["nfev"]


def test_failed_points_are_recorded_with_their_reason(tmp_path):
    # κ = 0 has no averaged method (theory §11): those points fail, the others run.
    sweep = load_sweep(
        _write_sweep(tmp_path, '[[axis]]\nkey = "parameters.kappa"\nvalues = [0.5, 0.0, 2.0]\n')
    )
    points = [sweep.plan.assignments(i) for i in range(3)]
    recs = compute_chunk(sweep.base, sweep.source, points, sweep.keep)
    assert [r["status"] for r in recs] == [0, 1, 1]
    # Both are refused when the scenario is read, before any run (κ = 0 cannot have the
    # averaged method; κ = 2 is outside (−1, 1]).
    for rec in recs[1:]:
        assert rec["reason"].startswith("invalid input") and "kappa" in rec["reason"]
    ds = records_to_dataset(
        sweep.plan,
        dict(enumerate(recs)),
        model="resisting_medium",
        time_name="tau",
        columns=sweep.columns,
    )
    assert ds.attrs["points_failed"] == 2
    assert np.isnan(ds["final_k"].sel(kappa=0.0)).all()
    assert np.isfinite(ds["final_k"].sel(kappa=0.5)).all()


def test_partial_dataset_marks_pending_points_and_round_trips_netcdf(tmp_path):
    sweep = load_sweep(
        _write_sweep(
            tmp_path,
            '[[axis]]\nkey = "parameters.eps"\nlogspace = [0.005, 0.02, 3]\n'
            '[[axis]]\nkey = "initial.theta"\nlinspace = [0.5, 1.0, 2]\n',
        )
    )
    store = SweepStore(tmp_path / "out", sweep)
    points = [sweep.plan.assignments(i) for i in sweep.chunk_points(0)]
    store.write_part(0, compute_chunk(sweep.base, sweep.source, points, sweep.keep))
    recs = store.records()
    ds = records_to_dataset(
        sweep.plan, recs, model="resisting_medium", time_name="tau", columns=sweep.columns
    )
    assert (ds["status"].values.ravel()[: len(points)] == 0).all()
    assert (ds["status"].values.ravel()[len(points) :] == -1).all()
    assert ds["eps"].attrs["scale"] == "log" and ds["theta"].attrs["units"] == "rad"
    assert ds["final_theta"].attrs["units"] == "rad"
    path = store.write_dataset(ds)
    back = xr.load_dataset(path)
    for v in ("status", "final_k", "reason", "difference_k"):
        np.testing.assert_array_equal(back[v].values, ds[v].values)
    assert sweep_png(ds)[:8] == b"\x89PNG\r\n\x1a\n"


def test_another_sweep_in_the_same_directory_is_refused(tmp_path):
    a = load_sweep(_write_sweep(tmp_path, '[[axis]]\nkey = "parameters.eps"\nvalues = [0.01]\n'))
    SweepStore(tmp_path / "out", a)
    b = load_sweep(_write_sweep(tmp_path, '[[axis]]\nkey = "parameters.eps"\nvalues = [0.02]\n'))
    with pytest.raises(ScenarioError, match="holds another sweep"):
        SweepStore(tmp_path / "out", b)


def test_keep_verify_and_stability_figures(tmp_path):
    base = (
        template("rotating_field")
        .replace("tau_end = 300.0", "tau_end = 60.0")
        .replace("samples = 601", "samples = 31")
        .replace('regime = "x1"', 'regime = "x3"')
    )
    sweep = load_sweep(
        _write_sweep(
            tmp_path,
            '[keep]\nverify = true\n[[axis]]\nkey = "parameters.beta"\nvalues = [0.5, 2.5]\n',
            base,
        )
    )
    assert sweep.keep == Keep(stability=True, verify=True)  # stability: RF has a stationary motion
    points = [sweep.plan.assignments(i) for i in range(2)]
    recs = compute_chunk(sweep.base, sweep.source, points, sweep.keep)
    ds = records_to_dataset(
        sweep.plan,
        dict(enumerate(recs)),
        model="rotating_field",
        time_name="tau",
        columns=sweep.columns,
    )
    assert set(ds["verify_status"].values) <= {"first-order", "degraded", "invalid"}
    assert np.isfinite(ds["verify_error_L"]).all() and np.isfinite(ds["max_real"]).all()
    assert ds["max_real"].attrs["units"] == "1/τ"


def test_kept_series_are_the_runs_columns_and_draw_percentile_bands(tmp_path):
    # [keep] series: each method's column at every sample time, the same numbers a run writes
    # (same integrator: equal to the bit), with a sample dimension the figure draws as bands.
    sweep = load_sweep(
        _write_sweep(
            tmp_path,
            '[monte_carlo]\nsamples = 3\nseed = 4\n[[monte_carlo.draw]]\nkey = "initial.theta"\n'
            'uniform = [0.6, 0.9]\n[keep]\nseries = ["k", "theta"]\n',
        )
    )
    points = [sweep.plan.assignments(i) for i in range(3)]
    recs = compute_chunk(sweep.base, sweep.source, points, sweep.keep)
    ds = records_to_dataset(sweep.plan, dict(enumerate(recs)), model="resisting_medium",
                            time_name="tau", columns=sweep.columns)  # fmt: skip
    assert ds["series_k"].dims == ("sample", "method", "time")
    assert ds["series_theta"].attrs["units"] == "rad"
    for i, p in enumerate(points):
        with warnings.catch_warnings():  # the run's validity warnings: the record keeps them
            warnings.simplefilter("ignore", TumbleWarning)
            ref = run(parse_scenario(point_scenario(sweep.base, p), sweep.source).request)
        for method, dsm in ref.datasets.items():
            got = ds["series_k"].isel(sample=i).sel({"method": method}).values
            np.testing.assert_array_equal(got, dsm["k"].values)
    np.testing.assert_array_equal(ds["time"].values, ref.datasets["averaged"]["tau"].values)
    assert sweep_png(ds)[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_series_the_model_does_not_write_is_refused(tmp_path):
    with pytest.raises(ScenarioError, match=r"keep\.series: 'period' is not a variable"):
        load_sweep(_write_sweep(tmp_path, '[[axis]]\nkey = "parameters.eps"\nvalues = [0.01]\n'
                                '[keep]\nseries = ["period"]\n'))  # fmt: skip


def test_a_physical_sweep_keeps_si_values(tmp_path):
    # Points of an SI scenario have their own time scale T0 = 1/|ω(0)|: the final values and
    # series are kept in SI (the spin period in s, against time in s), comparable across them.
    base = (EXAMPLES / "ob_envisat_like.toml").read_text(encoding="utf-8")
    base = base.replace("t_end_days = 365.0", "t_end_days = 1.0").replace(
        "samples = 366", "samples = 5"
    )
    sweep = load_sweep(_write_sweep(
        tmp_path, '[[axis]]\nkey = "initial.spin_period"\nvalues = [100.0, 150.0]\n'
        '[keep]\nseries = ["period"]\n', base=base))  # fmt: skip
    points = [sweep.plan.assignments(i) for i in range(2)]
    recs = compute_chunk(sweep.base, sweep.source, points, sweep.keep)
    ds = records_to_dataset(sweep.plan, dict(enumerate(recs)), model="orbiting_body",
                            time_name="t", columns=sweep.columns)  # fmt: skip
    assert ds["final_period"].attrs["units"] == "s" and ds["time"].attrs["units"] == "s"
    start = ds["series_period"].sel({"method": "averaged"}).isel(time=0).values
    np.testing.assert_allclose(start, [100.0, 150.0], rtol=1e-12)
    np.testing.assert_allclose(ds["time"].values, np.linspace(0.0, 86400.0, 5), rtol=1e-12)
