"""Resisting-medium closed forms (2.4)–(2.10), §8.7, crossing times (§8.4), limits (§9)."""

import math

import numpy as np
import pytest

from tumble.errors import IntegrationError
from tumble.integrate import simulate
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions

M = rm.MODEL
KAPPA = 0.5
# Integrated averaged system, asked 1e-12 relative per step: its global error over ~1e3 steps
# stays ≲ 1e-10, so 1e-8 (the required figure) is met with a margin of 100.
TIGHT = {"rtol": 1e-12, "atol": 1e-14}
ALONE = AveragingOptions(averaged_only=True)  # (2.2) itself: no step at the passage


def medium(alpha=0.0, beta=0.0, gamma=0.0, delta=0.0, a3=0.0, eps=0.01, a12=(0.0, 0.0)):
    """Params with the given α, β, γ, δ of (2.2) (diagonal b, s)."""
    b = np.diag([alpha, alpha, beta * (1 + KAPPA)])
    s = np.diag([gamma * 3 * math.pi / 8, gamma * 3 * math.pi / 8, delta * (1 + KAPPA) ** 2])
    return rm.Params(eps=eps, kappa=KAPPA, a=[*a12, a3], b=b, s=s)


def state(k, theta):
    return rm.State(k=k, rho=1.0, sigma=0.2, psi=0.0, theta=theta, phi=0.0)


# name, params, initial, slow-time horizon ε τ_end, crossing expected
CASES = [
    ("(2.5) a3 > 0 upper", medium(0.2, 0.3, 0.1, 0.2, a3=0.4), state(1.0, 1.0), 10.0, False),
    ("(2.6) -> (2.7)", medium(0.1, 0.2, 0.1, 0.3, a3=-0.5), state(1.0, 0.8), 10.0, True),
    ("(2.7) a3 > 0 -> (2.5)", medium(0.1, 0.5, 0.1, 0.1, a3=0.2), state(1.5, 2.5), 10.0, True),
    ("(2.8) -> (2.5)", medium(0.2, 0.1, 0.1, 0.2, a3=0.6), state(1.0, 2.6), 10.0, True),
    (
        "(2.5) small a3 < 0 -> (2.7)",
        medium(0.1, 0.6, 0.1, 0.1, a3=-0.05),
        state(1.0, 1.2),
        10.0,
        True,
    ),
    ("upper double root", medium(0.1, 0.2, 0.1, 0.1, a3=-0.1), state(1.0, 1.0), 10.0, True),
    ("lower double root", medium(0.1, 0.2, 0.1, 0.1, a3=0.1), state(1.0, 2.0), 10.0, True),
    ("near double root", medium(0.1, 0.2, 0.1, 0.1, a3=-0.1 + 1e-9), state(1.0, 1.0), 10.0, True),
    ("(2.9) a3 = 0 upper", medium(0.2, 0.3, 0.1, 0.2), state(1.0, 0.7), 10.0, False),
    ("(2.10) a3 = 0 lower", medium(0.3, 0.2, 0.1, 0.2), state(1.0, 2.3), 10.0, False),
    ("quadratic upper", medium(gamma=0.3, delta=0.2), state(1.0, 0.5), 20.0, False),
    ("quadratic lower", medium(gamma=0.3, delta=0.2), state(1.0, 2.5), 20.0, False),
    ("delta = 0", medium(0.2, 0.3, 0.1, 0.0, a3=-0.2), state(1.0, 1.0), 10.0, True),
    ("beta = delta = 0", medium(0.2, 0.0, 0.1, 0.0, a3=0.2), state(1.0, 2.0), 10.0, True),
    ("beta = 0, delta > 0", medium(0.2, 0.0, 0.1, 0.2, a3=-0.3), state(1.0, 0.9), 10.0, True),
    ("alpha = 0", medium(0.0, 0.3, 0.2, 0.1, a3=0.2), state(1.0, 1.3), 10.0, False),
    # cos(π/2) = 6e-17 > 0 in floating point: W leaves the upper branch at once.
    ("W0 = 0 start", medium(0.1, 0.2, 0.1, 0.1, a3=-0.2), state(1.0, math.pi / 2), 10.0, True),
    ("W0 at equilibrium", medium(0.1, 0.2, 0.0, 0.1, a3=0.3), state(1.0, 0.0), 5.0, False),
]


@pytest.mark.parametrize("name,p,st,horizon,crosses", CASES, ids=[c[0] for c in CASES])
def test_closed_form_matches_integrated_averaged_system(name, p, st, horizon, crosses):
    """Theory §13.5: every branch of the closed form against integration of (2.2), to 1e-8."""
    if name == "W0 at equilibrium":
        W_plus = (-p.beta + math.sqrt(p.beta**2 + 4 * p.delta * 0.3)) / (2 * p.delta)
        st = state(W_plus, 0.0)
    tau = np.linspace(0.0, horizon / p.eps, 801)
    assert (rm.crossing_time(st.W, p) <= tau[-1]) == crosses
    cf = simulate(M, p, st, tau, "closed_form")
    av = simulate(M, p, st, tau, "averaged", averaging=ALONE, **TIGHT)
    for var in ("k", "theta"):
        assert np.max(np.abs(cf.columns[var] - av.columns[var])) < 1e-8, var


def _printed_window(p, W0, tau):
    """The paper's own formula for the first window (before any crossing)."""
    a3, be, de = float(p.a[2]), p.beta, p.delta
    h = be / (2 * de)
    if W0 >= 0:
        nu_sq = h * h + a3 / de
        f = (
            rm.axial_upper_exp
            if nu_sq > 1e-12
            else rm.axial_upper_tan
            if nu_sq < -1e-12
            else rm.axial_upper_double_root
        )
    else:
        nu_sq = h * h - a3 / de
        f = (
            rm.axial_lower_exp
            if nu_sq > 1e-12
            else rm.axial_lower_tan
            if nu_sq < -1e-12
            else rm.axial_lower_double_root
        )
    return f(tau, W0, p)


@pytest.mark.parametrize(
    "name,p,st,horizon,crosses",
    [c for c in CASES if c[1].delta > 0 and c[2].W != 0 and "near" not in c[0]],
    ids=lambda c: c if isinstance(c, str) else "",
)
def test_printed_formulas_equal_the_well_conditioned_form(name, p, st, horizon, crosses):
    """(2.5)–(2.8) and the double roots as printed (with E3) equal the §8.5 form in their window."""
    tau1 = rm.crossing_time(st.W, p)
    end = min(tau1 * 0.999, horizon / p.eps)
    tau = np.linspace(0.0, end, 300)
    printed = _printed_window(p, st.W, tau)
    ours = rm.axial_momentum(tau, st.W, p)
    # Both are exact; the printed exponential forms lose a few digits to cancellation.
    assert np.max(np.abs(printed - ours)) < 1e-11 * (1 + np.max(np.abs(ours)))


def test_equatorial_component_is_2_4():
    p = medium(0.2, 0.3, 0.1, 0.2)
    tau = np.linspace(0, 500, 11)
    V0 = 0.8
    e = np.exp(-p.eps * p.alpha * tau)
    printed = p.alpha * V0 * e / (p.alpha + p.gamma * V0 * (1 - e))
    assert np.allclose(rm.equatorial_momentum(tau, V0, p), printed, rtol=1e-13, atol=0)
    # α → 0 limit V0/(1 + εγV0τ), and α = γ = 0: V constant (§8.1).
    p0 = medium(0.0, 0.3, 0.1, 0.2)
    assert np.allclose(
        rm.equatorial_momentum(tau, V0, p0), V0 / (1 + p0.eps * p0.gamma * V0 * tau), rtol=1e-14
    )
    assert np.all(rm.equatorial_momentum(tau, V0, medium(beta=0.3)) == V0)


@pytest.mark.parametrize(
    "p,st",
    [(medium(0.2, 0.3, 0.1, 0.2), state(1.0, 0.7)), (medium(0.3, 0.2, 0.1, 0.2), state(1.3, 0.4))],
)
def test_tan_theta_a3_zero_upper_2_9(p, st):
    tau = np.linspace(0.0, 800.0, 81)
    theta = simulate(M, p, st, tau, "closed_form").columns["theta"]
    assert np.allclose(
        rm.tan_theta_a3_zero_upper(tau, st.k, st.theta, p), np.tan(theta), rtol=1e-12
    )


@pytest.mark.parametrize(
    "p,st",
    [(medium(0.3, 0.2, 0.1, 0.2), state(1.0, 2.3)), (medium(0.2, 0.3, 0.1, 0.2), state(1.3, 2.0))],
)
def test_tan_theta_a3_zero_lower_2_10(p, st):
    tau = np.linspace(0.0, 800.0, 81)
    theta = simulate(M, p, st, tau, "closed_form").columns["theta"]
    tan = rm.tan_theta_a3_zero_lower(tau, st.k, st.theta, p)
    assert np.all(tan < 0)  # stays in the lower hemisphere
    assert np.allclose(math.pi + np.arctan(tan), theta, rtol=0, atol=1e-12)


@pytest.mark.parametrize("theta0", [0.5, 2.5])
def test_quadratic_only_law_both_hemispheres(theta0):
    """Theory §8.7 and correction E8: tan ϑ → δ/γ (upper) or −δ/γ (lower); k → 0 like 1/(ετ)."""
    p = medium(gamma=0.3, delta=0.2)
    st = state(1.0, theta0)
    tau = np.linspace(0.0, 1e6, 201)
    theta = simulate(M, p, st, tau, "closed_form").columns["theta"]
    tan = rm.tan_theta_quadratic(tau, st.k, st.theta, p)
    assert np.allclose(np.tan(theta), tan, rtol=1e-11)
    limit = (
        math.atan(p.delta / p.gamma)
        if theta0 < math.pi / 2
        else math.pi - math.atan(p.delta / p.gamma)
    )
    # Algebraic approach ∝ 1/τ: at ετ = 1e4 the remaining gap is ~1e-4 of the initial one.
    assert abs(theta[-1] - limit) < 1e-3
    assert rm.predicted_limits(p, st)["theta"] == pytest.approx(limit, abs=1e-15)


def test_crossing_times_match_the_table_of_the_theory_page():
    """Theory §8.4: τ1 from the table against the closed form's root of W."""
    rows = []
    p = medium(0.1, 0.6, 0.1, 0.1, a3=-0.05)  # W0 > 0, a3 < 0, (2.5) branch
    de, be, a3, e = p.delta, p.beta, -0.05, p.eps
    h = be / (2 * de)
    W0 = 0.5
    nu1 = math.sqrt(h * h + a3 / de)
    c1 = (2 * de * W0 + be - 2 * de * nu1) / (2 * de * W0 + be + 2 * de * nu1)
    rows.append((p, W0, math.log(c1 * (h + nu1) / (h - nu1)) / (2 * e * de * nu1)))
    p = medium(0.1, 0.2, 0.1, 0.3, a3=-0.5)  # (2.6) branch
    de, be, a3 = p.delta, p.beta, -0.5
    mu1 = math.sqrt(-((be / (2 * de)) ** 2) - a3 / de)
    rows.append(
        (
            p,
            W0,
            (math.atan((2 * de * W0 + be) / (2 * de * mu1)) - math.atan(be / (2 * de * mu1)))
            / (e * de * mu1),
        )
    )
    p = medium(0.1, 0.5, 0.1, 0.1, a3=0.2)  # W0 < 0, a3 > 0, (2.7) branch
    de, be, a3 = p.delta, p.beta, 0.2
    h, W0n = be / (2 * de), -0.7
    nu2 = math.sqrt(h * h - a3 / de)
    c2 = (2 * de * (W0n - nu2) - be) / (2 * de * (W0n + nu2) - be)
    rows.append((p, W0n, math.log((h + nu2) / (c2 * (h - nu2))) / (2 * e * de * nu2)))
    p = medium(0.2, 0.1, 0.1, 0.2, a3=0.6)  # (2.8) branch
    de, be, a3 = p.delta, p.beta, 0.6
    mu2 = math.sqrt(a3 / de - (be / (2 * de)) ** 2)
    rows.append(
        (
            p,
            W0n,
            (math.atan((be - 2 * de * W0n) / (2 * de * mu2)) - math.atan(be / (2 * de * mu2)))
            / (e * de * mu2),
        )
    )
    p = medium(0.1, 0.2, 0.1, 0.1, a3=-0.1)  # upper double root
    h = p.beta / (2 * p.delta)
    rows.append((p, W0, (1 / h - 1 / (W0 + h)) / (e * p.delta)))
    p = medium(0.1, 0.2, 0.1, 0.1, a3=0.1)  # lower double root
    y0 = W0n - h
    rows.append((p, W0n, (1 + y0 / h) / y0 / (e * p.delta)))
    p = medium(0.2, 0.3, 0.1, 0.0, a3=-0.2)  # δ = 0, β > 0
    rows.append((p, W0, math.log(1 - p.beta * W0 / -0.2) / (e * p.beta)))
    p = medium(0.2, 0.0, 0.1, 0.0, a3=0.2)  # δ = β = 0
    rows.append((p, W0n, -W0n / (e * 0.2)))
    for p, W0_, expected in rows:
        tau1 = rm.crossing_time(W0_, p)
        assert tau1 == pytest.approx(expected, rel=1e-12)
        assert abs(rm.axial_momentum(np.array([tau1]), W0_, p)[0]) < 1e-13


def test_negative_damping_blow_up_is_reported():
    """Theory §11: negative coefficients are valid solutions of (2.3) but may diverge: raise."""
    p = medium(alpha=0.0, gamma=-0.2, beta=0.1, delta=0.1)
    with pytest.raises(IntegrationError, match="diverges at τ"):
        rm.closed_form(p, state(1.0, 1.0), np.linspace(0, 1e4, 10))


def test_k_through_zero_is_reported():
    """Theory §11: V0 = 0 and W changes sign: averaged k passes 0, ϑ jumps; a warning, not
    silence."""
    p = medium(0.1, 0.2, 0.1, 0.1, a3=0.3)
    st = state(1.0, math.pi)
    tau = np.linspace(0.0, 1000.0, 201)
    cf = simulate(M, p, st, tau, "closed_form")
    av = simulate(M, p, st, tau, "averaged", averaging=ALONE, **TIGHT)
    # sin(π) = 1.2e-16 in floating point: ϑ ends within round-off of 0.
    assert cf.columns["theta"][0] == math.pi and cf.columns["theta"][-1] < 1e-15
    assert np.max(np.abs(cf.columns["k"] - av.columns["k"])) < 1e-8
    issues = rm.validity(p, st, cf.slow, tau[-1])
    assert [i.condition for i in issues][:1] == ["through_k_zero"]
