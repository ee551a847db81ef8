"""The observations set (tumble.analysis.claims.observations): its tables build the orbiting
body as a scenario file of them does, and each record keeps its sources' numbers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tumble.analysis.claims import observations as obs
from tumble.io import parse_scenario
from tumble.models.orbiting_body.inputs import SCENARIO
from tumble.models.schema import GivenInputs

TABLES = {
    "box-wing tumbling": {
        **obs.GEO_BOX_WING,
        "initial": {"spin_period": 60.0, "spin_axis": [1.0, 0.6, 0.4], **obs._euler(0.1, 0.5)},
    },
    "envisat": {
        "body": {"mass": 7827.9, "inertia": obs.ENVISAT_INERTIA,
                 "magnetic_tensor": obs.ENVISAT_TENSOR},
        "orbit": {"altitude": 766.0, "sun_synchronous": True, "epoch": "2013-09-25T00:00:00Z"},
        "initial": {"spin_period": obs.ENVISAT_PERIOD, "spin_axis": [0.0, 0.0, 1.0],
                    **obs._euler_towards(-obs._orbit_normal(98.46))},
    },
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(TABLES))
def test_the_tables_build_what_a_scenario_file_of_them_builds(name):
    tables = TABLES[name]
    variant = SCENARIO.variant(True)
    got = variant.build(GivenInputs(tables, variant.sections))
    data = {"model": "orbiting_body", **tables, "run": {"t_end_days": 1.0}}
    want = parse_scenario(data, "observation.toml").request
    # The same build function on the same values: equal to the last bit.
    assert got.scaling.T0 == want.scaling.T0 and got.scaling.I0 == want.scaling.I0
    np.testing.assert_array_equal(got.initial.omega, want.initial.omega)
    np.testing.assert_array_equal(got.initial.q, want.initial.q)
    np.testing.assert_array_equal(got.params.inertia, want.params.inertia)
    np.testing.assert_array_equal(got.params.torque.program, want.params.torque.program)
    np.testing.assert_array_equal(got.params.mean_torque.program, want.params.mean_torque.program)


def test_a_table_with_an_undeclared_or_missing_key_is_tumbles_error():
    variant = SCENARIO.variant(True)
    with pytest.raises(ValueError, match="not declared"):
        variant.build(GivenInputs({**TABLES["envisat"], "orbit": {"height": 1.0}},
                                  variant.sections))  # fmt: skip
    with pytest.raises(ValueError, match=r"body\.inertia is required"):
        variant.build(GivenInputs({**TABLES["envisat"], "body": {"mass": 1.0}},
                                  variant.sections))  # fmt: skip


def test_the_records_keep_their_sources_numbers():
    # The figures the sources publish, as the records hold them (docs/theory/observations.md).
    assert obs.ENVISAT_PERIOD == 134.74 and obs.ENVISAT_RATE == 36.7
    assert 1.0 / obs.LARETS_FIT[1] == pytest.approx(50.74, abs=0.01)
    assert 1.0 / obs.STELLA_FIT[1] == pytest.approx(231.89, abs=0.01)
    # The bands: agreement within 25 %, a qualitative explanation within a factor 3.
    assert obs._ratio_verdict([1.2, 0.85]) == (True, False)
    assert obs._ratio_verdict([1.2, 2.9]) == (True, True)
    assert obs._ratio_verdict([0.3]) == (False, True)
    assert math.isclose(obs.QUALITATIVE, 3.0) and math.isclose(obs.AGREEMENT, 1.25)
