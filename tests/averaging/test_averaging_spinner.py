"""The averaging engine in the fast-spinner setting: any torque averaged over ψ and φ of the
unperturbed motion (2.1), against the paper's (2.2) and against hand-derived rates."""

from __future__ import annotations

import math
import time
from functools import partial

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import angle, kappa, matrices, rho_regular, theta_regular, vectors

from tumble.averaging import AveragingError, torus_mean
from tumble.averaging.quadrature import AVERAGE_RTOL
from tumble.averaging.spinner import (
    _spinner_average,
    body_momentum,
    spinner_average,
    standard_form,
)
from tumble.errors import ParameterError
from tumble.models import resisting_medium as rm
from tumble.models.resisting_medium import full as rm_full
from tumble.rotations import (
    attitude_from_kframe_angles,
    euler313_to_matrix,
    kframe_angles_from_attitude,
    kframe_matrix,
    matrix_to_quat,
    quat_to_matrix,
)

# The engine converges its quadrature to AVERAGE_RTOL = 1e-12 of the largest |m| on the torus;
# the requirement is agreement with the closed forms to 1e-10 of the scale of the rates.
AGREEMENT = 1e-10


def medium(p: rm.Params):
    """The moment m of (1.2) as a batched torque (the model's own law, without ε)."""
    return lambda t, q, w: rm_full._body_moment(p, w)


def rate_scale(p: rm.Params, k: float, rho: float) -> np.ndarray:
    """Size of each averaged rate: ε max|m| times the factors 1, 1/k, 1/(k sin ρ), 1/k of (1.3).

    |m| ≤ Σ|a_i| + Σ|b_ij| |w| + Σ|s_ij| |w|² with |w| ≤ c k, c = 1/min(1, 1 + κ) (entrywise
    sums bound the 2-norms and, unlike them, do not underflow for tiny hypothesis entries).
    """
    c = 1.0 / min(1.0, 1.0 + p.kappa)
    m = np.abs(p.a).sum() + np.abs(p.b).sum() * c * k + np.abs(p.s).sum() * (c * k) ** 2
    return p.eps * max(m, 1e-300) * np.array([1.0, 1.0 / k, 1.0 / (k * math.sin(rho)), 1.0 / k])


def closed_form(p: rm.Params, k: float, theta: float) -> np.ndarray:
    """(2.2) as (dk, dρ, dσ, dϑ)/dτ: ρ and σ are constant."""
    dk, dtheta = rm.averaged_rhs(0.0, np.array([k, theta]), p)
    return np.array([dk, 0.0, 0.0, dtheta])


# ---------------------------------------------------------------------------------------------
# The resisting-medium moment (1.2): the engine reproduces (2.2).

MEDIUM_POINTS = (
    vectors(),  # a
    matrices(),  # b
    matrices(),  # s
    kappa,
    st.floats(0.05, 1.0),  # ε
    st.floats(0.2, 3.0),  # k
    rho_regular,
    angle,  # σ
    theta_regular,
    angle,  # τ
)
"""Random points of the resisting-medium model's domain: medium, body and slow state."""


@settings(max_examples=60)
@given(*MEDIUM_POINTS)
def test_engine_equals_closed_form_2_2(a, b, s, kap, eps, k, rho, sigma, theta, t):
    """Random points of the model's domain, full random a, b, s."""
    p = rm.Params(eps=eps, kappa=kap, a=a, b=b, s=s)
    engine = spinner_average(medium(p), kap, eps, k, rho, sigma, theta, t)
    # The quadrature is converged to 1e-12 of max|m|; measured worst ~1e-13 of the scale.
    assert np.all(np.abs(engine - closed_form(p, k, theta)) <= AGREEMENT * rate_scale(p, k, rho))


@settings(max_examples=60)
@given(*MEDIUM_POINTS)
def test_model_torque_takes_the_rate_path_and_equals_2_2(
    a, b, s, kap, eps, k, rho, sigma, theta, t
):
    """``Params.torque`` (built-in Torque objects, as resisting_medium.averaged_rhs_numeric
    passes it) is recognized as a moment of the body rate: one ψ node, and the Romberg
    extrapolation in φ settles the quadratic law with at most 1024 nodes (256–512 measured
    over 2000 random points; plain doubling needs 1024–4096)."""
    p = rm.Params(eps=eps, kappa=kap, a=a, b=b, s=s)
    rates, n_psi, n_phi = _spinner_average(
        p.torque, kap, 1.0, (k, rho, sigma, theta), t, AVERAGE_RTOL, None
    )
    assert n_psi == 1 and n_phi <= 1024
    # Same budget as the general path above (quadrature converged to 1e-12 of max|m|).
    assert np.all(np.abs(rates - closed_form(p, k, theta)) <= AGREEMENT * rate_scale(p, k, rho))


@pytest.mark.parametrize("offset", [0.0, 1e-9, -1e-6, 1e-3])
def test_engine_near_theta_pi_half_with_phi_dependent_moment(offset):
    """At and near ϑ = π/2 (φ stops there, §10.2) the mean over the torus still equals
    (2.2), which is regular at π/2, for a moment whose k, ϑ equations depend on φ."""
    p = rm.Params(
        eps=0.02,
        kappa=-0.4,
        a=[0.3, -0.2, 0.1],
        b=[[0.2, 0.05, -0.1], [0.02, 0.35, 0.04], [0.1, -0.03, 0.15]],
        s=[[0.1, 0.02, 0.0], [-0.01, 0.2, 0.03], [0.02, 0.0, 0.3]],
    )
    assert rm.moment_depends_on_phi(p)
    k, rho, theta = 1.3, 0.9, math.pi / 2 + offset
    engine = spinner_average(medium(p), p.kappa, p.eps, k, rho, 0.4, theta)
    # Same budget as the random points (quadrature converged to 1e-12 of max|m|).
    assert np.all(np.abs(engine - closed_form(p, k, theta)) <= AGREEMENT * rate_scale(p, k, rho))


def test_composable_model_torque_batched_and_one_state_at_a_time():
    """``Params.torque`` (ε m as composable Torque objects, which accept batches) gives (2.2)
    batched, and the same when forced to one call per node."""
    p = rm.Params(
        eps=0.01,
        kappa=0.5,
        a=[0.1, -0.05, 0.3],
        b=[[0.2, 0.01, 0.02], [0.0, 0.25, 0.0], [0.03, 0.0, 0.1]],
        s=[[0.1, 0.0, 0.01], [0.0, 0.12, 0.0], [0.0, 0.02, 0.05]],
    )
    k, rho, theta = 1.1, 1.2, 2.0
    engine = spinner_average(p.torque, p.kappa, 1.0, k, rho, 0.3, theta)  # ε is in the torque
    # Same quadrature budget as above.
    assert np.all(np.abs(engine - closed_form(p, k, theta)) <= AGREEMENT * rate_scale(p, k, rho))
    single = spinner_average(p.torque, p.kappa, 1.0, k, rho, 0.3, theta, batched=False)
    # Same nodes, same arithmetic per node: round-off apart.
    assert np.all(np.abs(engine - single) <= AGREEMENT * rate_scale(p, k, rho))


def test_one_state_torque_that_broadcasts_wrongly_is_detected():
    """A one-state torque m = c·w[2] (= c r) returns shape (3,) when handed a batch (w[2] is
    then a node, not a component): the two-node probe catches it, and the result is that of
    the constant body moment a = c r, i.e. (2.2) with a3 = c3 r."""
    c = np.array([0.4, -0.3, 0.7])
    kap, k, rho, theta = 0.6, 1.4, 1.1, 0.8
    r = k * math.cos(theta) / (1.0 + kap)
    engine = spinner_average(lambda t, q, w: c * w[2], kap, 0.05, k, rho, 0.0, theta)
    p = rm.Params(eps=0.05, kappa=kap, a=c * r)
    # Same quadrature budget as above.
    assert np.all(np.abs(engine - closed_form(p, k, theta)) <= AGREEMENT * rate_scale(p, k, rho))


# ---------------------------------------------------------------------------------------------
# Torques that depend on the attitude: rates derived by hand.


def inertial_constant(M):
    """A moment fixed in inertial space, M_body = R(q)ᵀ M (batched)."""
    M = np.asarray(M, dtype=float)
    return lambda t, q, w: np.einsum("...ji,j->...i", quat_to_matrix(q), M)


@settings(max_examples=20)
@given(vectors(), kappa, st.floats(0.2, 3.0), rho_regular, angle, theta_regular)
def test_inertially_fixed_torque_by_hand(M, kap, k, rho, sigma, theta):
    """A constant inertial moment M: its K-frame components m_K = C R(q)ᵀ M = Ξ(ρ, σ)ᵀ M do not
    depend on ψ, φ at all (R = Ξ C), so by (1.3)

        ⟨dk/dτ⟩ = ε ξ3·M,  ⟨dρ/dτ⟩ = ε ξ1·M / k,  ⟨dσ/dτ⟩ = ε ξ2·M / (k sin ρ),

    and dϑ/dτ = ε μ2/k with μ2 = m2 cos ψ − m1 sin ψ, whose mean over ψ is 0."""
    eps = 0.01
    engine = spinner_average(inertial_constant(M), kap, eps, k, rho, sigma, theta)
    xi = kframe_matrix(rho, sigma)
    mk = xi.T @ M
    expected = eps * np.array([mk[2], mk[0] / k, mk[1] / (k * math.sin(rho)), 0.0])
    scale = eps * (np.abs(M).sum() + 1e-300) * np.array([1, 1 / k, 1 / (k * math.sin(rho)), 1 / k])
    # Smooth (trigonometric) integrand: converged to round-off, far inside 1e-10.
    assert np.all(np.abs(engine - expected) <= AGREEMENT * scale)


@settings(max_examples=20)
@given(kappa, st.floats(0.2, 3.0), rho_regular, angle, theta_regular, angle, angle)
def test_gravity_gradient_like_torque_by_hand(kap, k, rho, sigma, theta, lat, lon):
    """The moment 3 e × (J e), J = diag(1, 1, 1 + κ), e the body components of a fixed inertial
    unit vector ê: in inertial axes 3κ (ê·x3)(ê × x3). x3 precesses about e_K at the angle ϑ
    (x3 = cos ϑ e_K + sin ϑ n(ψ)), and
    ⟨(ê·x3) x3⟩_ψ = cos²ϑ (ê·e_K) e_K + ½ sin²ϑ (ê − (ê·e_K) e_K),
    so ⟨M⟩ = (3κ/2)(3cos²ϑ − 1)(ê·e_K)(ê × e_K): ⟨dk/dτ⟩ = 0 (⟨M⟩ ⊥ e_K), ⟨dρ/dτ⟩ = ε ξ1·⟨M⟩/k,
    ⟨dσ/dτ⟩ = ε ξ2·⟨M⟩/(k sin ρ), and ⟨dϑ/dτ⟩ = 0 (μ2 = −3κ cos ϑ (ê·x3)(ê·N), N the line of
    nodes, averages to 0). The moment is of degree 2 in ψ: the engine must refine ψ."""
    eps = 0.01
    e_hat = np.array([math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)])
    J = np.array([1.0, 1.0, 1.0 + kap])

    def gravity_gradient(t, q, w):
        e = np.einsum("...ji,j->...i", quat_to_matrix(q), e_hat)
        return 3.0 * np.cross(e, J * e)

    engine = spinner_average(gravity_gradient, kap, eps, k, rho, sigma, theta)
    xi = kframe_matrix(rho, sigma)
    e_k = xi[:, 2]
    c = math.cos(theta)
    mean = 1.5 * kap * (3 * c * c - 1) * (e_hat @ e_k) * np.cross(e_hat, e_k)
    expected = eps * np.array(
        [0.0, xi[:, 0] @ mean / k, xi[:, 1] @ mean / (k * math.sin(rho)), 0.0]
    )
    scale = eps * 3 * abs(kap) * np.array([1, 1 / k, 1 / (k * math.sin(rho)), 1 / k])
    # Smooth integrand: round-off.
    assert np.all(np.abs(engine - expected) <= AGREEMENT * scale)


def test_torque_receives_the_models_attitude_and_rate():
    """q at every node is matrix_to_quat(attitude_from_kframe_angles(ρ, σ, ψ, ϑ, φ)) (q0 ≥ 0), as
    resisting_medium.full_from_slow builds it, and w = k_b/(1, 1, 1 + κ) at the same φ."""
    kap, k, rho, sigma, theta = -0.3, 1.7, 0.7, -2.0, 2.4
    seen = []

    def record(t, q, w):
        seen.append((np.array(q), np.array(w)))
        # depends on ψ so that more than one ψ node is used
        return np.einsum("...ji,j->...i", quat_to_matrix(q), [0.0, 1.0, 0.0])

    spinner_average(record, kap, 0.01, k, rho, sigma, theta, batched=True)
    q = np.concatenate([s[0] for s in seen])
    w = np.concatenate([s[1] for s in seen])
    R = quat_to_matrix(q)
    kb = w * np.array([1.0, 1.0, 1.0 + kap])
    r, sg, psi, th, phi = kframe_angles_from_attitude(R, np.einsum("nij,nj->ni", R, kb))
    assert len(set(np.round(psi, 9))) > 1
    # Angles of O(1) recovered from matrices built with O(1) round-off: a few ulps.
    assert np.allclose(r, rho, atol=1e-13) and np.allclose(sg, sigma, atol=1e-13)
    assert np.allclose(th, theta, atol=1e-13)
    assert np.allclose(np.linalg.norm(kb, axis=1), k, atol=1e-13)
    assert np.allclose(kb, body_momentum(k, theta, phi), atol=1e-13)
    model = matrix_to_quat(attitude_from_kframe_angles(rho, sigma, psi, theta, phi))
    assert np.all(q[:, 0] >= 0.0)
    assert np.allclose(q, model, atol=1e-13)


# ---------------------------------------------------------------------------------------------
# The kinematics of (1.3), shared with resisting_medium.osculating_rhs.


@settings(max_examples=30)
@given(vectors(), kappa, st.floats(0.2, 3.0), rho_regular, angle, theta_regular, angle)
def test_standard_form_from_kframe_components(m, kap, k, rho, psi, theta, phi):
    """standard_form (via the μ identity of §3) equals (1.3) written with the K-frame
    components m_K = C(ψ, ϑ, φ) m directly."""
    eps = 0.03
    m1, m2, m3 = euler313_to_matrix(psi, theta, phi) @ m
    sp, cp = math.sin(psi), math.cos(psi)
    direct = [
        eps * m3,
        eps * m1 / k,
        eps * m2 / (k * math.sin(rho)),
        k
        - eps / k * (math.cos(theta) / math.sin(theta) * (m2 * sp + m1 * cp) + m2 / math.tan(rho)),
        eps / k * (m2 * cp - m1 * sp),
        -k * kap / (1 + kap) * math.cos(theta) + eps / (k * math.sin(theta)) * (m2 * sp + m1 * cp),
    ]
    got = standard_form(m, k, rho, psi, theta, phi, kap, eps)
    # Two roundings of the same O(1/sin) expressions: round-off of the largest term.
    assert np.allclose(got, direct, rtol=0, atol=1e-13 * (k + 1 / math.sin(theta) ** 2 / k))


# ---------------------------------------------------------------------------------------------
# Where the engine cannot work.


@pytest.mark.parametrize(
    "kap,rho,theta,field",
    [
        (0.5, 1.0, 0.0, "theta"),
        (0.5, 1.0, math.pi, "theta"),
        (0.5, 0.0, 1.0, "rho"),
        (0.5, math.pi, 1.0, "rho"),
        (0.0, 1.0, 1.0, "kappa"),
        (0.5, 1.0, 3.5, "theta"),
    ],
)
def test_refuses_singular_or_degenerate_states(kap, rho, theta, field):
    """sin ϑ = 0, sin ρ = 0 (standard form singular, §11), κ = 0 (no fast φ, §10.5)."""
    with pytest.raises(ParameterError, match=f"^{field} = "):
        spinner_average(lambda t, q, w: np.zeros(3), kap, 0.01, 1.0, rho, 0.0, theta)


def test_reports_non_convergence_and_non_finite_torques():
    def cusp(t, q, w):
        # m3 = √|p|: a cusp at φ = 0, π; the trapezoidal error falls only like n^-1.5.
        return np.stack([0 * w[:, 0], 0 * w[:, 0], np.sqrt(np.abs(w[:, 0]))], -1)

    with pytest.raises(AveragingError, match="did not converge"):
        spinner_average(cusp, 0.5, 0.01, 1.0, 1.0, 0.0, 1.0)
    with pytest.raises(AveragingError, match="non-finite"):
        spinner_average(lambda t, q, w: np.full(3, np.nan), 0.5, 0.01, 1.0, 1.0, 0.0, 1.0)
    with pytest.raises(ParameterError, match="shape"):
        spinner_average(lambda t, q, w: np.zeros(2), 0.5, 0.01, 1.0, 1.0, 0.0, 1.0)


# ---------------------------------------------------------------------------------------------
# Romberg extrapolation of the doubling sequence (torus_mean(..., extrapolate=True)).


def test_romberg_settles_kinks_at_the_nodes():
    """|sin φ|³ has a jump in its third derivative at the nodes 0, π of every grid: the plain
    rule converges like n⁻⁴, the extrapolated one much faster. ⟨|sin φ|³⟩ = 4/(3π)."""
    exact = 4.0 / (3.0 * math.pi)

    def f(x):
        return np.abs(np.sin(x)) ** 3

    plain, n_plain = torus_mean(f, rtol=AVERAGE_RTOL, n_start=16, n_max=1 << 14)
    rich, n_rich = torus_mean(f, rtol=AVERAGE_RTOL, n_start=16, n_max=1 << 14, extrapolate=True)
    assert n_plain >= 2048 and n_rich <= 512
    # Both within the requested 1e-12 of the mean; the extrapolated one to round-off (a few
    # ulps of a mean of 512 values of size ≤ 1).
    assert abs(plain - exact) <= AVERAGE_RTOL * exact
    assert abs(rich - exact) <= 1e-14


@pytest.mark.parametrize(
    "f",
    [
        lambda x: np.abs(np.sin(x) - 0.3),  # kinks at asin 0.3, π − asin 0.3: between nodes
        lambda x: np.sin(x - 1.0) * np.abs(np.sin(x - 1.0)),  # kinks at 1, 1 + π
        lambda x: np.sqrt(np.abs(np.sin(x))),  # cusps at the nodes: not an even-power series
    ],
)
def test_romberg_does_not_accept_what_it_cannot_extrapolate(f):
    """Where the error is no series in h² the extrapolated values do not settle: reported."""
    with pytest.raises(AveragingError, match="did not converge"):
        torus_mean(f, rtol=AVERAGE_RTOL, n_start=16, n_max=1 << 14, extrapolate=True)


def test_romberg_leaves_analytic_integrands_to_the_plain_test():
    """exp(3 cos φ): the trapezoidal means converge first and are returned as they are."""
    from scipy.special import i0

    def f(x):
        return np.exp(3.0 * np.cos(x))

    plain = torus_mean(f, rtol=AVERAGE_RTOL, n_start=16)
    assert torus_mean(f, rtol=AVERAGE_RTOL, n_start=16, extrapolate=True) == plain
    # Spectral convergence: round-off of a mean of values up to e³ (a few ulps of 20).
    assert abs(plain[0] - i0(3.0)) <= 1e-14 * math.exp(3.0)


def test_known_values_serve_the_coarse_levels():
    """``known`` on N nodes replaces the calls of f up to N nodes; it must hold n_start·2^p."""
    calls = []

    def f(x):
        calls.append(x.size)
        return np.abs(np.sin(x)) ** 3

    nodes = 2.0 * math.pi / 256 * np.arange(256)
    mean, _ = torus_mean(f, n_start=16, n_max=1 << 14, extrapolate=True, known=f(nodes))
    assert calls == [256, 256]  # the known values, then the 256 midpoints of the 512 level
    # Same nodes as without known, so the same mean to round-off.
    again, _ = torus_mean(f, n_start=16, n_max=1 << 14, extrapolate=True)
    assert abs(mean - again) <= 1e-15
    with pytest.raises(ValueError, match="n_start"):
        torus_mean(f, n_start=16, known=np.zeros(48))


# ---------------------------------------------------------------------------------------------
# Cost


@pytest.mark.slow
def test_benchmark_resisting_medium_evaluation():
    """One evaluation of the engine for the moment (1.2) at default tolerance (target ≤ 1 ms),
    as resisting_medium.averaged_rhs_numeric makes it (``Params.torque``); the same law as a
    plain batched function goes by the general path (printed, no target).
    benchmarks/averaging_cost.py times every setting."""
    rng = np.random.default_rng(5)
    times = {"quadratic": [], "linear": [], "quadratic, plain function": []}
    for _ in range(10):
        kap = rng.uniform(-0.8, 1.0)
        a, b, s = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, (3, 3)), rng.uniform(-1, 1, (3, 3))
        k, rho, theta = rng.uniform(0.3, 3.0), rng.uniform(0.1, 3.0), rng.uniform(0.05, 3.09)
        quadratic = rm.Params(eps=0.01, kappa=kap, a=a, b=b, s=s)
        linear = rm.Params(eps=0.01, kappa=kap, a=a, b=b)
        y = np.array([k, rho, 0.3, theta])
        calls = {
            "quadratic": partial(rm.averaged_rhs_numeric, 0.0, y, quadratic),
            "linear": partial(rm.averaged_rhs_numeric, 0.0, y, linear),
            "quadratic, plain function": partial(
                spinner_average, medium(quadratic), kap, 0.01, k, rho, 0.3, theta
            ),
        }
        for law, call in calls.items():
            best = math.inf
            for _ in range(7):  # best of 7: the cost of the code, not of the machine's load
                start = time.perf_counter()
                call()
                best = min(best, time.perf_counter() - start)
            times[law].append(best)
    for law, values in times.items():
        print(f"{law:26s} median {1e3 * np.median(values):.2f} ms, max {1e3 * max(values):.2f} ms")
    # Measured here (2 shared cores): ~0.25 ms for both laws (1.4 and 0.6 ms before the rate
    # path and the Romberg extrapolation); ~1 ms as a plain function. The bound.
    assert float(np.median(times["quadratic"])) <= 1e-3
    assert float(np.median(times["linear"])) <= 1e-3
