"""Every registered model fills in the contract: its forms name their state components, the
state vectors have those lengths, and the methods follow the capabilities."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from tumble.integrate.ode import integrate
from tumble.io.scenario import parse_scenario, template
from tumble.models import MODELS
from tumble.models.base import AveragingOptions


@pytest.mark.parametrize("name", sorted(MODELS))
def test_forms_name_their_state(name):
    model = MODELS[name]
    sc = parse_scenario(tomllib.loads(template(name)), f"<{name} template>")
    p, st = sc.request.params, sc.request.initial
    for form in model.full.forms.values():
        y = form.initial_state(p, st)
        assert len(form.state) == np.size(y) == len(set(form.state)), form.name
    if model.averaged is not None:
        coordinates = model.averaged.coordinates or ("",)
        for coords in coordinates:
            avg = model.averaged.form(p, st, AveragingOptions(coordinates=coords))
            assert len(avg.slow) == np.size(avg.initial_state(p, st)), (name, coords)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_methods_follow_the_capabilities(name):
    model = MODELS[name]
    assert ("averaged" in model.methods) == (model.averaged is not None)
    assert ("closed_form" in model.methods) == (model.closed_form is not None)
    assert model.full.default in model.full.forms


def _same_motion(name, form, y, back):
    """Two state vectors of one form describe the same motion: equal components, except a
    quaternion's sign (q and −q are one attitude)."""
    if "q0" in form.state:
        i = form.state.index("q0")
        if np.dot(y[i : i + 4], back[i : i + 4]) < 0.0:
            back = back.copy()
            back[i : i + 4] *= -1.0
    # The conversions are a few trigonometric functions and a 3×3 product of O(1) numbers.
    assert np.allclose(back, y, rtol=1e-12, atol=1e-12), (name, form.name)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_state_of_inverts_initial_state_and_feeds_the_averaged_form(name):
    model = MODELS[name]
    sc = parse_scenario(tomllib.loads(template(name)), f"<{name} template>")
    p, st = sc.request.params, sc.request.initial
    for form in model.full.forms.values():
        y = form.initial_state(p, st)
        _same_motion(name, form, y, form.initial_state(p, form.state_of(p, y)))
        if model.averaged is None:
            continue
        for coords in model.averaged.coordinates or ("",):
            options = AveragingOptions(coordinates=coords)
            want = model.averaged.form(p, st, options).initial_state(p, st)
            got = model.slow_state(p, y, options, form.name)
            assert np.allclose(got, want, rtol=1e-10, atol=1e-12), (name, form.name, coords)


@pytest.mark.parametrize("name", [name for name in sorted(MODELS) if MODELS[name].unperturbed])
def test_the_unperturbed_motion_solves_the_full_equations_at_zero(name):
    """The closed-form motion at ε = 0 against the default full form integrated with the
    perturbation removed, over a few units of time."""
    model = MODELS[name]
    assert model.unperturbed is not None
    sc = parse_scenario(tomllib.loads(template(name)), f"<{name} template>")
    p, st = sc.request.params, sc.request.initial
    form, free = model.full.form(), model.unperturbed
    t = np.linspace(0.0, 5.0, 11)
    exact = free.motion(p, st)(t)
    sol = integrate(lambda s, y: free.rhs(s, y, p), form.initial_state(p, st), 5.0,
                    rtol=1e-12, atol=1e-12)  # fmt: skip
    got = sol(t)
    if "q0" in form.state:  # q and −q are one attitude: compare with the integrated sign
        i = form.state.index("q0")
        flip = np.sum(exact[:, i : i + 4] * got[:, i : i + 4], axis=1) < 0.0
        exact[flip, i : i + 4] *= -1.0
    # Integration at rtol 1e-12 over ~5 periods of O(1) rates: a few 1e-11 of global error;
    # the elliptic-function motion is exact to a few ulps.
    assert np.allclose(exact, got, rtol=1e-9, atol=1e-9), np.max(np.abs(exact - got))


def test_every_paper_model_declares_its_unperturbed_motion():
    assert all(MODELS[name].unperturbed for name in MODELS if MODELS[name].paper)


def test_the_catalogue_lists_every_shipped_model_as_registered():
    # `tumble models` reads the catalogue without loading the models: it must say what the
    # registry says, in the same order.
    from tumble.catalogue import CATALOGUE

    shipped = [m for m in MODELS.values() if m.name in CATALOGUE]
    assert [m.name for m in shipped] == list(CATALOGUE)
    for m in shipped:
        assert (m.description, m.paper) == (CATALOGUE[m.name].description, CATALOGUE[m.name].paper)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_declaration_is_the_models_own(name):
    """A scenario is validated against the declaration alone: it must say what the model
    does (time, methods, checks, keys, averaging choices)."""
    from tumble.models import declaration
    from tumble.models.base import Declaration

    assert declaration(name) == Declaration.of(MODELS[name])


@pytest.mark.parametrize("name", ["torqued_body", "orbiting_body"])
def test_the_angles_alone_are_those_of_the_columns(name):
    # A form's ``angles`` replaces ``to_columns`` on every step of a run: the same values,
    # bit for bit, on states spread around its start (the azimuth's whole circle, and the
    # ξ3 axis, where a vector form has no azimuth and keeps the initial one). The models
    # whose averaged form has them: the vector forms [L_ξ, r] whose azimuth turns (the
    # rotating field's does not: tests/models/test_rf_averaged.py).
    model = MODELS[name]
    assert model.averaged is not None
    sc = parse_scenario(tomllib.loads(template(name)), f"<{name} template>")
    p, st = sc.request.params, sc.request.initial
    avg = model.averaged.form(p, st, AveragingOptions())
    assert avg.angles is not None
    y0 = np.asarray(avg.initial_state(p, st), dtype=float)
    turn = np.linspace(0.0, 2.0 * np.pi, 9)
    Y = np.repeat(y0[None, :], turn.size + 1, axis=0)
    size = np.hypot(y0[0], y0[1])
    Y[:-1, 0], Y[:-1, 1] = size * np.cos(turn), size * np.sin(turn)
    Y[-1, :2] = 0.0
    t = np.zeros(len(Y))
    angles, cols = avg.angles(p, st, t, Y), avg.to_columns(p, st, t, Y)
    assert angles and all(np.array_equal(angles[k], cols[k]) for k in angles)
