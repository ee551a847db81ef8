"""Rotations: quaternions, matrices, 3-1-3 angles and the K-frame angles of
docs/theory/resisting-medium.md §2."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from strategies import angle

from tumble import rotations as rot

# Round-off of a handful of 3×3 products and trig calls: a few ulps of 1.
ROUNDOFF = 1e-13


def random_quats(n, seed=0):
    return rot.quat_normalize(np.random.default_rng(seed).normal(size=(n, 4)))


def test_quaternion_matrix_round_trip_and_orthogonality():
    q = random_quats(500)
    R = rot.quat_to_matrix(q)
    assert np.allclose(R @ np.swapaxes(R, -1, -2), np.eye(3), atol=ROUNDOFF)
    assert np.allclose(np.linalg.det(R), 1.0, atol=ROUNDOFF)
    q2 = rot.matrix_to_quat(R)
    # q and −q are the same rotation; matrix_to_quat returns q0 ≥ 0.
    assert np.allclose(q2, np.where(q[:, :1] < 0, -q, q), atol=ROUNDOFF)


def test_matrix_to_quat_at_half_turns():
    # Trace −1: the pivot must move away from q0 (no division by ~0).
    for R in (rot.rot_x(math.pi), rot.rot_z(math.pi), np.diag([-1.0, -1.0, 1.0])):
        assert np.allclose(rot.quat_to_matrix(rot.matrix_to_quat(R)), R, atol=ROUNDOFF)


def test_quaternion_product_composes_rotations():
    p, q = random_quats(2, seed=3)
    assert np.allclose(
        rot.quat_to_matrix(rot.quat_multiply(p, q)),
        rot.quat_to_matrix(p) @ rot.quat_to_matrix(q),
        atol=ROUNDOFF,
    )


@given(angle, st.floats(1e-3, math.pi - 1e-3), angle)
def test_euler313_round_trip_away_from_gimbal_lock(psi, theta, phi):
    C = rot.euler313_to_matrix(psi, theta, phi)
    out = rot.matrix_to_euler313(C)
    # The angles come back; tolerance grows as 1/sin ϑ (conditioning of ψ, φ near lock).
    tol = ROUNDOFF / math.sin(theta)
    assert np.allclose(np.angle(np.exp(1j * (np.array(out) - (psi, theta, phi)))), 0.0, atol=tol)


@pytest.mark.parametrize("theta", [0.0, math.pi, 1e-14, math.pi - 1e-14])
@pytest.mark.parametrize("psi,phi", [(0.3, -1.2), (2.5, 2.9), (-3.0, 0.1)])
def test_euler313_at_gimbal_lock(psi, theta, phi):
    C = rot.euler313_to_matrix(psi, theta, phi)
    p2, t2, f2 = rot.matrix_to_euler313(C)
    # The matrix is reproduced exactly; only ψ + φ (ϑ = 0) or ψ − φ (ϑ = π) is defined.
    assert np.allclose(rot.euler313_to_matrix(p2, t2, f2), C, atol=ROUNDOFF)
    combo = (psi + phi, p2 + f2) if theta < 1 else (psi - phi, p2 - f2)
    assert abs(np.angle(np.exp(1j * (combo[0] - combo[1])))) < 1e-12


def test_kframe_matches_section_2_of_the_theory_page():
    rho, sigma = 0.7, -2.1
    Xi = rot.kframe_matrix(rho, sigma)
    e_K = np.array(
        [math.sin(rho) * math.cos(sigma), math.sin(rho) * math.sin(sigma), math.cos(rho)]
    )
    assert np.allclose(Xi[:, 2], e_K, atol=ROUNDOFF)
    # ξ1 = ∂e_K/∂ρ, ξ2 = (−sin σ, cos σ, 0); right-handed.
    h = 1e-6
    d = (rot.kframe_matrix(rho + h, sigma)[:, 2] - rot.kframe_matrix(rho - h, sigma)[:, 2]) / (
        2 * h
    )
    assert np.allclose(Xi[:, 0], d, atol=1e-9)  # central difference error O(h²)
    assert np.allclose(np.linalg.det(Xi), 1.0, atol=ROUNDOFF)
    # Body axis x3 and K in each other's frames, theory §2.
    psi, theta, phi = 0.4, 1.1, -0.8
    C = rot.euler313_to_matrix(psi, theta, phi)
    st, ct = math.sin(theta), math.cos(theta)
    assert np.allclose(C[:, 2], [st * math.sin(psi), -st * math.cos(psi), ct], atol=ROUNDOFF)
    assert np.allclose(C[2, :], [st * math.sin(phi), st * math.cos(phi), ct], atol=ROUNDOFF)


@given(st.floats(0.01, math.pi - 0.01), angle, angle, st.floats(0.01, math.pi - 0.01), angle)
def test_kframe_angles_round_trip(rho, sigma, psi, theta, phi):
    R = rot.attitude_from_kframe_angles(rho, sigma, psi, theta, phi)
    K = R @ (
        np.array(
            [math.sin(theta) * math.sin(phi), math.sin(theta) * math.cos(phi), math.cos(theta)]
        )
        * 2.5
    )
    out = np.array(rot.kframe_angles_from_attitude(R, K))
    # K is built from body components, so ρ, σ come back; ψ, φ conditioned by 1/sin ϑ, 1/sin ρ.
    tol = ROUNDOFF * 10 / (math.sin(theta) * math.sin(rho))
    assert np.allclose(np.angle(np.exp(1j * (out - (rho, sigma, psi, theta, phi)))), 0.0, atol=tol)


@pytest.mark.parametrize("rho", [0.0, math.pi])
def test_kframe_angles_at_rho_singularity(rho):
    sigma, psi, theta, phi = 0.9, -0.4, 1.2, 2.2
    R = rot.attitude_from_kframe_angles(rho, sigma, psi, theta, phi)
    K = R @ np.array(
        [math.sin(theta) * math.sin(phi), math.sin(theta) * math.cos(phi), math.cos(theta)]
    )
    r2, s2, p2, t2, f2 = rot.kframe_angles_from_attitude(R, K)
    # Only σ + ψ (ρ = 0) or σ − ψ (ρ = π) is defined; the attitude is reproduced exactly.
    assert np.allclose(rot.attitude_from_kframe_angles(r2, s2, p2, t2, f2), R, atol=1e-12)
    assert abs(r2 - rho) < 1e-12 and abs(t2 - theta) < 1e-12
    combo = (sigma + psi, s2 + p2) if rho == 0.0 else (sigma - psi, s2 - p2)
    assert abs(np.angle(np.exp(1j * (combo[0] - combo[1])))) < 1e-12
