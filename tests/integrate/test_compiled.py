"""The compiled integrator: its right-hand sides against the models' Python forms,
its steps against scipy's DOP853, the events, the batches, and the disk cache."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from files import EXAMPLES, write
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from strategies import TORQUE_PARAMETERS, angle, inertias, vectors
from typer.testing import CliRunner

from tumble import kernels
from tumble.cli import app
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs
from tumble.errors import IntegrationError, ParameterError
from tumble.integrate import dop853, integrate, simulate
from tumble.io import load_scenario
from tumble.models import nonlinear_moment as nm
from tumble.models import rotating_field as rf
from tumble.rotations import euler313_to_matrix, matrix_to_quat
from tumble.torques import (
    ConstantBodyTorque,
    ConstantInertialTorque,
    EddyCurrentTorque,
    GravityGradientTorque,
    LinearDrag,
    QuadraticDrag,
    UserTorque,
)

runner = CliRunner()
FREE_INERTIA = np.array([1.0, 2.0, 3.0])
FREE_Y0 = np.array([0.3, 1.0, 0.2, 1.0, 0.0, 0.0, 0.0])


def _state(w, psi, theta, phi):
    q = matrix_to_quat(euler313_to_matrix(psi, theta, phi))
    return np.concatenate([w, q])


def _close(a, b, scale):
    # Same formulas, evaluated in another order (the kernels may reassociate sums): a few
    # ulps of the largest term.
    return np.max(np.abs(a - b)) <= 1e-13 * max(1.0, scale)


@settings(max_examples=40, deadline=None)
@given(
    inertia=inertias(),
    w=vectors(2.0),
    psi=angle,
    theta=st.floats(0.0, np.pi),
    phi=angle,
    **TORQUE_PARAMETERS,
)
def test_rigid_body_kernel_matches_the_python_right_hand_side(
    inertia, w, psi, theta, phi, a, B, S, M, n, normal, beta, t
):
    """The kernel reads its packed torque program as the torque's own call does (the same
    compiled terms, reached from Python), every term alone and summed with factors; the terms
    themselves are checked against their formulas in test_torques.py."""
    inertia = np.array(inertia)
    y = _state(w, psi, theta, phi)
    terms = [
        ConstantBodyTorque(a),
        LinearDrag(B),
        QuadraticDrag(S),
        ConstantInertialTorque(M),
        GravityGradientTorque(inertia, n, normal, 0.3),
        EddyCurrentTorque(0.7, 1.3, beta),
    ]
    # The gravity gradient is a difference of products of size 3n²·max I (×2 in the sum);
    # the gyroscopic terms are of size max I·|ω|²: the rounding scale, divided by min I.
    scale = (6.0 * n * n + float(w @ w) + 10.0) * inertia.max() / inertia.min()
    for torque in [*terms, 0.01 * (terms[0] + terms[2]) + 2.0 * terms[4] + terms[5]]:
        kernel = rigid_body_kernel(inertia, torque)
        assert kernel is not None
        expected = rigid_body_rhs(t, y, inertia, torque)
        got = kernels.evaluate_rhs(kernel, t, y)
        assert _close(got, expected, scale), type(torque).__name__


def test_a_python_torque_has_no_kernel():
    user = UserTorque(lambda t, q, w, params: np.zeros(3), {}, "m:f")
    assert rigid_body_kernel(FREE_INERTIA, user) is None
    assert rigid_body_kernel(FREE_INERTIA, LinearDrag(np.eye(3)) + user) is None


@settings(max_examples=40, deadline=None)
@given(inertia=inertias(), beta=st.floats(0.0, np.pi), eps=st.floats(1e-3, 0.5), w=vectors(2.0),
       psi=angle, theta=st.floats(0.0, np.pi), phi=angle)  # fmt: skip
def test_rotating_field_kernel_matches_1_5(inertia, beta, eps, w, psi, theta, phi):
    p = rf.Params(np.array(inertia), beta, eps)
    y = np.concatenate([w, euler313_to_matrix(psi, theta, phi).ravel()])
    expected = rf.full_rhs(0.0, y, p)
    got = kernels.evaluate_rhs(rf.full_kernel(p), 0.0, y)
    assert _close(got, expected, float(np.max(np.abs(expected))))
    y_in = np.concatenate([w, matrix_to_quat(euler313_to_matrix(psi, theta, phi))])
    expected = rf.inertial_rhs(1.7, y_in, p)
    assert _close(kernels.evaluate_rhs(rf.inertial_kernel(p), 1.7, y_in), expected, 1.0)


PRESSURES = [
    nm.Pressure(),
    nm.Pressure("exp"),
    nm.Pressure("table", (-1.0, 0.5, 2.0, 9.0), (0.5, 1.0, 3.0, 4.0)),
]


@settings(max_examples=40, deadline=None)
@given(mu=st.floats(0.2, 2.0), a=st.floats(-2.0, 2.0), b=st.floats(-2.0, 2.0),
       w=vectors(2.0), psi=angle, theta=st.floats(0.01, np.pi - 0.01), phi=angle,
       t=st.floats(0.0, 80.0), which=st.integers(0, 2))  # fmt: skip
def test_nonlinear_moment_kernel_matches_1_1(mu, a, b, w, psi, theta, phi, t, which):
    p = nm.Params(mu=mu, a=a, b=b, eps=0.1, d=0.3, nu=0.2, pressure=PRESSURES[which])
    y = _state(w, psi, theta, phi)
    expected = nm.full_rhs(t, y, p)
    got = kernels.evaluate_rhs(nm.full_kernel(p), t, y)
    assert _close(got, expected, float(np.max(np.abs(expected))))


def test_a_pressure_function_has_no_kernel():
    pressure = nm.Pressure("function", function=np.ones_like, derivative=np.zeros_like)
    assert nm.full_kernel(nm.Params(mu=1.0, a=1.0, b=0.0, eps=0.1, pressure=pressure)) is None


def test_steps_are_scipys():
    """The same method, error norm and step control as scipy's DOP853: the same steps."""
    kernel = rigid_body_kernel(FREE_INERTIA, None)
    res = dop853.solve(kernel, FREE_Y0, 20.0, rtol=1e-10, atol=1e-12)
    ref = solve_ivp(
        lambda t, y: rigid_body_rhs(t, y, FREE_INERTIA, None),
        (0.0, 20.0),
        FREE_Y0,
        method="DOP853",
        rtol=1e-10,
        atol=1e-12,
        dense_output=True,
    )
    assert res.status == 0
    assert res.ts.size == ref.t.size
    # Both count the 3 extra stages of the dense output of every step.
    assert res.nfev == ref.nfev
    # Step sizes differ only by the rounding of the error norm (the kernel may reassociate
    # sums), which the controller turns into relative step changes of ~1e-8 at most.
    assert np.max(np.abs(res.ts - ref.t)) < 1e-6
    # States at the end: both are within the same local errors of the same steps.
    assert np.max(np.abs(res.y - ref.y[:, -1])) < 1e-12
    t = np.linspace(0.0, 20.0, 301)
    assert np.max(np.abs(res(t) - ref.sol(t).T)) < 1e-12


def test_samples_equal_the_dense_output():
    kernel = rigid_body_kernel(FREE_INERTIA, None)
    t = np.linspace(0.0, 20.0, 57)
    dense = dop853.solve(kernel, FREE_Y0, 20.0, rtol=1e-10, atol=1e-12)
    sampled = dop853.solve(
        kernel, FREE_Y0, 20.0, rtol=1e-10, atol=1e-12, t_eval=t, record=False, dense=False
    )
    # The same interpolant evaluated twice: equal to the last bits.
    assert np.max(np.abs(dense(t) - sampled.y_eval)) < 1e-14
    assert np.array_equal(sampled.y_eval[-1], sampled.y)


@pytest.mark.parametrize(
    "example",
    [
        "a3_zero_beta_lt_alpha.toml",
        "quadratic_only.toml",
        "rf_transient_x1.toml",
        "nm_damped_exp.toml",
        "tb_gravity_gradient.toml",
        "tb_inertial_torque.toml",
    ],
)
def test_compiled_and_scipy_runs_agree(example):
    """Each model's default full form, compiled and in Python, over a slow time of the
    example: the difference is the rounding of two evaluation orders carried by the flow."""
    r = load_scenario(EXAMPLES / example).request
    tau = r.tau[r.tau <= min(r.tau[-1], 100.0)]
    runs = {
        i: simulate(r.model, r.params, r.initial, tau, "full", rtol=1e-10, atol=1e-12,
                    integrator=i)
        for i in ("numba", "scipy")
    }  # fmt: skip
    assert runs["numba"].integrator == "numba"
    assert runs["scipy"].integrator == "scipy"
    for name, ref in runs["scipy"].columns.items():
        diff = np.max(np.abs(runs["numba"].columns[name] - ref))
        # Both solutions carry local errors ≤ rtol per step; over ≤ 100 time units the flow
        # amplifies their difference to at most ~1e3·rtol of the column's scale (measured
        # worst 1.4e-7 on the angle ψ ≈ 175 of the resisting-medium example, i.e. 8e-10).
        assert diff <= 1e3 * 1e-10 * max(1.0, float(np.max(np.abs(ref)))), name


def test_extrema_from_events_agree_between_the_integrators():
    """Both integrators locate the extrema of θ as zeros of the full form's event (θ'): the
    compiled one with its own root finder on its dense output, scipy's through solve_ivp's
    events. Both must list the same turning points."""
    r = load_scenario(EXAMPLES / "nm_damped_exp.toml").request
    tau = r.tau[r.tau <= 60.0]
    fast = simulate(r.model, r.params, r.initial, tau, "full", integrator="numba")
    slow = simulate(r.model, r.params, r.initial, tau, "full", integrator="scipy")
    a, b = nm.extrema(fast, r.params), nm.extrema(slow, r.params)
    assert len(a) == len(b) > 5
    assert [row[:2] for row in a] == [row[:2] for row in b]
    # Both roots are zeros of the interpolants of two runs at rtol 1e-10, to round-off: they
    # differ by the runs' difference over θ'' (≈ 1e-8 here).
    assert max(abs(x[2] - y[2]) for x, y in zip(a, b, strict=True)) < 1e-6


def test_integrator_choice_is_checked():
    r = load_scenario(EXAMPLES / "tb_bdot.toml").request
    with pytest.raises(ParameterError, match=r"run\.integrator = 'numba' cannot integrate"):
        simulate(r.model, r.params, r.initial, r.tau[:3], "full", integrator="numba")
    auto = simulate(r.model, r.params, r.initial, r.tau[:3], "full", integrator="auto")
    assert auto.integrator == "scipy"  # the user's Python torque
    with pytest.raises(ParameterError, match='allowed: "auto", "numba", "scipy"'):
        simulate(r.model, r.params, r.initial, r.tau[:3], "full", integrator="fast")


def test_pressure_table_end_is_an_error():
    p = nm.Params(mu=1.0, a=1.0, b=0.0, eps=0.1, pressure=PRESSURES[2])
    st0 = nm.State(theta=1.0)
    with pytest.raises(ParameterError, match="pressure table covers"):
        simulate(nm.MODEL, p, st0, np.linspace(0.0, 100.0, 5), "full", integrator="numba")


def test_a_state_that_blows_up_is_reported():
    """ω̇ = ω²-like growth (a quadratic drag of the wrong sign) reaches infinity in finite time:
    an IntegrationError with the time, never NaN samples."""
    kernel = rigid_body_kernel(FREE_INERTIA, QuadraticDrag(-np.eye(3)))
    res = dop853.solve(kernel, FREE_Y0, 10.0, rtol=1e-10, atol=1e-12)
    assert res.status != 0 and res.t < 10.0
    from tumble.integrate import integrate

    with pytest.raises(IntegrationError, match="failed at t ="):
        integrate(lambda t, y: y, FREE_Y0, 10.0, kernel=kernel)


def test_batch_equals_single_runs_on_any_number_of_threads():
    rng = np.random.default_rng(7)
    N = 6
    y0 = np.tile(FREE_Y0, (N, 1))
    y0[:, :3] = rng.normal(size=(N, 3))
    torque = LinearDrag(0.01 * np.eye(3)) + ConstantInertialTorque([0.0, 0.0, 0.02])
    params = np.tile(rigid_body_kernel(FREE_INERTIA, torque).params, (N, 1))
    t = np.linspace(0.0, 30.0, 7)
    one = dop853.solve_batch(kernels.KIND_RIGID_BODY, params, y0, 30.0, t, rtol=1e-10,
                               atol=1e-12, threads=1)  # fmt: skip
    many = dop853.solve_batch(kernels.KIND_RIGID_BODY, params, y0, 30.0, t, rtol=1e-10,
                                atol=1e-12)  # fmt: skip
    assert np.all(one.status == 0)
    # Each trajectory is integrated by the same code on whichever thread: identical bits.
    assert np.array_equal(one.y, many.y)
    for i in range(N):
        single = dop853.solve(
            kernels.Kernel(kernels.KIND_RIGID_BODY, params[i]), y0[i], 30.0, rtol=1e-10,
            atol=1e-12, t_eval=t, record=False, dense=False,
        )  # fmt: skip
        assert np.array_equal(single.y_eval, one.y[i])


def test_compiled_code_is_cached_on_disk():
    """A second process loads the integrator from numba's disk cache instead of compiling:
    its loop, and the functions of the right-hand side's kind (closures told apart by their
    kind)."""
    dop853.solve(rigid_body_kernel(FREE_INERTIA, None), FREE_Y0, 1.0, rtol=1e-8,
                 atol=1e-10)  # fmt: skip
    code = textwrap.dedent(
        """
        import numpy as np
        from tumble.dynamics import rigid_body_kernel
        from tumble.integrate import dop853
        from tumble.integrate.dop853 import core, functions
        k = rigid_body_kernel(np.array([1.0, 2.0, 3.0]), None)
        dop853.solve(k, np.array([0.3, 1.0, 0.2, 1.0, 0.0, 0.0, 0.0]), 1.0, rtol=1e-8,
                     atol=1e-10)
        kind = functions.kind_functions(k.kind)
        for f in (core.advance, kind.step.dispatcher, kind.rhs.dispatcher):
            print(sum(f.stats.cache_hits.values()), sum(f.stats.cache_misses.values()))
        """
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    for line in out.stdout.splitlines():
        hits, misses = (int(v) for v in line.split())
        assert hits >= 1 and misses == 0


GG_SCENARIO = (
    'model = "torqued_body"\n[[torque]]\nkind = "gravity_gradient"\nn = 0.3\n'
    "[parameters]\ninertia = [1.0, 1.5, 2.0]\neps = 0.01\n"
    "[initial]\nomega = [0.3, 0.2, 1.0]\n[run]\nt_end = 20.0\nsamples = 21\n"
)


@pytest.mark.parametrize("integrator", ["numba", "scipy"])
def test_scenario_key_chooses_the_integrator(tmp_path, integrator):
    text = GG_SCENARIO + f'integrator = "{integrator}"\nmethods = ["full"]\n'
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, text)), "-o", str(out)])
    assert res.exit_code == 0, res.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["methods"]["full"]["integrator"] == integrator


def test_bad_integrator_is_one_line_exit_2(tmp_path):
    text = GG_SCENARIO + 'integrator = "rk4"\n'
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, text)), "-o", str(out)])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln]
    assert len(lines) == 1 and "run.integrator" in res.output, res.output
    assert not out.exists()


@pytest.mark.parametrize(
    "scenario",
    ["a3_positive.toml", "rf_counter_rotating.toml", "nm_damped_exp.toml",
     "tb_gravity_gradient.toml"],
)  # fmt: skip
def test_a_streamed_run_equals_the_dense_one(scenario, monkeypatch):
    """By default a compiled full run keeps only its samples: chunk by chunk, its angles
    unwrapped on each chunk's steps. Same steps, same samples, same turns of the angles and
    the same events as the run that keeps its dense output; small chunks here, so that the
    carrying over between chunks is exercised hundreds of times."""
    monkeypatch.setattr(dop853, "CHUNK_STEPS", 97)
    r = load_scenario(EXAMPLES / scenario).request
    tau = r.tau[r.tau <= r.tau[-1] / 4]
    kept = simulate(r.model, r.params, r.initial, tau, "full", dense=True)
    streamed = simulate(r.model, r.params, r.initial, tau, "full")
    assert streamed.integrator == kept.integrator == "numba"
    # The same steps; the dense run also forms every step's interpolant (3 more evaluations
    # each), the streamed one only where a sample or an event needs it.
    assert streamed.nfev <= kept.nfev
    for name, ref in kept.columns.items():
        # The same arithmetic on the same steps: equal to the last bits (the samples of both
        # come from the same interpolants).
        assert np.allclose(streamed.columns[name], ref, rtol=1e-13, atol=1e-13), name
    assert np.array_equal(streamed.events, kept.events)
    assert np.array_equal(streamed.event_signs, kept.event_signs)
    with pytest.raises(ParameterError, match="dense=True"):
        streamed.slow(tau[:2])


def test_the_step_budget_stops_a_run_with_the_key_to_change(tmp_path):
    r = load_scenario(EXAMPLES / "tb_gravity_gradient.toml").request
    with pytest.raises(IntegrationError, match=r"run\.max_steps = 500 steps spent at t = "):
        simulate(r.model, r.params, r.initial, r.tau, "full", max_steps=500)
    # A run that cannot fit is refused after its first chunk, from its step size.
    far = np.linspace(0.0, 1e15, 5)
    with pytest.raises(IntegrationError, match=r"needs about .* more steps, far beyond run\.max"):
        simulate(r.model, r.params, r.initial, far, "full")
    text = (EXAMPLES / "tb_gravity_gradient.toml").read_text()
    res = CliRunner().invoke(
        app, ["run", str(write(tmp_path, text + "max_steps = 0\n")), "-o", str(tmp_path / "o")]
    )
    assert res.exit_code == 2 and "run.max_steps = 0 is outside" in res.output, res.output


def test_the_step_budget_holds_on_the_scipy_path_too():
    # The averaged equations (~6 steps here) spend the same key's budget, on the Python
    # engine under scipy and compiled alike (a budget below one chunk of steps included)...
    r = load_scenario(EXAMPLES / "tb_gravity_gradient.toml").request
    for integrator in ("scipy", "numba"):
        with pytest.raises(IntegrationError, match=r"run\.max_steps = 2 steps spent at t = "):
            simulate(r.model, r.params, r.initial, r.tau, "averaged", max_steps=2,
                     integrator=integrator)  # fmt: skip
    # ...and a stiff Python right-hand side is stopped from its pace after ~1000 steps (the
    # message says so), not after the hours its 2e10 steps would take.
    with pytest.raises(IntegrationError, match=r"far beyond run\.max_steps = 1000000"):
        integrate(lambda t, y: -1e7 * (y - np.cos(t)), [0.0], 1e4, rtol=1e-10, atol=1e-12)
