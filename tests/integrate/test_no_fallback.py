"""Every shipped example runs its integrations compiled: none falls back to scipy's DOP853 in
Python unless it asks for it or gives a Python function, and a run that does says so in one
line with the reason."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from files import EXAMPLES

from tumble.integrate import simulate
from tumble.integrate.simulate import integrator_named
from tumble.io import load_scenario
from tumble.models import torqued_body as tb
from tumble.torques import CallableTorque

SCENARIOS = sorted(p.name for p in EXAMPLES.glob("*.toml"))


def _forms(request):
    """(method, form) of every integrated method of a scenario's request."""
    model, p, st = request.model, request.params, request.initial
    for method in request.methods:
        if method == "full":
            yield method, model.full.form()
        elif method == "averaged":
            options = model.averaged.check(request.averaging)
            yield method, model.averaged.form(p, st, options)
            if options.hybrid:
                yield "full", model.full.form()


@pytest.mark.parametrize("name", SCENARIOS)
def test_every_shipped_example_runs_compiled(name):
    scenario = load_scenario(EXAMPLES / name, allow_modules=())
    request = scenario.request
    chosen = integrator_named(request.integrator)
    for method, form in _forms(request):
        reason = chosen.scipy_reason(request.model, form, request.params)
        python_code = any(f.endswith(".py") for f in scenario.user_code)
        # A Python function in the scenario is the one documented reason for scipy.
        assert reason == "" or ("Python function" in reason and python_code), (method, reason)


def test_the_symmetric_and_spherical_examples_are_among_them():
    # The bodies the compiled engine once refused: a rocket body (I2 = I3) and a sphere.
    inertias = {n: load_scenario(EXAMPLES / n).request.params.inertia for n in
                ("ob_rocket_body.toml", "ob_aluminium_sphere.toml")}  # fmt: skip
    assert np.ptp(inertias["ob_aluminium_sphere.toml"]) == 0.0
    i1, i2, i3 = sorted(inertias["ob_rocket_body.toml"])
    assert i2 == i3 > i1


def test_a_python_torque_says_it_runs_on_scipy():
    # A torque written as a Python function: the averaged run goes to scipy, in one warning.
    torque = CallableTorque(lambda t, q, omega: 1e-3 * np.ones_like(omega))
    p = tb.Params(np.array([1.0, 1.6, 2.0]), 0.01, torque)
    st = tb.State(np.array([0.3, 0.9, 0.4]), np.array([1.0, 0.0, 0.0, 0.0]))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        simulate(tb.MODEL, p, st, np.linspace(0.0, 1.0, 3), "averaged")
    said = [str(w.message) for w in seen if "scipy" in str(w.message)]
    assert len(said) == 1 and "Python function" in said[0] and "\n" not in said[0], said
