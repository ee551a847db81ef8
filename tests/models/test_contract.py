"""Every registered model fills in the contract: its forms name their state components, the
state vectors have those lengths, and the methods follow the capabilities."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

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
