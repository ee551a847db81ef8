"""Rigid bodies: validation of the principal moments."""

import pytest
from hypothesis import given
from strategies import inertias

from tumble.bodies import RigidBody
from tumble.errors import ParameterError


@given(inertias())
def test_valid_inertias_are_accepted(moments):
    body = RigidBody(*moments)
    assert body.inertia.tolist() == list(moments)


@pytest.mark.parametrize("moments", [(0.0, 1.0, 1.0), (-1.0, 1.0, 1.0), (1.0, 1.0, float("nan"))])
def test_nonpositive_moment_is_refused(moments):
    with pytest.raises(ParameterError, match=r"inertia\.I"):
        RigidBody(*moments)


def test_triangle_inequality_is_enforced_and_thin_plate_allowed():
    with pytest.raises(ParameterError, match="triangle inequality"):
        RigidBody(1.0, 1.0, 2.5)
    RigidBody(1.0, 2.0, 3.0)  # flat body I3 = I1 + I2 is a legitimate limit
    assert RigidBody.symmetric(1.0, 1.5).is_symmetric


def test_energy_and_momentum():
    body = RigidBody(1.0, 2.0, 3.0)
    assert body.kinetic_energy([1.0, 1.0, 1.0]) == pytest.approx(3.0)
    assert body.angular_momentum([1.0, 1.0, 1.0]).tolist() == [1.0, 2.0, 3.0]
