"""Rotating-field model: torque, the two full forms, invariants, slow elements
(docs/theory/rotating-field.md §§3–4, 9)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tumble.dynamics import rigid_body_rhs
from tumble.errors import ParameterError
from tumble.integrate import integrate
from tumble.models import rotating_field as rf
from tumble.rotations import matrix_to_quat, quat_normalize, quat_to_matrix, rot_z
from tumble.torques import EddyCurrentTorque

BODY = (1.0, 1.7, 2.3)  # triaxial, I1 < I2 < I3


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    return quat_to_matrix(quat_normalize(rng.normal(size=4)))


# ---------------------------------------------------------------------------------------------
# Torque (1.2)/(1.3)


@given(
    st.floats(0.0, math.pi),
    st.floats(-3.0, 3.0),
    st.floats(0.0, 10.0),
    st.integers(0, 2**32 - 1),
)
def test_torque_matrix_form_equals_cross_product_form(beta, omega, t, seed):
    """(1.3) ≡ (1.2) with the dot being d/dt (correction C1): M = k_f H × (H × Ω + Ḣ)."""
    rng = np.random.default_rng(seed)
    torque = EddyCurrentTorque(0.7, omega, beta)
    q = quat_normalize(rng.normal(size=4))
    w = rng.normal(size=3)
    A = quat_to_matrix(q)
    H = torque.field_direction(t)
    H_dot = omega * np.cross([0.0, 0.0, 1.0], H)
    expected = A.T @ (0.7 * np.cross(H, np.cross(H, A @ w) + H_dot))
    # Both are a few products of O(1) numbers: agreement to round-off.
    assert np.allclose(torque(t, q, w), expected, rtol=0.0, atol=1e-14)


def test_torque_vanishes_at_co_rotation_and_spins_up_a_body_at_rest():
    """Theory §3: zero torque at Ω_ξ = ω ξ3; dL_ξ3/dt = k_f H² ω sin²β > 0 from rest."""
    rng = np.random.default_rng(3)
    torque = EddyCurrentTorque(0.5, 1.3, 0.8)
    q = quat_normalize(rng.normal(size=4))
    A = quat_to_matrix(q)
    co = A.T @ np.array([0.0, 0.0, 1.3])
    assert np.max(np.abs(torque(0.4, q, co))) < 1e-15  # round-off of O(1) products
    M_xi = A @ torque(0.4, q, np.zeros(3))
    assert M_xi[2] == pytest.approx(0.5 * 1.3 * math.sin(0.8) ** 2, rel=1e-14)


def test_static_field_damps_any_rotation():
    """Static field (ω = 0), §3: T decreases monotonically, L·H is conserved, and the body
    ends spinning about the field direction."""
    torque = EddyCurrentTorque(0.3, 0.0, 0.9)
    inertia = np.array(BODY)
    rng = np.random.default_rng(5)
    y0 = np.concatenate([[0.8, -1.1, 0.6], matrix_to_quat(random_rotation(rng))])
    sol = integrate(lambda t, y: rigid_body_rhs(t, y, inertia, torque), y0, 300.0, rtol=1e-11)
    t = np.linspace(0.0, 300.0, 3001)
    Y = sol(t)
    w = Y[:, :3]
    T = 0.5 * np.sum(inertia * w * w, axis=1)
    # Monotone up to the integration error (rtol 1e-11 on O(1) values).
    assert np.all(np.diff(T) <= 1e-10)
    assert T[-1] < 0.5 * T[0]
    h = torque.field_direction(0.0)
    L_xi = np.einsum("nij,nj->ni", quat_to_matrix(Y[:, 3:]), inertia * w)
    LH = L_xi @ h
    assert np.max(np.abs(LH - LH[0])) < 1e-8  # conserved to ~100× the tolerance
    # End: Ω parallel to H (no perpendicular relative rotation left).
    w_xi = np.einsum("ij,j->i", quat_to_matrix(Y[-1, 3:]), w[-1])
    perp = w_xi - h * (w_xi @ h)
    assert np.linalg.norm(perp) < 1e-3 * np.linalg.norm(w_xi)


def test_rotating_field_drags_a_body_at_rest_into_co_rotation():
    """Theory §3, §11: a body at rest is spun up toward co-rotation about its largest axis."""
    p = rf.Params(BODY, math.pi / 3, 0.25)
    st0 = rf.State([0.0, 0.0, 0.0], random_rotation(np.random.default_rng(8)))
    sol = integrate(lambda t, y: rf.full_rhs(t, y, p), rf.full_from_slow(p, st0), 400.0)
    z = sol([400.0])[0, :3]
    # Co-rotation about x3 (largest), either sense of the body axis: z = (0, 0, 1).
    # The final approach is exponential at the rates of (2.6) (~ε/I): 1e-3 after τ = 400.
    assert np.allclose(z, [0.0, 0.0, 1.0], atol=1e-3)


# ---------------------------------------------------------------------------------------------
# The two full forms, and invariants at ε = 0


def test_inertial_form_equals_rotating_form():
    """(1.4) ≡ the corrected (1.5) (correction C3), to 1e-8 over τ = 1/ε: z and Γ = B A."""
    eps = 0.02
    p = rf.Params((1.3, 1.0, 1.9), 1.1, eps)
    st0 = rf.State([0.4, -0.7, 1.6], random_rotation(np.random.default_rng(11)))
    tau_end = 1.0 / eps
    # rtol 1e-12: both forms then carry errors ≪ 1e-8 over 50 time units (the bound checked).
    rot = integrate(
        lambda t, y: rf.full_rhs(t, y, p),
        rf.full_from_slow(p, st0),
        tau_end,
        rtol=1e-12,
        atol=1e-14,
    )
    ine = integrate(
        lambda t, y: rf.inertial_rhs(t, y, p),
        np.concatenate([st0.z, matrix_to_quat(st0.gamma)]),
        tau_end,
        rtol=1e-12,
        atol=1e-14,
    )
    t = np.linspace(0.0, tau_end, 501)
    Yr, Yi = rot(t), ine(t)
    assert np.max(np.abs(Yr[:, :3] - Yi[:, :3])) < 1e-8
    gamma_from_A = rot_z(-t) @ quat_to_matrix(Yi[:, 3:])  # Γ = B A, B(τ) = Rz(−τ)
    assert np.max(np.abs(Yr[:, 3:].reshape(-1, 3, 3) - gamma_from_A)) < 1e-8


def test_other_readings_of_gamma_prime_disagree():
    """Correction C3: the readings +ξ̂3Γ or −Γξ̂3 of the last term do not reproduce (1.4)."""
    p = rf.Params(BODY, 0.7, 0.05)
    st0 = rf.State([0.3, 0.2, 1.2], np.eye(3))

    def wrong(t, y):
        out = rf.full_rhs(t, y, p)
        G = y[3:].reshape(3, 3)
        hat = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        out[3:] += 2.0 * (hat @ G).ravel()  # −ξ̂3Γ → +ξ̂3Γ
        return out

    good = integrate(lambda t, y: rf.full_rhs(t, y, p), rf.full_from_slow(p, st0), 5.0)
    bad = integrate(wrong, rf.full_from_slow(p, st0), 5.0)
    assert np.max(np.abs(good([5.0]) - bad([5.0]))) > 1e-2


@settings(max_examples=3, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_free_body_conserves_energy_momentum_and_orthogonality(seed):
    """ε → 0 (ε = 1e-300: the torque is below round-off): T, |L| and Γ Γᵀ = E are conserved."""
    rng = np.random.default_rng(seed)
    p = rf.Params(BODY, 0.9, 1e-300)
    st0 = rf.State(rng.normal(size=3), random_rotation(rng))
    sol = integrate(
        lambda t, y: rf.full_rhs(t, y, p),
        rf.full_from_slow(p, st0),
        60.0,
        rtol=1e-12,
        atol=1e-14,
    )
    inv = rf.invariants(p, sol(np.linspace(0.0, 60.0, 121)))
    # DOP853 at rtol 1e-12 keeps invariants to ~1e-10 relative over 200 time units, and its
    # drift grows with time: 60 (ten or so turns at |ω0| ~ 1.6, the Python right-hand side,
    # ~1 s an example) keep it well within 1e-9.
    assert np.max(np.abs(inv["T"] / inv["T"][0] - 1.0)) < 1e-9
    assert np.max(np.abs(inv["L"] / inv["L"][0] - 1.0)) < 1e-9
    assert np.max(inv["orthogonality"]) < 1e-9


# ---------------------------------------------------------------------------------------------
# Slow elements (§9, §16)


@pytest.mark.parametrize("inertia", [BODY, (2.3, 1.0, 1.7), (1.7, 2.3, 1.0)])
@pytest.mark.parametrize("regime", ["x3", "x1"])
def test_state_from_elements_round_trip(inertia, regime):
    """The slow variables of the built state are the prescribed ones, in any axis labelling."""
    p = rf.Params(inertia, 1.0, 0.01)
    for k2, u0, psi0 in [(0.3, 0.0, 0.0), (0.8, 1.3, 2.0), (0.0, 0.4, -1.0), (1.0, 0.2, 0.3)]:
        s = rf.slow_elements(
            p, rf.state_from_elements(p, 1.8, 0.7, -2.1, k2, regime, u0=u0, psi0=psi0)
        )
        # Each element goes through (3.1), a rotation and back: round-off of O(1) quantities.
        assert s["L"] == pytest.approx(1.8, rel=1e-13)
        assert s["rho"] == pytest.approx(0.7, abs=1e-13)
        assert s["sigma"] == pytest.approx(-2.1, abs=1e-13)
        assert s["k2"] == pytest.approx(k2, abs=1e-12)
        regime_found = "x3" if s["L"] ** 2 >= 2 * s["T"] * sorted(inertia)[1] else "x1"
        if k2 < 1.0:
            assert regime_found == regime


def test_full_state_slow_variables_at_tau_zero():
    """σ is the inertial azimuth: σ = atan2(L_η2, L_η1) + τ (§9)."""
    p = rf.Params(BODY, 1.0, 0.01)
    st0 = rf.state_from_elements(p, 2.0, 1.1, 0.5, 0.4)
    sol = integrate(lambda t, y: rf.full_rhs(t, y, p), rf.full_from_slow(p, st0), 3.0)
    cols = rf.slow_from_full(p, np.array([0.0, 3.0]), sol(np.array([0.0, 3.0])))
    # Over τ = 3 the slow variables move by O(ε·τ) = O(0.03) only, not by the field's 3 rad.
    assert abs(cols["sigma"][1] - cols["sigma"][0]) < 0.1


def test_bad_initial_states_are_refused():
    p = rf.Params(BODY, 1.0, 0.01)
    with pytest.raises(ParameterError, match=r"initial\.gamma is not a rotation"):
        rf.State([0.0, 0.0, 1.0], np.diag([1.0, 1.0, 1.0 + 1e-6]))
    with pytest.raises(ParameterError, match=r"initial\.gamma is not a rotation"):
        rf.State([0.0, 0.0, 1.0], np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ParameterError, match=r"initial\.k2"):
        rf.state_from_elements(p, 1.0, 0.1, 0.0, 1.5)
    with pytest.raises(ParameterError, match=r"parameters\.eps"):
        rf.Params(BODY, 1.0, 0.0)
    with pytest.raises(ParameterError, match="triangle"):
        rf.Params((1.0, 1.0, 2.5), 1.0, 0.01)
    with pytest.raises(ParameterError, match="equal moments"):
        rf.state_from_elements(rf.Params((1.0, 1.0, 1.5), 1.0, 0.01), 1.0, 0.1, 0.0, 0.5)
