"""The architecture page's example: a model outside the package, in one module, registered
with one line, runs through every method like the built-in ones."""

from __future__ import annotations

import importlib.util
import sys

import numpy as np
import pytest
from files import EXAMPLES

from tumble.analysis import RunRequest, run
from tumble.integrate import simulate
from tumble.models import MODELS, register

PATH = EXAMPLES / "models" / "damped_top.py"


@pytest.fixture(scope="module")
def top():
    found = importlib.util.spec_from_file_location("damped_top", PATH)
    module = importlib.util.module_from_spec(found)
    sys.modules["damped_top"] = module  # dataclasses resolve their module by name
    found.loader.exec_module(module)
    register(module.MODEL)
    yield module
    MODELS.pop(module.MODEL.name)
    sys.modules.pop("damped_top")


def test_registered_with_one_line(top):
    assert MODELS["damped_top"] is top.MODEL
    with pytest.raises(ValueError, match="already registered"):
        register(type(top.MODEL)(**{**top.MODEL.__dict__}))


def test_every_method_agrees_with_the_closed_form(top):
    p, st = top.Params(A=1.0, C=1.6, b=0.5, eps=0.02), top.State((0.4, -0.3, 2.0))
    t = np.linspace(0.0, 200.0, 41)
    exact = top.closed_form(p, st, t)
    for method in ("full", "averaged", "closed_form"):
        for integrator in ("numba", "scipy") if method == "full" else ("auto",):
            got = simulate(top.MODEL, p, st, t, method, integrator=integrator).columns
            for name in ("w_perp", "w3"):
                # The decay is exact in every form (the drag commutes with the free motion):
                # they agree to the integration tolerance (rtol 1e-10) times the O(1) values.
                assert np.max(np.abs(got[name] - exact[name])) < 1e-8, (method, name)


def test_invariants_are_conserved_without_drag(top):
    p, st = top.Params(A=1.0, C=1.6, b=0.5, eps=0.0), top.State((0.4, -0.3, 2.0))
    full = top.MODEL.full.form()
    from tumble.integrate import integrate

    sol = integrate(lambda t, y: full.rhs(t, y, p), full.initial_state(p, st), 300.0)
    inv = full.invariants(p, sol(np.linspace(0.0, 300.0, 31)))
    for name, values in inv.items():
        # Conserved to the integration tolerance (rtol 1e-10) over 300 time units.
        assert np.ptp(values) < 1e-8 * np.max(np.abs(values)), name


SCENARIO = """model = "damped_top"
[parameters]
A = 1.0
C = 1.6
b = 0.5
eps = 0.02
[initial]
omega = [0.4, -0.3, 2.0]
[run]
t_end = 100.0
samples = 21
"""


def test_a_scenario_file_of_the_example_runs(top, tmp_path):
    """Its declared keys make it a scenario model like the others: one-line errors too."""
    from typer.testing import CliRunner

    from tumble.cli import app

    (tmp_path / "top.toml").write_text(SCENARIO)
    res = CliRunner().invoke(app, ["run", str(tmp_path / "top.toml"), "-o", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "o" / "averaged.csv").exists()
    (tmp_path / "bad.toml").write_text(SCENARIO.replace("C = 1.6", "C = 1.6\nD = 1.0"))
    res = CliRunner().invoke(app, ["run", str(tmp_path / "bad.toml"), "-o", str(tmp_path / "o")])
    assert res.exit_code == 2 and "parameters.D: unknown key (allowed here: A, C, b, eps)" in (
        res.stderr
    )


def test_a_run_of_the_example_compares_its_methods(top):
    p, st = top.Params(A=1.0, C=1.6, b=0.5, eps=0.02), top.State((0.4, -0.3, 2.0))
    result = run(RunRequest(top.MODEL, p, st, np.linspace(0.0, 100.0, 21), top.MODEL.methods))
    # Exact decay in every form: the differences are integration noise.
    for pair, diffs in result.differences.items():
        assert max(diffs.values()) < 1e-8, pair
