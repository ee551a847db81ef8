"""The built-in torques: each against its formula written out here, batches, sums of compiled
and Python terms, and the attitude-free convention ``q = None``."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import TORQUE_PARAMETERS, vectors

from tumble.errors import ParameterError
from tumble.rotations import quat_normalize, quat_to_matrix
from tumble.torques import (
    CallableTorque,
    ConstantBodyTorque,
    ConstantInertialTorque,
    EddyCurrentTorque,
    GravityGradientTorque,
    LinearDrag,
    QuadraticDrag,
    Torque,
    TorqueSum,
    ZeroTorque,
    inertial_moments_on_grid,
    split_compiled,
)

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


# ---------------------------------------------------------------------------------------------
# Each compiled torque against its physics written in vector form, independently of the
# compiled code (which uses component formulas and, for the eddy current, the projection form).


def _references(t, q, w, a, B, S, M, gg, eddy):
    A = quat_to_matrix(q)  # body → inertial
    r_b = A.T @ gg.radial(t)
    H = eddy.field_direction(t)
    H_dot = eddy.omega * np.cross([0.0, 0.0, 1.0], H)  # (1.1): the field turns about ξ3
    Omega = A @ w
    return [
        a,
        -B @ w,
        -S @ (w * np.abs(w)),
        A.T @ M,
        3.0 * gg.n**2 * np.cross(r_b, gg.inertia * r_b),
        # (1.2) of the rotating-field paper with the field's rate: M0 H × (H × Ω + dH/dt).
        A.T @ (eddy.M0 * np.cross(H, np.cross(H, Omega) + H_dot)),
    ]


@settings(max_examples=60)
@given(
    q=quaternions,
    w=vectors(scale=3.0),
    rate=st.floats(-2.0, 2.0),
    **TORQUE_PARAMETERS,
)
def test_each_builtin_torque_is_its_formula(q, w, a, B, S, M, n, normal, beta, rate, t):
    q = quat_normalize(np.array(q))
    gg = GravityGradientTorque([1.0, 1.7, 2.4], n, normal, 0.3)
    eddy = EddyCurrentTorque(0.7, rate, beta)
    torques = [ConstantBodyTorque(a), LinearDrag(B), QuadraticDrag(S)]
    torques += [ConstantInertialTorque(M), gg, eddy]
    expected = _references(t, q, w, a, B, S, M, gg, eddy)
    # Entries of size ≤ 3 (|B|, |S| ≤ 1, |ω| ≤ 3√3: quadratic terms ≤ ~100), n² ≤ 9: a few
    # hundred roundings of size 1e-16 of the largest term.
    for torque, ref in zip(torques, expected, strict=True):
        assert np.allclose(torque(t, q, w), ref, rtol=1e-12, atol=1e-12), type(torque).__name__
    total = 0.01 * (torques[0] + torques[2]) + 2.0 * torques[4] + torques[5]
    want = 0.01 * (expected[0] + expected[2]) + 2.0 * expected[4] + expected[5]
    assert np.allclose(total(t, q, w), want, rtol=1e-12, atol=1e-12)


def test_the_eddy_current_inertial_form_is_the_body_form_rotated():
    eddy = EddyCurrentTorque(0.4, 1.1, 0.6)
    rng = np.random.default_rng(3)
    q = quat_normalize(rng.normal(size=4))
    w = rng.normal(size=3)
    A = quat_to_matrix(q)
    # Same compiled term at two attitudes: rounding only.
    assert np.allclose(A @ eddy(0.9, q, w), eddy.inertial(0.9, A @ w), atol=1e-15)


def test_a_python_subclass_is_not_compiled_and_sums_split():
    class Spring(Torque):
        def __call__(self, t, q, omega):
            return -0.5 * np.asarray(omega)

    assert Spring().program is None and not Spring().rate_only
    drag = LinearDrag(np.eye(3))
    total = 2.0 * (drag + Spring()) + ZeroTorque()
    assert total.program is None
    compiled, python = split_compiled(total)
    assert compiled.program is not None and python is not None
    w = np.array([0.3, -1.0, 2.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    assert np.allclose(total(0.0, q, w), -3.0 * w, atol=1e-15)
    assert np.allclose(compiled(0.0, q, w) + python(0.0, q, w), -3.0 * w, atol=1e-15)
    assert split_compiled(drag) == (drag, None)
    assert split_compiled(CallableTorque(lambda t, q, w: w))[1] is not None


def test_q_none_is_allowed_only_for_rate_torques():
    w = np.array([[0.1, 0.2, 0.3], [1.0, 0.0, -1.0]])
    rate = ConstantBodyTorque([1.0, 0.0, 0.0]) + QuadraticDrag(np.eye(3))
    assert rate.rate_only
    assert np.allclose(rate(0.0, None, w), [1.0, 0.0, 0.0] - w * np.abs(w), atol=1e-15)
    with pytest.raises(ParameterError, match="attitude"):
        EddyCurrentTorque(1.0, 0.0, 0.0)(0.0, None, w)
    with pytest.raises(ParameterError, match="shape"):
        rate(0.0, None, np.zeros(2))


def test_moments_on_a_grid_are_calls_at_each_node_and_time():
    torque = GravityGradientTorque([1.0, 2.0, 3.5], 0.8) + EddyCurrentTorque(0.2, 0.7, 1.0)
    rng = np.random.default_rng(11)
    q = quat_normalize(rng.normal(size=(4, 4)))
    w = rng.normal(size=(4, 3))
    t = np.array([0.0, 0.4, 1.3])
    grid = inertial_moments_on_grid(torque, t, quat_to_matrix(q), w)
    assert grid.shape == (4, 3, 3)
    for k in range(4):
        for j in range(3):
            want = quat_to_matrix(q[k]) @ torque(t[j], q[k], w[k])
            assert np.allclose(grid[k, j], want, atol=1e-14)
    assert isinstance(torque, TorqueSum)


def test_gravity_gradient_u0_is_the_argument_of_latitude():
    # An orbit of inclination i and ascending node Ω: at u0 = 0 the body is at the node,
    # (cos Ω, sin Ω, 0), and a quarter orbit later at its northernmost point, ξ3 = sin i.
    # (The former convention measured u0 from ξ1 projected on the orbit plane: 0.84 rad off
    # the node here.)
    inc, node = math.radians(50.0), math.radians(60.0)
    h = [math.sin(node) * math.sin(inc), -math.cos(node) * math.sin(inc), math.cos(inc)]
    gg = GravityGradientTorque([1.0, 2.0, 3.0], n=0.5, normal=h)
    assert np.allclose(gg.radial(0.0), [math.cos(node), math.sin(node), 0.0], atol=1e-15)
    north = gg.radial(0.25 * gg.period)
    assert north[2] == pytest.approx(math.sin(inc), abs=1e-15)
    # The motion runs counter-clockwise about the normal; u0 shifts it along the orbit.
    assert np.cross(gg.radial(0.0), north) @ gg.normal == pytest.approx(1.0, abs=1e-15)
    shifted = GravityGradientTorque([1.0, 2.0, 3.0], n=0.5, normal=h, u0=0.3)
    assert np.allclose(shifted.radial(0.0), gg.radial(0.3 / 0.5), atol=1e-15)
    # An equatorial orbit has no node: u is measured from ξ1 (prograde and retrograde).
    for sign in (1.0, -1.0):
        flat = GravityGradientTorque([1.0, 2.0, 3.0], n=0.5, normal=[0.0, 0.0, sign])
        assert np.allclose(flat.radial(0.0), [1.0, 0.0, 0.0], atol=1e-15)
