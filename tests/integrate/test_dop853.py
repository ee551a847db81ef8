"""The compiled DOP853 in pieces: its tableau, runs that advance in chunks, and a disk cache
that notices an edit to any compiled source."""

from __future__ import annotations

import ast
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from files import ROOT
from scipy.integrate._ivp import dop853_coefficients as scipy_tableau

from tumble.dynamics import rigid_body_kernel
from tumble.integrate import dop853
from tumble.integrate.dop853 import core, tableau
from tumble.kernels import evaluate_rhs, jit
from tumble.kernels.kinds import KINDS
from tumble.models import nonlinear_moment as nm
from tumble.torques import ConstantInertialTorque, LinearDrag

PACKAGE = ROOT / "src" / "tumble"
INERTIA = np.array([1.0, 2.0, 3.0])
Y0 = np.array([0.3, 1.0, 0.2, 1.0, 0.0, 0.0, 0.0])
TOL = {"rtol": 1e-10, "atol": 1e-12}


@pytest.mark.parametrize("name", ["A", "B", "C", "D", "E3", "E5"])
def test_tableau_is_scipys_to_the_bit(name):
    """Hairer's coefficients as written here are the doubles scipy's DOP853 uses."""
    assert np.array_equal(getattr(tableau, name), getattr(scipy_tableau, name))


def test_tableau_sizes_are_scipys():
    assert tableau.N_STAGES == scipy_tableau.N_STAGES
    assert tableau.N_STAGES_EXTENDED == scipy_tableau.N_STAGES_EXTENDED
    assert tableau.N_INTERPOLANT == scipy_tableau.INTERPOLATOR_POWER


def test_tableau_conditions():
    """Row sums equal the nodes (c_i = Σ_j a_ij), the weights sum to one, and the error
    weights are consistent (they integrate a constant to zero); to rounding of the printed
    coefficients, a few ulps of the largest entry."""
    A, C = tableau.A, tableau.C
    assert np.allclose(A.sum(axis=1), C, rtol=0.0, atol=1e-13 * np.abs(A).max())
    assert abs(tableau.B.sum() - 1.0) < 1e-14
    assert abs(tableau.E5.sum()) < 1e-14 * np.abs(tableau.E5).max()


def _nm_kernel():
    p = nm.Params(mu=0.7, a=1.0, b=0.3, eps=0.05, d=0.3, nu=0.2)
    return nm.full_kernel(p), np.array([0.1, 0.2, 3.0, 0.9, 0.3, 0.1, 0.0])


@pytest.mark.parametrize("steps", [1, 7, 100])
def test_a_run_in_chunks_equals_one_run(steps):
    """Stopping every few steps and resuming changes nothing: the same steps, states,
    interpolants, events and samples, to the bit."""
    kernel, y0 = _nm_kernel()
    t_eval = np.linspace(0.0, 40.0, 23)
    whole = dop853.solve(kernel, y0, 40.0, t_eval=t_eval, **TOL)
    run = dop853.Integration(kernel, y0, 40.0, dop853.Options(**TOL), t_eval=t_eval)
    calls = 0
    while not run.advance(max_steps=steps):
        calls += 1
    parts = run.solution()
    assert calls >= (whole.ts.size - 1) // steps - 1  # it did stop that often
    assert parts.status == whole.status == 0 and parts.nfev == whole.nfev
    for name in ("ts", "ys", "F", "y_eval", "event_t", "event_signs", "event_y"):
        assert np.array_equal(getattr(parts, name), getattr(whole, name)), name
    assert whole.event_t.size > 10  # the events were exercised


def test_memory_of_a_sampled_run_is_bounded_by_the_samples():
    """Without a record, a run keeps its samples and the current state only, however many
    steps it takes and however it is chunked."""
    kernel = rigid_body_kernel(INERTIA, LinearDrag(0.01 * np.eye(3)))
    t_eval = np.linspace(0.0, 500.0, 5)
    opts = dop853.Options(**TOL, record=False, dense=False)
    run = dop853.Integration(kernel, Y0, 500.0, opts, t_eval=t_eval)
    while not run.advance(max_steps=50):
        assert all(c.ts.size == 1 and c.F.size <= 7 * 7 for c in run._chunks)
    sol = run.solution()
    assert sol.ts.size == 1 and sol.F.shape[0] == 0
    assert run.progress.n_steps > 100 * t_eval.size  # many steps, none of them kept
    ref = dop853.solve(kernel, Y0, 500.0, t_eval=t_eval, record=False, dense=False, **TOL)
    assert np.array_equal(sol.y_eval, ref.y_eval)


def test_a_failure_stops_the_chunks_with_its_status():
    """ω' ∝ ω² (a quadratic drag of the wrong sign) blows up: the chunked run ends with the
    failure's status and time, like the whole run."""
    from tumble.torques import QuadraticDrag

    kernel = rigid_body_kernel(INERTIA, QuadraticDrag(-np.eye(3)))
    whole = dop853.solve(kernel, Y0, 10.0, **TOL)
    run = dop853.Integration(kernel, Y0, 10.0, dop853.Options(**TOL))
    while not run.advance(max_steps=5):
        pass
    assert run.progress.status == whole.status < 0
    assert run.progress.t == whole.t < 10.0
    assert run.advance(max_steps=5)  # a finished run stays finished


def test_batch_runs_keep_their_own_options():
    """solve_many and solve give the same bits (the options record travels unchanged)."""
    torque = LinearDrag(0.01 * np.eye(3)) + ConstantInertialTorque([0.0, 0.0, 0.02])
    kernel = rigid_body_kernel(INERTIA, torque)
    ((many, _seconds),) = dop853.solve_many([kernel], [Y0], [15.0], **TOL)
    one = dop853.solve(kernel, Y0, 15.0, **TOL)
    assert np.array_equal(many.F, one.F) and np.array_equal(many.ys, one.ys)


_COMPILERS = {"jit", "njit", "vectorize", "guvectorize", "cfunc", "stencil"}


def _compiles(path: Path) -> bool:
    """Whether the module defines a function under a numba decorator (or tumble's jit)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.FunctionDef):
            for deco in node.decorator_list:
                target = deco.func if isinstance(deco, ast.Call) else deco
                name = (
                    target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
                )
                if name in _COMPILERS:
                    return True
    return False


def test_every_compiled_module_is_stamped():
    """A module that defines compiled code must be in COMPILED_SOURCES, or an edit to it would
    leave the integrator's cached machine code stale. (A user's torque compiled at run time by
    a call, as the crossings study's dipole, is never cached and needs no stamp.)"""
    stamped = {entry for entry, _mtime, _size in jit.source_stamp()}
    compiled = {f.relative_to(PACKAGE).as_posix() for f in PACKAGE.rglob("*.py") if _compiles(f)}
    assert {"kernels/rhs.py", "integrate/dop853/core.py"} <= compiled  # the scan finds them
    assert compiled - stamped == set()
    assert "kernels/torque.py" in stamped  # the torque terms and their codes


def test_cached_functions_carry_the_stamp_of_every_compiled_source():
    """numba compares this stamp with the one in its index on disk: with every compiled
    source in it, an edit to a callee's file recompiles its callers too."""
    stamp = core.advance._cache._cache_file._source_stamp
    assert stamp[1] == jit.source_stamp()


def test_a_terminal_event_stops_the_run_at_its_first_zero():
    """Made terminal, the event ends the run at its first zero: the time the recording run
    locates, the state its dense output gives there, the step that crossed it not taken."""
    kernel, y0 = _nm_kernel()
    recorded = dop853.solve(kernel, y0, 40.0, **TOL)
    stopped = dop853.solve(replace(kernel, terminal=True), y0, 40.0, **TOL)
    assert stopped.status == dop853.STOPPED and stopped.message
    first = recorded.event_t[0]
    # The same root finder on the same step: the zero to round-off of t.
    assert stopped.t == pytest.approx(first, rel=1e-14, abs=1e-14)
    assert list(stopped.event_t) == [stopped.t]  # the zero it stopped at, recorded once
    assert stopped.ts[-1] == stopped.t and np.all(np.diff(stopped.ts) > 0.0)
    # The last step lands on the zero with the usual error control: within ~rtol of the
    # recording run's interpolant there.
    assert np.allclose(stopped.y, recorded(np.array([first]))[0], rtol=1e-9, atol=1e-9)
    assert stopped.nfev < recorded.nfev


def test_a_breakpoint_surface_on_the_compiled_path_matches_scipys():
    """integrate() with one surface breakpoint and its compiled event: stopped there,
    restarted through the map, the same solution as scipy's path with the Python condition."""
    from tumble.integrate.ode import integrate
    from tumble.kernels import EVENT_NONE, EVENT_THETA_DOT, evaluate_rhs
    from tumble.kernels.rhs import evaluate_event
    from tumble.models.base import Breakpoint

    kernel, y0 = _nm_kernel()
    quiet = replace(kernel, event=EVENT_NONE)

    def kick(t: float, y: np.ndarray) -> np.ndarray:
        return y * np.array([1.0, 1.0, 1.01, 1, 1, 1, 1])  # a jump in r: visible after

    surface = Breakpoint(
        lambda t, y: evaluate_event(EVENT_THETA_DOT, t, y, kernel.params),
        kick,
        None,
        event=EVENT_THETA_DOT,
    )
    compiled = integrate(None, y0, 20.0, breakpoints=(surface,), kernel=quiet, **TOL)
    scipy = integrate(lambda t, y: evaluate_rhs(kernel, t, y), y0, 20.0, breakpoints=(surface,),
                      **TOL)  # fmt: skip
    assert compiled.integrator == "numba" and scipy.integrator == "scipy"
    t = np.linspace(0.0, 20.0, 41)
    # Two runs at rtol 1e-10 (the same method and controller), a restart each: ~1e-8.
    assert np.allclose(compiled(t), scipy(t), rtol=0.0, atol=1e-7)
    assert abs(compiled(t)[-1, 2] - y0[2]) > 1e-3  # the kick happened


def _nm_averaged(eps):
    """The nonlinear moment's template at ``eps`` over its slow horizon: its averaged
    (compiled, slow) kernel and start."""
    from tumble.app.bench import at_eps
    from tumble.io.scenario import parse_scenario, template

    data = at_eps(tomllib.loads(template("nonlinear_moment")), eps, None, 11)
    req = parse_scenario(data, "<template>").request
    avg = req.model.averaged.form(req.params, req.initial, req.model.averaged.check(req.averaging))
    kernel = avg.kernel(req.params)
    return kernel, np.asarray(avg.initial_state(req.params, req.initial)), float(req.tau[-1])


def test_a_slow_kind_starts_at_the_time_of_a_one_percent_change():
    # Averaged equations (rates of order ε): Hairer's estimate would start them at about 1e-5
    # of the slow time at ε = 1e-4, and four tenfold steps would follow before the first the
    # error asks for. A slow kind starts at h0 = 0.01‖y‖/‖f‖ (its first guess) instead.
    kernel, y0, t_end = _nm_averaged(1e-4)
    full = rigid_body_kernel(INERTIA, LinearDrag(0.01 * np.eye(3)))
    assert KINDS[kernel.kind].slow and not KINDS[full.kind].slow  # full kinds: scipy's start
    f0 = evaluate_rhs(kernel, 0.0, y0)
    scale = TOL["atol"] + TOL["rtol"] * np.abs(y0)
    h0 = 0.01 * np.sqrt(np.mean((y0 / scale) ** 2)) / np.sqrt(np.mean((f0 / scale) ** 2))
    run = dop853.Integration(kernel, y0, t_end, dop853.Options(**TOL))
    run.advance()
    sol = run.solution()
    assert sol.status == 0
    # The first step is h0 itself, to round-off: accepted at once (the next grows by the whole
    # tenfold the controller allows, so its error norm was below (0.9/10)^8 = 4e-9).
    assert sol.ts[1] - sol.ts[0] == pytest.approx(h0, rel=1e-12)
    # 6 steps and 92 evaluations over the slow horizon 1.5 (9 steps, 137 evaluations from
    # Hairer's start).
    assert sol.ts.size - 1 <= 7


def test_a_slow_kinds_steps_do_not_depend_on_eps():
    # The averaged equations are ε·g(y, εt): from the slow start the whole run is the same in
    # the slow time at every ε (to round-off in the step sizes), as it should be; Hairer's
    # start is not (it depends on ε through (0.01/‖f‖)^(1/8)).
    runs = []
    for eps in (1e-3, 1e-4):
        kernel, y0, t_end = _nm_averaged(eps)
        run = dop853.Integration(kernel, y0, t_end, dop853.Options(**TOL))
        run.advance()
        sol = run.solution()
        runs.append((eps * sol.ts, sol.y[-1], sol.nfev))
    (s3, y3, n3), (s4, y4, n4) = runs
    assert n3 == n4 and s3.size == s4.size
    # The step times agree to 1e-5 (measured 1.4e-6): the controller takes err^(-1/8) of error
    # estimates formed by cancellation, whose round-off differs between the two time units.
    # The end states agree within the tolerance.
    np.testing.assert_allclose(s3, s4, rtol=1e-5, atol=1e-12)
    np.testing.assert_allclose(y3, y4, rtol=1e-9)
