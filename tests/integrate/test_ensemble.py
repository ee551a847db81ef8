"""Averaged ensembles: simulate_batch(method="averaged") against one simulate() per point."""

from __future__ import annotations

import dataclasses
import tomllib

import numpy as np
import pytest

from tumble.errors import ParameterError, TumbleError
from tumble.integrate import Trajectory, simulate, simulate_batch
from tumble.io.scenario import parse_scenario, template


def _same(batch: Trajectory, single: Trajectory) -> None:
    assert batch.method == "averaged" and batch.integrator == "numba"
    for name, ref in single.columns.items():
        # The same steps (the pieces restart alike); the samples come from the same
        # interpolant evaluated in the loop instead of from the dense output: round-off.
        scale = max(1.0, float(np.max(np.abs(ref))))
        assert np.max(np.abs(batch.columns[name] - ref)) <= 1e-12 * scale, name


def _ensemble(name: str, vary: dict[str, tuple[float, float]], n: int, **section):
    """Requests of the model's template with the ``[initial]`` keys of ``vary`` drawn
    uniformly (seeded) and the other sections updated by ``section``."""
    rng = np.random.default_rng(11)
    out = []
    for _ in range(n):
        data = tomllib.loads(template(name))
        for sec, values in section.items():
            data[sec].update(values)
        for key, (lo, hi) in vary.items():
            data["initial"][key] = float(rng.uniform(lo, hi))
        out.append(parse_scenario(data, f"<{name} ensemble>").request)
    return out


CASES = {
    # The medium: its runs split at an equator crossing of their own.
    "resisting_medium": ({"theta": (0.2, 2.9), "k": (0.5, 2.0)}, {}),
    # The rotating field: a terminal event at the separatrix and the restart past it.
    "rotating_field": ({"rho": (0.2, 2.9), "k2": (0.2, 0.8)}, {}),
    # The nonlinear moment under growing pressure, stopped at the barrier where it reaches it.
    "nonlinear_moment": ({"theta": (0.6, 1.4)}, {"run": {"t_end": 60.0}}),
    # The general engine's triaxial setting on the gravity gradient, compiled.
    "torqued_body": ({"theta": (0.3, 1.2)}, {"run": {"t_end": 100.0}}),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_ensemble_equals_one_run_per_point(name):
    vary, section = CASES[name]
    reqs = _ensemble(name, vary, 12, **section)
    first = reqs[0]
    params, initials = [r.params for r in reqs], [r.initial for r in reqs]
    batch = simulate_batch(first.model, params, initials, first.tau, method="averaged",
                           averaging=first.averaging, threads=2)  # fmt: skip
    assert len(batch) == len(reqs)
    for req, got in zip(reqs, batch, strict=True):
        try:
            single = simulate(req.model, req.params, req.initial, req.tau, "averaged",
                              averaging=req.averaging)  # fmt: skip
        except TumbleError as exc:
            # The point fails alike, with the same message, and the batch goes on.
            assert isinstance(got, TumbleError) and str(got) == str(exc)
            continue
        assert isinstance(got, Trajectory), got
        _same(got, single)


def test_ensemble_results_do_not_depend_on_the_threads():
    vary, section = CASES["resisting_medium"]
    reqs = _ensemble("resisting_medium", vary, 70, **section)  # three blocks
    args = (reqs[0].model, [r.params for r in reqs], [r.initial for r in reqs], reqs[0].tau)
    one = simulate_batch(*args, method="averaged", threads=1)
    two = simulate_batch(*args, method="averaged", threads=2)
    for a, b in zip(one, two, strict=True):
        for name in a.columns:
            assert np.array_equal(a.columns[name], b.columns[name])


def test_an_invalid_point_fails_alone():
    from tumble.models.nonlinear_moment import Pressure

    vary, section = CASES["nonlinear_moment"]
    reqs = _ensemble("nonlinear_moment", vary, 3, **section)
    params = [r.params for r in reqs]
    # A pressure table that ends before the run does: refused before it starts.
    short = Pressure("table", tau=(0.0, 0.1), Q=(1.0, 1.1))
    params[1] = dataclasses.replace(params[1], pressure=short)
    out = simulate_batch(reqs[0].model, params, [r.initial for r in reqs], reqs[0].tau,
                         method="averaged")  # fmt: skip
    assert isinstance(out[0], Trajectory) and isinstance(out[2], Trajectory)
    assert isinstance(out[1], ParameterError) and "pressure" in str(out[1])


def test_slow_of_an_ensemble_member_integrates_it_again():
    vary, section = CASES["resisting_medium"]
    req = _ensemble("resisting_medium", vary, 1, **section)[0]
    (got,) = simulate_batch(req.model, [req.params], [req.initial], req.tau, method="averaged")
    single = simulate(req.model, req.params, req.initial, req.tau, "averaged")
    t = np.linspace(0.0, float(req.tau[-1]), 17)
    for name, values in single.slow(t).items():
        assert np.array_equal(got.slow(t)[name], values)


def test_a_python_right_hand_side_runs_point_by_point():
    # A torque given as a Python function (the scenario's own, wrapped): its triaxial average
    # is the Python engine's, and each point goes through simulate().
    import dataclasses

    from tumble.torques import CallableTorque

    reqs = _ensemble("torqued_body", {}, 2, run={"t_end": 20.0, "samples": 5})
    params = [dataclasses.replace(r.params, torque=CallableTorque(r.params.torque)) for r in reqs]
    out = simulate_batch(reqs[0].model, params, [r.initial for r in reqs], reqs[0].tau,
                         method="averaged", averaging=reqs[0].averaging)  # fmt: skip
    for req, p, got in zip(reqs, params, out, strict=True):
        single = simulate(req.model, p, req.initial, req.tau, "averaged",
                          averaging=req.averaging)  # fmt: skip
        assert got.integrator == single.integrator == "scipy"
        for name, values in single.columns.items():
            assert np.array_equal(got.columns[name], values), name


def test_method_is_checked():
    req = _ensemble("resisting_medium", {}, 1)[0]
    with pytest.raises(ParameterError, match="method"):
        simulate_batch(req.model, [req.params], [req.initial], req.tau, method="closed_form")


def test_runs_that_fail_fail_as_alone():
    from tumble.models import nonlinear_moment as nm

    # Negative pitch damping pumps planar swings up to the barrier of the double well: from
    # θ = 0.6 the run stops at the separatrix; from 0.4 and 0.8 the step size collapses
    # first (the averaged system nears its singular limit): each fails alike, alone.
    p = nm.Params(mu=1.0, a=0.0, b=-1.0, eps=0.05, d=-1.0)
    initials = [nm.State(theta, 0.0, 0.0, 0.0, 0.0, 0.0) for theta in (0.4, 0.6, 0.8)]
    initials.append(nm.State(0.6, 0.0, 0.0, 0.0, 0.0, 0.0))
    params = [p] * 3 + [dataclasses.replace(p, d=0.5)]  # and one that does not fail
    tau = np.linspace(0.0, 400.0, 11)
    out = simulate_batch(nm.MODEL, params, initials, tau, method="averaged")
    messages = []
    for pp, st, got in zip(params, initials, out, strict=True):
        try:
            single = simulate(nm.MODEL, pp, st, tau, "averaged")
        except TumbleError as exc:
            assert isinstance(got, TumbleError) and str(got) == str(exc)
            messages.append(str(exc))
        else:
            _same(got, single)
    assert len(messages) == 3 and "reaches a separatrix" in messages[1]


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_dense_ensemble_equals_one_run_per_point_to_the_bit(name):
    vary, section = CASES[name]
    reqs = _ensemble(name, vary, 6, **section)
    first = reqs[0]
    batch = simulate_batch(first.model, [r.params for r in reqs], [r.initial for r in reqs],
                           first.tau, method="averaged", averaging=first.averaging,
                           threads=2, dense=True)  # fmt: skip
    t = np.linspace(0.0, float(first.tau[-1]), 13)
    for req, got in zip(reqs, batch, strict=True):
        try:
            single = simulate(req.model, req.params, req.initial, req.tau, "averaged",
                              averaging=req.averaging)  # fmt: skip
        except TumbleError as exc:
            assert isinstance(got, TumbleError) and str(got) == str(exc)
            continue
        assert isinstance(got, Trajectory) and got.nfev == single.nfev
        # The same compiled pieces, joined and sampled by the same code: identical bits.
        for key, values in single.columns.items():
            assert np.array_equal(got.columns[key], values), key
        for key, values in single.slow(t).items():
            assert np.array_equal(got.slow(t)[key], values), key


def test_points_with_their_own_time_units_run_together():
    # A physical scenario's points each have their time unit (T0 = 1/|ω0|): the same half day
    # is another τ for each, and the batch takes a row of sample times per point.
    rng = np.random.default_rng(3)
    reqs = []
    for _ in range(4):
        data = tomllib.loads(template("orbiting_body"))
        spin = [float(v * rng.uniform(0.5, 2.0)) for v in data["initial"]["omega_deg_s"]]
        data["initial"]["omega_deg_s"] = spin
        reqs.append(parse_scenario(data, "<orbiting_body ensemble>").request)
    taus = np.stack([r.tau for r in reqs])
    assert not np.array_equal(taus[0], taus[1])
    first = reqs[0]
    params, initials = [r.params for r in reqs], [r.initial for r in reqs]
    for method in ("averaged", "full"):
        n = 4 if method == "averaged" else 2  # the full half day is the slow part
        batch = simulate_batch(first.model, params[:n], initials[:n], taus[:n], method=method,
                               rtol=first.rtol, atol=first.atol, threads=1)  # fmt: skip
        for req, got in zip(reqs, batch, strict=False):
            assert isinstance(got, Trajectory), got
            assert np.array_equal(got.tau, req.tau)
            single = simulate(req.model, req.params, req.initial, req.tau, method,
                              rtol=req.rtol, atol=req.atol, integrator="numba")  # fmt: skip
            if method == "averaged":
                _same(got, single)
            else:  # the same compiled integrator and samples: to the bit
                for name, values in single.columns.items():
                    assert np.array_equal(got.columns[name], values), name
    with pytest.raises(ParameterError, match="3 rows of sample times for 4 points"):
        simulate_batch(first.model, params, initials, taus[:3], method="averaged")
