"""Torques added for the averaging engine (issue 5): inertial constant and gravity gradient."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.errors import ParameterError
from tumble.rotations import quat_normalize, quat_to_matrix
from tumble.torques import ConstantInertialTorque, GravityGradientTorque

quaternions = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(
    lambda v: np.linalg.norm(v) > 0.1
)


@settings(max_examples=30)
@given(quaternions, st.floats(0.0, 10.0))
def test_constant_inertial_torque_is_fixed_in_space(q, t):
    M = np.array([0.3, -1.2, 0.7])
    q = quat_normalize(np.array(q))
    body = ConstantInertialTorque(M)(t, q, np.zeros(3))
    # A M_body = M to round-off.
    assert np.allclose(quat_to_matrix(q) @ body, M, atol=1e-14)


def test_gravity_gradient_vanishes_with_principal_axes_along_the_radius():
    gg = GravityGradientTorque([1.0, 2.0, 3.0], n=0.7)
    # Normal ξ3: at t = 0 the radius is e1 = ξ1. The identity attitude puts body x1 along the
    # radius: no torque.
    assert np.allclose(gg(0.0, np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3)), 0.0, atol=1e-15)


def test_gravity_gradient_small_tilt_restores_the_long_axis():
    # Tilt by a small angle α about the orbit normal (body x3 = ξ3): with r̂_b = (cos α,
    # −sin α, 0), M3 = 3n²(I2 − I1) r1 r2 = −3n²(I2 − I1) sin α cos α: it turns the axis of the
    # smallest moment back to the radius when I2 > I1.
    I1, I2, I3, n, alpha = 1.0, 2.0, 3.0, 0.5, 1e-3
    gg = GravityGradientTorque([I1, I2, I3], n=n)
    q = np.array([math.cos(alpha / 2), 0.0, 0.0, math.sin(alpha / 2)])
    m = gg(0.0, q, np.zeros(3))
    assert m[2] == pytest.approx(-3 * n**2 * (I2 - I1) * math.sin(alpha) * math.cos(alpha))
    assert abs(m[0]) < 1e-15 and abs(m[1]) < 1e-15


def test_gravity_gradient_batches_equal_single_calls():
    gg = GravityGradientTorque([1.0, 1.5, 2.2], n=1.3, normal=[0.2, -0.4, 1.0], u0=0.3)
    rng = np.random.default_rng(4)
    q = rng.normal(size=(7, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    batch = gg(0.8, q, np.zeros((7, 3)))
    single = np.array([gg(0.8, qi, np.zeros(3)) for qi in q])
    assert np.allclose(batch, single, atol=1e-15)
    # The radius stays in the orbit plane and has unit length.
    r = gg.radial(np.linspace(0.0, gg.period, 9))
    assert np.allclose(np.linalg.norm(r, axis=-1), 1.0)
    assert np.allclose(r @ gg.normal, 0.0, atol=1e-15)


def test_gravity_gradient_rejects_bad_input():
    with pytest.raises(ParameterError, match="inertia"):
        GravityGradientTorque([1.0, -2.0, 3.0], n=1.0)
    with pytest.raises(ParameterError, match="normal"):
        GravityGradientTorque([1.0, 2.0, 3.0], n=1.0, normal=[0.0, 0.0, 0.0])


def test_every_builtin_torque_accepts_batches():
    from tumble.torques import (
        ConstantBodyTorque,
        EddyCurrentTorque,
        LinearDrag,
        QuadraticDrag,
        ZeroTorque,
    )

    rng = np.random.default_rng(7)
    q = rng.normal(size=(5, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w = rng.normal(size=(5, 3))
    B, S = rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    total = 0.5 * (ConstantBodyTorque([0.1, 0.2, 0.3]) + LinearDrag(B) + QuadraticDrag(S))
    for torque in (
        total,
        ZeroTorque(),
        EddyCurrentTorque(0.3, 1.0, 0.8),
        total + EddyCurrentTorque(0.1, 0.0, 0.2),
    ):
        batch = torque(0.7, q, w)
        single = np.array([torque(0.7, qi, wi) for qi, wi in zip(q, w, strict=True)])
        assert batch.shape == (5, 3)
        assert np.allclose(batch, single, atol=1e-14)
