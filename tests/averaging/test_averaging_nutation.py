"""The averaging engine in the nonlinear-moment setting: a torque in body axes, averaged over ψ
and φ and Volosov-averaged over the nutation, against the paper's (2.2)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from tumble.averaging import torus_mean
from tumble.averaging.nutation import numeric_averages, torque_perturbation
from tumble.errors import ParameterError
from tumble.models import nonlinear_moment as nm
from tumble.models.nonlinear_moment import perturbation as nm_perturbation
from tumble.torques import ConstantBodyTorque, LinearDrag
from tumble.unperturbed.symmetric_body import NutationOrbit


def test_torus_mean_is_spectrally_accurate():
    # ⟨exp(cos x)⟩ = I0(1) and ⟨exp(cos x + sin y)⟩ = I0(1)²: round-off after a few doublings.
    from scipy.special import i0

    value, n = torus_mean(lambda x: np.exp(np.cos(x)))
    assert abs(value - i0(1.0)) < 1e-14 and n <= 64
    value, _ = torus_mean(lambda x, y: np.exp(np.cos(x) + np.sin(y)), dims=2)
    assert abs(value - i0(1.0) ** 2) < 1e-13


@settings(max_examples=10)
@given(
    st.tuples(st.floats(0.3, 1.8), st.floats(-2.0, 0.0), st.floats(-1.5, 1.5)),
    st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)),
    st.tuples(st.floats(0.3, math.pi - 0.3), st.floats(-1.0, 1.0)),
    st.tuples(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0)),
)
def test_damping_torque_through_the_engine_equals_the_closed_form(body, momenta, start, damping):
    mu, a, b = body
    R, G = momenta
    theta, theta_dot = start
    d, nu = damping
    try:
        orbit = NutationOrbit.from_state(mu, a, b, R, G, theta, theta_dot)
    except ParameterError:
        assume(False)  # no regular orbit through this state
    # Near a separatrix or a pole the trapezoidal rules need many nodes.
    assume(orbit.mc >= 1e-4 and min(orbit.theta_min, math.pi - orbit.theta_max) >= 0.05)
    p = nm.Params(mu=mu, a=a, b=b, eps=0.01, d=d, nu=nu, pressure=nm.Pressure("exp"))

    def damping_torque(t, q, omega):
        # Theory §9 per unit A and ε, one state at a time: −d(p, q, 0) − ν(0, 0, R), R = μr.
        return np.array([-d * omega[0], -d * omega[1], -nu * mu * omega[2]])

    pert = torque_perturbation(
        damping_torque,
        mu,
        ab_rate=lambda tau: tuple(float(v) for v in p.ab_rate(tau)),
        vectorized=False,
    )
    g_engine, z_engine = numeric_averages(orbit, pert, 0.2)
    g_closed, z_closed = nm_perturbation._builtin_averages(orbit, p, 0.2)
    scale = max(1.0, abs(g_closed), float(np.max(np.abs(z_closed))))
    # Both to round-off (trapezoidal rules converged to 1e-12 relative): the required 1e-10.
    assert abs(g_engine - g_closed) < 1e-10 * scale
    assert np.max(np.abs(z_engine - z_closed)) < 1e-10 * scale
    # And the averaged right-hand side (2.2) built from them.
    y = np.array([orbit.E, R, G, a, b])
    engine = nm.averaged_rhs(1.0, y, p, u_hint=math.cos(theta), perturbation=pert)
    closed = nm.averaged_rhs(1.0, y, p, u_hint=math.cos(theta))
    assert np.max(np.abs(engine - closed)) < 1e-10 * p.eps * scale


def test_engine_with_a_batched_torque_on_a_fixed_orbit():
    # The same comparison on one fixed double-well orbit, with the model's own (batched)
    # damping torque: the path `averaging = "numeric"` takes.
    p = nm.Params(mu=0.8, a=-1.0, b=-0.3, eps=0.01, d=0.5, nu=0.2, pressure=nm.Pressure("exp"))
    orbit = NutationOrbit.from_state(0.8, -1.0, -0.3, 0.4, 0.6, 1.0, 0.3)
    g_engine, z_engine = numeric_averages(orbit, nm.engine_perturbation(p), 0.3)
    g_closed, z_closed = nm_perturbation._builtin_averages(orbit, p, 0.3)
    # Round-off of both rules (converged to 1e-12): the required 1e-10.
    assert abs(g_engine - g_closed) < 1e-10
    assert np.max(np.abs(z_engine - z_closed)) < 1e-10


def test_torque_of_the_body_rate_is_averaged_over_phi_only():
    # The damping of §9 as the built-in LinearDrag(diag(d, d, νμ)), plus a constant body
    # moment (zero mean over φ for its p, q components): functions of the body rate known
    # from their types, averaged over φ alone. Against the closed form, and against the same
    # torque called one state at a time on the full ψ, φ torus (the generic path).
    p = nm.Params(mu=0.8, a=-1.0, b=-0.3, eps=0.01, d=0.5, nu=0.2, pressure=nm.Pressure("exp"))
    orbit = NutationOrbit.from_state(0.8, -1.0, -0.3, 0.4, 0.6, 1.0, 0.3)
    drag = LinearDrag(np.diag([p.d, p.d, p.nu * p.mu]))
    g_closed, z_closed = nm_perturbation._builtin_averages(orbit, p, 0.3)
    pert = torque_perturbation(drag, p.mu, ab_rate=lambda tau: tuple(map(float, p.ab_rate(tau))))
    g_fast, z_fast = numeric_averages(orbit, pert, 0.3)
    # Round-off of both rules (converged to 1e-12): the required 1e-10.
    assert abs(g_fast - g_closed) < 1e-10
    assert np.max(np.abs(z_fast - z_closed)) < 1e-10
    both = drag + ConstantBodyTorque([0.3, -0.2, 0.1])
    fast = numeric_averages(orbit, torque_perturbation(both, p.mu), 0.3)
    slow = numeric_averages(orbit, torque_perturbation(both, p.mu, vectorized=False), 0.3)
    # The same averages by two quadratures, each converged to 1e-12 relative.
    assert abs(fast[0] - slow[0]) < 1e-10 and np.max(np.abs(fast[1] - slow[1])) < 1e-10
    # A real check: the axial part of the constant moment adds 0.1 to ⟨Φ_R⟩ = ⟨δM_r⟩.
    alone = numeric_averages(orbit, torque_perturbation(drag, p.mu), 0.3)
    assert abs(fast[1][0] - alone[1][0] - 0.1) < 1e-10


def test_a_perturbation_with_zero_averages_converges():
    """Φθ = c (a constant extra moment in θ only) does no work over a period: ⟨Φθθ'⟩ = 0 and
    Φz = 0. The averages must converge to zero (to rtol of the integrand's size |c|·max|θ'|)
    instead of chasing round-off relative to themselves."""
    from tumble.averaging.nutation import Perturbation

    orbit = NutationOrbit.from_state(0.8, -1.0, -0.3, 0.4, 0.6, 1.0, 0.3)
    c = 0.7
    pert = Perturbation(
        phi_theta=lambda tau, th, thd, z: np.full_like(th, c),
        phi_z=lambda tau, th, z: np.zeros((4, np.size(th))),
        name="constant pitch moment",
    )
    g, phi_z = numeric_averages(orbit, pert, 0.0)
    scale = c * float(np.max(np.abs(orbit.theta_dot(np.linspace(0.0, orbit.period, 257)))))
    # 1e-12 relative convergence of the trapezoid (AVERAGE_RTOL) on the integrand's size.
    assert abs(g) < 1e-11 * scale
    assert np.all(phi_z == 0.0)


@settings(max_examples=15, deadline=None)
@given(
    theta=st.floats(0.3, 2.8),
    theta_dot=st.floats(-0.8, 0.8),
    R=st.floats(-0.5, 0.5),
    G=st.floats(-0.5, 0.5),
)
def test_the_general_generator_is_the_turning_point_correction(theta, theta_dot, R, G):
    """The first-order generator of the general mean ↔ osculating map (FFT over the nutation
    phase, zero mean) equals the nonlinear-moment paper's corrected start, the integral from
    the last turning point: for a damping Φθ ∝ θ' the integrand is even about every turning
    point, so the zero-mean antiderivative is the one that vanishes there."""
    from tumble.averaging.nutation import nutation_generator, potential_gradient
    from tumble.models.inputs.nonlinear_moment import orbit_of

    # |G ∓ R| small: the axis passes (near) a pole, where W_R, W_G are singular and the
    # averages are refused (tested elsewhere), not computed.
    assume(abs(G - R) > 0.05 and abs(G + R) > 0.05)
    p = nm.Params(mu=1.2, a=-1.0, b=0.3, eps=0.02, d=0.5, nu=0.2)
    s0 = nm.State(theta, theta_dot, 0.0, 0.0, R, G)
    try:
        orbit = orbit_of(p, s0)
    except ParameterError:  # a separatrix, a pole: no orbit to average over
        assume(False)
    assume(orbit.kind == "elliptic" and orbit.mc > 1e-3)
    assume(0.15 < orbit.theta_min and orbit.theta_max < math.pi - 0.15)  # away from the poles
    pert = nm.builtin_perturbation(p)
    u_H, u_z = nutation_generator(orbit, pert, 0.0)
    z = np.array([R, G, *p.ab(0.0)])
    g_mean, pz_mean = numeric_averages(orbit, pert, 0.0)
    t_star = orbit.turning_time("last")

    def g(th, thd):
        ph, pz = pert.evaluate(0.0, th, thd, z)
        return ph * thd + np.sum(pz * potential_gradient(np.cos(th), z), axis=0)

    def row(i):
        return lambda th, thd: pert.evaluate(0.0, th, thd, z)[1][i]

    paper_H = orbit.time_integral(g, t_star, 0.0) + g_mean * t_star
    paper_z = [orbit.time_integral(row(i), t_star, 0.0) + pz_mean[i] * t_star for i in range(4)]
    # Both are quadratures of an analytic integrand, each converged to ~1e-13 of its size
    # (measured agreement 1e-16); 1e-10 is the bound the general map is held to.
    scale = max(1.0, abs(paper_H))
    assert abs(u_H - paper_H) <= 1e-10 * scale
    assert np.allclose(u_z, paper_z, atol=1e-10 * scale)
