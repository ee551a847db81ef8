"""Input errors that once read weakly, each one line that says what to give."""

from __future__ import annotations

import tomllib

import pytest

from tumble.errors import TumbleError
from tumble.io.scenario import parse_scenario, template


def _refused(change: str, to: str) -> str:
    text = template("orbiting_body")
    line = next(x for x in text.splitlines() if x.startswith(change))
    data = tomllib.loads(text.replace(line, to))
    with pytest.raises(TumbleError) as err:
        parse_scenario(data, "ob.toml")
    message = str(err.value)
    assert "\n" not in message
    return message


def test_a_number_where_a_vector_belongs_says_so():
    message = _refused("omega_deg_s", "omega_deg_s = 10.0")
    assert message.startswith("initial.omega_deg_s = 10.0: should be a list, e.g. [x, y, z]")


def test_a_value_outside_a_choice_lists_the_choices_once():
    message = _refused("shape", 'shape = "cube"')
    assert message.count("thin_spherical_shell") == 1 and "not one of the allowed" in message


def test_an_altitude_in_metres_is_told_the_unit():
    message = _refused("altitude", "altitude = 800e3")
    assert "800000 km" in message and "above 5974 km" in message and "in km" in message


def test_the_template_names_every_field_model():
    assert '"igrf"' in template("orbiting_body")
