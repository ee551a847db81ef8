"""Resisting-medium model: invariants, the two full forms, and the averaged system (2.2)/(2.3)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from strategies import kappa, matrices, rho_regular, theta_regular, vectors

from tumble.integrate import integrate, simulate
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions
from tumble.models.resisting_medium import averaged as rm_averaged

M = rm.MODEL
GENERAL = rm.Params(
    eps=0.01,
    kappa=0.5,
    a=[0.1, -0.05, 0.3],
    b=[[0.2, 0.01, 0.02], [0.0, 0.25, 0.0], [0.03, 0.0, 0.1]],
    s=[[0.1, 0.0, 0.01], [0.0, 0.12, 0.0], [0.0, 0.02, 0.05]],
)
START = rm.State(k=1.0, rho=1.2, sigma=0.3, psi=0.2, theta=1.0, phi=0.1)


def test_invariants_at_zero_eps():
    """Theory §13.1: |K|, energy, ρ, σ, ϑ constant; ψ, φ advance at the rates of (2.1)."""
    p = GENERAL.with_eps(0.0)
    tau = np.linspace(0.0, 500.0, 501)
    rtol = 1e-11
    c = simulate(M, p, START, tau, "full", rtol=rtol, atol=1e-13).columns
    # Over ~700 steps the global error stays within a few hundred rtol.
    for name in ("k", "theta", "rho", "sigma"):
        assert np.max(np.abs(c[name] - getattr(START, name))) < 1e-8, name
    k, kap = START.k, p.kappa
    assert np.max(np.abs(c["psi"] - (START.psi + k * tau))) < 1e-8
    phi_rate = -k * kap / (1 + kap) * math.cos(START.theta)
    assert np.max(np.abs(c["phi"] - (START.phi + phi_rate * tau))) < 1e-8
    sol = integrate(
        lambda t, y: rm.full_rhs(t, y, p), rm.full_from_slow(p, START), 500.0, rtol=rtol, atol=1e-13
    )
    inv = rm.invariants(p, sol(tau))
    for name, values in inv.items():  # |k|, energy and the inertial components of k
        assert np.max(np.abs(values - values[0])) < 1e-8, name


def test_full_from_slow_round_trip():
    y = rm.full_from_slow(GENERAL, START)
    cols = rm.slow_from_full(GENERAL, np.zeros(1), y[None, :])
    for name in ("k", "rho", "sigma", "psi", "theta", "phi"):
        assert cols[name][0] == pytest.approx(getattr(START, name), abs=1e-14)


@pytest.mark.parametrize(
    "p,st_",
    [
        (GENERAL, START),
        # prolate body, lower hemisphere, a3 < 0
        (
            rm.Params(
                eps=0.02,
                kappa=-0.4,
                a=[0.05, 0.1, -0.2],
                b=[[0.15, -0.02, 0.0], [0.03, 0.1, 0.01], [0.0, 0.02, 0.2]],
                s=[[0.05, 0.01, 0.0], [0.0, 0.08, 0.0], [0.01, 0.0, 0.1]],
            ),
            rm.State(k=1.2, rho=2.0, sigma=-1.0, psi=1.0, theta=2.2, phi=-0.5),
        ),
    ],
)
def test_two_full_forms_agree(p, st_):
    """Euler + quaternions and the standard form (1.3) agree to 1e-7 over τ = 2/ε."""
    tau = np.linspace(0.0, 2.0 / p.eps, 201)
    a = simulate(M, p, st_, tau, "full", rtol=1e-11, atol=1e-13)
    b = simulate(M, p, st_, tau, "full", form="osculating", rtol=1e-11, atol=1e-13)
    # Asked 1e-11 per step over ~5e3 steps; both forms carry it into k, ρ, σ, ϑ as ~1e-9.
    for name in ("k", "theta", "rho", "sigma"):
        assert np.max(np.abs(a.columns[name] - b.columns[name])) < 1e-7, name
    # ψ, φ accumulate phase at rate ~k: the same budget ×10 (§13.2).
    for name in ("psi", "phi"):
        assert np.max(np.abs(a.columns[name] - b.columns[name])) < 1e-6, name


def _numerical_average(p, k, rho, theta, n_phi=4096, n_psi=8):
    """Average the (1.3) right-hand side over ψ, φ on the unperturbed torus (2.1)."""
    phi = np.linspace(0.0, 2 * np.pi, n_phi, endpoint=False)
    psi = np.linspace(0.0, 2 * np.pi, n_psi, endpoint=False)
    total = np.zeros(6)
    for ps in psi:
        for f in phi:
            total += rm.osculating_rhs(0.0, np.array([k, rho, 0.3, ps, theta, f]), p)
    return total / (n_phi * n_psi)


@settings(max_examples=6)
@given(vectors(), matrices(), matrices(0.5), kappa, st.floats(0.5, 2.0), rho_regular, theta_regular)
def test_averaged_rhs_equals_numerical_average(a, b, s, kap, k, rho, theta):
    """Theory §13.3: off-diagonal entries, a1, a2 drop out; γ = 4(s11+s22)/(3π) (E6)."""
    p = rm.Params(eps=0.01, kappa=kap, a=a, b=b, s=s)
    avg = _numerical_average(p, k, rho, theta, n_phi=1024, n_psi=4)
    expected = rm.averaged_rhs(0.0, np.array([k, theta]), p)
    # |sin φ|³ has a jump in its third derivative: trapezoid error O(N⁻⁴) ≈ 1e-12 at N = 1024.
    scale = p.eps * (1 + np.abs(a).sum() + np.abs(b).sum() + np.abs(s).sum())
    assert abs(avg[0] - expected[0]) < 1e-9 * scale  # dk/dτ
    assert abs(avg[4] - expected[1]) < 1e-9 * scale  # dϑ/dτ
    assert abs(avg[1]) < 1e-9 * scale and abs(avg[2]) < 1e-9 * scale  # ⟨dρ⟩ = ⟨dσ⟩ = 0


@given(vectors(), matrices(), matrices(), kappa, st.floats(0.01, 3.0), st.floats(0.0, math.pi))
def test_averaged_rhs_chain_rule_to_wv_form(a, b, s, kap, k, theta):
    """Theory §13.4: (2.2) written for W = k cos ϑ, V = k sin ϑ is (2.3), to round-off."""
    p = rm.Params(eps=0.03, kappa=kap, a=a, b=b, s=s)
    dk, dth = rm.averaged_rhs(0.0, np.array([k, theta]), p)
    dW = dk * math.cos(theta) - k * math.sin(theta) * dth
    dV = dk * math.sin(theta) + k * math.cos(theta) * dth
    ref = rm.averaged_rhs_wv(0.0, np.array([k * math.cos(theta), k * math.sin(theta)]), p)
    scale = p.eps * (1 + np.abs(a).sum() / k + (np.abs(b).sum() + np.abs(s).sum() * k) * k)
    assert np.allclose([dW, dV], ref, rtol=0, atol=1e-13 * scale)  # a few ulps of the terms


def test_exact_case_full_equals_averaged_across_pi_half():
    """Theory §10.1/§13.7: a1 = a2 = 0, b11 = b22, b12 = −b21, other off-diagonals 0, S = s33 only:
    the k, ϑ equations of the full model do not depend on φ and coincide with (2.2), even
    through ϑ = π/2."""
    p = rm.Params(
        eps=0.02,
        kappa=0.6,
        a=[0.0, 0.0, 0.4],
        b=[[0.1, 0.05, 0.0], [-0.05, 0.1, 0.0], [0.0, 0.0, 0.3]],
        s=[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.2]],
    )
    assert not rm.moment_depends_on_phi(p)
    st_ = rm.State(k=1.0, rho=1.0, sigma=0.0, psi=0.0, theta=2.5, phi=0.3)
    tau = np.linspace(0.0, 2.0 / p.eps, 401)
    assert rm.crossing_time(st_.W, p) < tau[-1]  # it does cross π/2
    full = simulate(M, p, st_, tau, "full", rtol=1e-12, atol=1e-14)
    cf = simulate(M, p, st_, tau, "closed_form")
    # No averaging error at all: only the integration error (asked 1e-12 per step).
    assert np.max(np.abs(full.columns["k"] - cf.columns["k"])) < 1e-9
    assert np.max(np.abs(full.columns["theta"] - cf.columns["theta"])) < 1e-9


def test_scale_invariance():
    """Theory §13.9: ε → cε with a, b, s → (a, b, s)/c changes nothing."""
    c = 4.0
    p2 = rm.Params(
        eps=GENERAL.eps * c, kappa=GENERAL.kappa, a=GENERAL.a / c, b=GENERAL.b / c, s=GENERAL.s / c
    )
    tau = np.linspace(0.0, 100.0, 51)
    a = simulate(M, GENERAL, START, tau, "full", rtol=1e-11, atol=1e-13)
    b = simulate(M, p2, START, tau, "full", rtol=1e-11, atol=1e-13)
    for name in ("k", "theta", "rho", "sigma"):
        assert np.max(np.abs(a.columns[name] - b.columns[name])) < 1e-9, name


@settings(max_examples=40)
@given(vectors(), matrices(), matrices(), kappa, st.floats(0.01, 3.0), rho_regular, theta_regular)
def test_compiled_averaged_forms_equal_the_engines_quadrature(a, b, s, kap, k, rho, theta):
    """(2.2) and (2.3) as the forms run them (their compiled kernels) against an independent
    oracle: the general engine's quadrature of the standard form (1.3) over ψ and φ
    (:func:`rm.averaged_rhs_numeric`), taken to W = k cos ϑ, V = k sin ϑ for (2.3)."""
    from tumble.kernels import evaluate_rhs

    p = rm.Params(eps=0.01, kappa=kap, a=a, b=b, s=s)
    st_ = rm.State(k, rho, 0.2, 0.0, theta, 0.0)
    dk, _, _, dth = rm.averaged_rhs_numeric(0.0, np.array([k, rho, 0.2, theta]), p)
    c, sn = math.cos(theta), math.sin(theta)
    expected = {"k_theta": [dk, dth], "W_V": [dk * c - k * sn * dth, dk * sn + k * c * dth]}
    # The engine's quadrature converges to AVERAGE_RTOL = 1e-12 of ε max|m| on the torus
    # (|w| ≤ k/min(1, 1 + κ)), the rates carry factors 1/k and k: measured 1.7e-14 of this
    # scale over 400 random points; 1e-10 is the engine's agreement budget of
    # test_averaging_spinner.
    w = k / min(1.0, 1.0 + kap)
    size = np.abs(a).sum() + np.abs(b).sum() * w + np.abs(s).sum() * w * w
    scale = p.eps * max(size, 1e-300) * (1.0 + k + 1.0 / k)
    for form, y in (("k_theta", [k, theta]), ("W_V", [st_.W, st_.V])):
        avg = next(
            f for f in (rm_averaged._AVERAGED_KTHETA, rm_averaged._AVERAGED_WV) if f.name == form
        )
        assert avg.kernel is not None
        compiled = evaluate_rhs(avg.kernel(p), 0.0, y)
        assert np.allclose(compiled, expected[form], rtol=0.0, atol=1e-10 * scale), form


@pytest.mark.parametrize("theta0", [1.0, 2.2, 0.0])
def test_compiled_averaged_run_equals_scipys_across_the_equator(theta0):
    """The compiled run, split at the equator crossing the closed form of W gives, against
    scipy's run of the same split system and against the closed form: the same solution."""
    p = rm.Params(eps=0.02, kappa=0.5, a=[0.0, 0.0, -0.4 if theta0 < 1.5 else 0.4],
                  b=np.diag([0.1, 0.1, 0.2]), s=np.diag([0.05, 0.05, 0.1]))  # fmt: skip
    st_ = rm.State(1.0, 0.4, 0.2, 0.0, theta0, 0.0)
    tau = np.linspace(0.0, 300.0, 301)
    alone = AveragingOptions(averaged_only=True)  # (2.2) itself, no step at the passage
    compiled = simulate(M, p, st_, tau, "averaged", rtol=1e-11, atol=1e-13, averaging=alone)
    scipy = simulate(M, p, st_, tau, "averaged", rtol=1e-11, atol=1e-13, integrator="scipy",
                     averaging=alone)  # fmt: skip
    closed = simulate(M, p, st_, tau, "closed_form")
    assert compiled.integrator == "numba" and scipy.integrator == "scipy"
    if theta0 != 0.0:
        assert np.isfinite(rm.crossing_time(st_.W, p)) and rm.crossing_time(st_.W, p) < 300.0
    for v in ("k", "theta"):
        # Two runs at rtol 1e-11 over ~300/h steps, each within ~1e-9 of the exact solution.
        assert np.allclose(compiled.columns[v], scipy.columns[v], rtol=0.0, atol=1e-8), v
        assert np.allclose(compiled.columns[v], closed.columns[v], rtol=0.0, atol=1e-8), v


@pytest.mark.parametrize("sigma0", [0.2, 7.0, -9.5])
def test_averaged_azimuth_is_the_initial_one_on_every_path(sigma0):
    """σ is constant in (2.2) and (2.3): its column is the initial σ at every sample, on the
    compiled (streamed, nothing to unwrap) and scipy paths alike, whatever its turn."""
    p = rm.Params(eps=0.02, kappa=0.5, a=[0.0, 0.0, -0.4], b=np.diag([0.1, 0.1, 0.2]),
                  s=np.diag([0.05, 0.05, 0.1]))  # fmt: skip
    st_ = rm.State(1.0, 0.4, sigma0, 0.0, 1.0, 0.0)
    tau = np.linspace(0.0, 300.0, 301)
    for integrator in ("auto", "scipy"):
        run = simulate(M, p, st_, tau, "averaged", integrator=integrator)
        assert np.array_equal(run.columns["sigma"], np.full(tau.size, sigma0)), integrator
        assert np.array_equal(run.columns["rho"], np.full(tau.size, 0.4)), integrator
