"""Euler–Poinsot motion (3.1), its averages (3.6) and fast frequencies
(docs/theory/rotating-field.md §8)."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st
from scipy import special
from scipy.integrate import solve_ivp
from strategies import inertias, vectors

from tumble.dynamics import rigid_body_rhs
from tumble.errors import ParameterError, TumbleWarning
from tumble.kernels.codes import DEGENERATE_RTOL
from tumble.rotations import matrix_to_euler313, matrix_to_quat, quat_normalize, quat_to_matrix
from tumble.unperturbed import (
    SEPARATRIX_RTOL,
    EulerPoinsot,
    energy_from_modulus,
    fast_frequencies,
    fast_frequencies_of_states,
    mean_square_rate,
    modulus_squared,
    regime,
)

# Reference: DOP853 asked for rtol 1e-13, atol 1e-14 (the required figures). Its measured
# global error over ten periods is ≲ 1e-12 |z| away from the separatrix.
TIGHT = {"method": "DOP853", "rtol": 1e-13, "atol": 1e-14}
# Closed form vs that reference: 100× the reference's own error for ω, 1000× for A (the
# attitude also carries the quaternion normalisation drift of the reference).
OMEGA_RTOL = 1e-10
ATTITUDE_ATOL = 1e-9
# Pure round-off of the closed form: a few dozen operations on O(1) numbers.
ROUNDOFF = 1e-12


def random_attitude(seed):
    return quat_to_matrix(np.random.default_rng(seed).normal(size=4))


def polhode_point(I_sorted, L, T, frac):
    """A state with given L, T whose middle component is ``frac`` of its largest value.

    Solves I1²z1² + I3²z3² = L² − I2²z2², I1 z1² + I3 z3² = 2T − I2 z2² for z1², z3²:
    independent of the formulas under test.
    """
    I1, I2, I3 = I_sorted
    d1, d3 = L * L - 2 * T * I1, 2 * T * I3 - L * L
    z2max2 = min(d3 / (I2 * (I3 - I2)), d1 / (I2 * (I2 - I1)))  # where z1 or z3 vanishes
    z2 = frac * math.sqrt(z2max2)
    rhs = [L * L - I2**2 * z2**2, 2 * T - I2 * z2**2]
    s1, s3 = np.linalg.solve([[I1**2, I3**2], [I1, I3]], rhs)
    return np.array([math.sqrt(max(s1, 0.0)), z2, math.sqrt(max(s3, 0.0))])


def user_state(I_user, k2, reg, frac=0.4, signs=(1, 1, 1)):
    """(z in the user's axes) with modulus k2 in regime ``reg``, L = 1."""
    I_user = np.asarray(I_user, dtype=float)
    order = np.argsort(I_user, kind="stable")
    Is = I_user[order]
    T = energy_from_modulus(*Is, 1.0, k2, reg)
    zs = polhode_point(Is, 1.0, T, frac) * np.asarray(signs)
    z = np.empty(3)
    z[order] = zs
    return z


def integrate(moments, z0, A0, t_end):
    y0 = np.concatenate([z0, matrix_to_quat(A0)])
    moments = np.asarray(moments, dtype=float)
    sol = solve_ivp(lambda t, y: rigid_body_rhs(t, y, moments, None), (0.0, t_end), y0, **TIGHT)
    assert sol.success
    return sol.t, sol.y[:3].T, sol.y[3:].T


def separatrix_drift(moments, W):
    """Max relative drift of L² − 2T·I2 along integrated angular velocities W (user axes)."""
    moments = np.asarray(moments, dtype=float)
    I2 = np.sort(moments)[1]
    d2 = np.sum(moments * (moments - I2) * W * W, axis=-1)
    return float(np.max(np.abs(d2 - d2[0])) / abs(d2[0]))


# (user inertia, k2, regime, phase fraction, sign pattern of the sorted state)
CASES = [
    ((1.0, 2.0, 2.5), 0.5, "x3", 0.4, (1, 1, 1)),
    ((1.0, 2.0, 2.5), 0.5, "x1", -0.7, (1, 1, -1)),
    ((2.5, 1.0, 2.0), 0.8, "x3", 0.2, (-1, 1, 1)),  # cyclic relabelling
    ((2.5, 1.0, 2.0), 0.3, "x1", 0.9, (-1, -1, 1)),
    ((1.0, 2.5, 2.0), 0.2, "x3", -0.5, (1, 1, -1)),  # transposition: one axis reversed
    ((3.0, 1.0, 2.0), 0.6, "x1", 0.1, (1, 1, 1)),  # thin plate, issue's [3, 1, 2]
    ((1.0, 1.7, 2.3), 1e-6, "x3", 0.3, (1, -1, 1)),
    ((1.0, 1.7, 2.3), 1e-6, "x1", 0.3, (1, 1, 1)),
    ((1.0, 2.0, 2.5), 1 - 1e-6, "x3", 0.5, (1, 1, 1)),
    ((2.0, 2.5, 1.0), 1 - 1e-6, "x1", -0.2, (1, -1, 1)),
]


@pytest.mark.parametrize("moments, k2, reg, frac, signs", CASES)
def test_omega_and_attitude_match_integration_over_ten_periods(moments, k2, reg, frac, signs):
    """(3.1) solves Euler's equations in both regimes (§15); A(τ) solves Ȧ = A ẑ."""
    z0 = user_state(moments, k2, reg, frac, signs)
    A0 = random_attitude(len(CASES) + int(1e6 * k2))
    ep = EulerPoinsot.from_state(moments, z0, A0)
    assert ep.regime == reg
    assert ep.k2 == pytest.approx(k2, rel=1e-9)
    t, W, Q = integrate(moments, z0, A0, 10.0 * ep.period)
    # Near the separatrix the quarter period K ≈ ½ ln(16/k'²) shifts by ½δ when the
    # reference's L² − 2T·I2 drifts by the fraction δ (round-off random walk, measured):
    # over 40 quarter periods ≤ 20δ in u, i.e. ≤ 20δ|z| in ω. Margin 2 on top.
    slack = 40.0 * separatrix_drift(moments, W)
    scale = np.linalg.norm(z0)
    err_w = np.max(np.abs(ep.omega(t) - W)) / scale
    err_A = np.max(np.abs(ep.attitude(t) - quat_to_matrix(Q)))
    err_q = np.max(np.abs(ep.quaternion(t) - quat_normalize(Q)))  # continuous, same sign
    assert err_w <= OMEGA_RTOL + slack
    assert err_A <= ATTITUDE_ATOL + slack
    assert err_q <= ATTITUDE_ATOL + slack


FD8 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])


def euler_residual(ep, taus, h=0.05):
    """max |I ż + z × I z| / (|I z| |z|) along the closed form, ż by 8th-order differences."""
    moments = np.asarray(ep.inertia)
    W = ep.omega(taus[:, None] + h * np.arange(-4, 5)[None, :])
    dW = np.einsum("k,nkj->nj", FD8, W) / h
    w = W[:, 4]
    R = moments * dW + np.cross(w, moments * w)
    return float(np.max(np.abs(R)) / (ep.L * np.max(np.linalg.norm(w, axis=-1))))


@pytest.mark.parametrize(
    "moments, k2, reg",
    [
        ((1.0, 2.0, 2.5), 0.5, "x3"),
        ((2.5, 1.0, 2.0), 1 - 1e-6, "x3"),
        ((1.0, 2.0, 2.5), 1 - 1e-10, "x1"),  # beyond what the reference can follow
    ],
)
def test_closed_form_solves_eulers_equations_near_the_separatrix(moments, k2, reg):
    """§15 "(3.1) solves Euler's equations", checked without an integrator: near the
    separatrix the reference's round-off drift of L² − 2T·I2 limits the comparison above,
    the residual has no such limit. Errors of a few ulps in ω, times Σ|c_k|/h ≈ 50 of the
    difference formula, give ~1e-13; its truncation error h⁸ ω⁽⁹⁾ is smaller. 1e-11 leaves a
    margin of 10 over the worst measured (1.5e-12)."""
    z0 = user_state(moments, k2, reg, frac=0.3)
    ep = EulerPoinsot.from_state(moments, z0)
    assert euler_residual(ep, np.linspace(0.0, 3.0 * ep.period, 1501)) < 1e-11


@pytest.mark.parametrize(
    "moments, z0",
    [
        ((1.0, 1.0, 1.5), (0.3, 0.2, 1.0)),  # symmetric about x3: regular precession
        ((1.5, 1.0, 1.5), (0.3, 0.2, -1.0)),  # I2 = I3 (sorted): symmetric about x1
        ((2.0, 2.0, 2.0), (0.3, -0.2, 1.0)),  # sphere
        ((1.0, 1.5, 1.5), (0.0, 0.2, -0.7)),  # equatorial spin of a symmetric body
        ((1.0, 2.0, 2.5), (0.0, 0.0, -1.2)),  # k2 = 0: uniform rotation about x3
        ((1.0, 2.0, 2.5), (0.9, 0.0, 0.0)),  # k2 = 0 in regime x1
    ],
)
def test_degenerate_motions_match_integration(moments, z0):
    z0 = np.array(z0)
    A0 = random_attitude(7)
    ep = EulerPoinsot.from_state(moments, z0, A0)
    t_end = 10.0 * ep.period if math.isfinite(ep.period) else 60.0
    t, W, Q = integrate(moments, z0, A0, t_end)
    assert np.max(np.abs(ep.omega(t) - W)) <= OMEGA_RTOL * np.linalg.norm(z0)
    assert np.max(np.abs(ep.attitude(t) - quat_to_matrix(Q))) <= ATTITUDE_ATOL


def test_regimes_and_rest():
    assert EulerPoinsot.from_state((1.0, 1.0, 1.5), (0.3, 0.2, 1.0)).regime == "symmetric"
    assert EulerPoinsot.from_state((2.0, 2.0, 2.0), (0.3, 0.2, 1.0)).regime == "sphere"
    rest = EulerPoinsot.from_state((1.0, 2.0, 2.5), (0.0, 0.0, 0.0), random_attitude(3))
    assert rest.regime == "rest" and rest.L == 0.0 and rest.period == math.inf
    tau = np.linspace(0.0, 5.0, 4)
    assert np.all(rest.omega(tau) == 0.0)
    assert np.allclose(rest.attitude(tau), random_attitude(3), atol=ROUNDOFF)


@pytest.mark.parametrize("reg", ["x3", "x1"])
@pytest.mark.parametrize("k2", [0.3, 0.95])
def test_period_is_4K_over_nu(reg, k2):
    """§8 and §15: the period of z is 4K/ν, measured as the time between two zero crossings
    of the cn-component (z1 in x3, z3 in x1) in the same direction, in the integration."""
    moments = (1.0, 1.6, 2.2)
    z0 = user_state(moments, k2, reg, frac=0.5)
    ep = EulerPoinsot.from_state(moments, z0)
    i = 0 if reg == "x3" else 2

    def crossing(t, y):
        return y[i]

    crossing.direction = 1.0
    y0 = np.concatenate([z0, [1.0, 0.0, 0.0, 0.0]])
    sol = solve_ivp(
        lambda t, y: rigid_body_rhs(t, y, np.array(moments), None),
        (0.0, 2.6 * ep.period),
        y0,
        events=crossing,
        **TIGHT,
    )
    t_ev = sol.t_events[0]
    assert len(t_ev) == 2  # exactly one crossing per period: 4K/ν is the least period
    # Event times come from root-finding on DOP853's 7th-order dense output, good to ~1e-12.
    assert t_ev[1] - t_ev[0] == pytest.approx(ep.period, rel=1e-10)
    assert ep.period == pytest.approx(4.0 * special.ellipk(ep.k2) / ep.nu, rel=1e-14)


def trapezoid_mean(values):
    """Mean over one period of samples at N equispaced points (periodic trapezoid rule).

    The integrands are analytic in a strip around the real u-axis (the nearest poles of
    sn, cn, dn are at distance K'): the rule converges like exp(−π N K'/(2K)), which for
    N = 2048 and k2 ≤ 1 − 1e-6 (K'/K ≥ 0.19) is below 1e-200.
    """
    return np.mean(values, axis=0)


def period_samples(ep, N=2048):
    return ep.omega(np.arange(N) * ep.period / N)


MEAN_CASES = [
    ((1.0, 2.0, 2.5), 0.0, "x3"),
    ((1.0, 2.0, 2.5), 0.5, "x3"),
    ((1.0, 2.0, 2.5), 0.99, "x1"),
    ((2.5, 1.0, 2.0), 0.3, "x1"),
    ((1.0, 1.7, 2.3), 1 - 1e-6, "x3"),
    ((1.0, 1.7, 2.3), 1 - 1e-6, "x1"),
    ((0.6, 1.0, 1.5), 0.7, "x3"),
]


@pytest.mark.parametrize("moments, k2, reg", MEAN_CASES)
def test_mean_square_rate_is_the_period_average(moments, k2, reg):
    """(3.6) (and its 1 ↔ 3 swap) equals the period average of |z|² on the closed form."""
    z0 = user_state(moments, k2, reg, frac=0.3)
    ep = EulerPoinsot.from_state(moments, z0)
    Z = period_samples(ep) if k2 > 0 else np.array([z0])
    numeric = trapezoid_mean(np.sum(Z * Z, axis=-1))
    Is = sorted(moments)
    # Both sides are sums of O(1) terms with round-off ~1e-15; 1e-10 is the required figure.
    assert mean_square_rate(*Is, ep.L, ep.T) == pytest.approx(numeric, rel=1e-10)


@pytest.mark.parametrize("moments, k2, reg", MEAN_CASES)
def test_mean_precession_rate(moments, k2, reg):
    """ν2 = ⟨ψ̇⟩ in closed form (Π/K) equals the period average of ψ̇ = L(2T − I_c z_c²)/(L² −
    I_c² z_c²) (§8) and the precession (ψ(τ + P) − ψ(τ))/P of the closed-form angles."""
    z0 = user_state(moments, k2, reg, frac=0.3)
    ep = EulerPoinsot.from_state(moments, z0)
    Is = np.sort(moments)
    nu1, nu2 = fast_frequencies(*Is, ep.L, ep.T)
    # The object takes d2 = L² − 2T·I2 from the components, the function from (L, T): they
    # differ by a few ulps of L², i.e. by 1e-15 L²/|d2| relative in k'², which moves
    # K ≈ ½ ln(16/k'²) by half that (absolute).
    d2 = float(np.sum(np.array(moments) * (np.array(moments) - Is[1]) * z0 * z0))
    assert (ep.nu1, ep.nu2) == pytest.approx((nu1, nu2), rel=1e-13 + 1e-15 * ep.L**2 / abs(d2))
    if k2 == 0.0:
        return
    assert ep.nu1 == pytest.approx(2 * math.pi / ep.period, rel=1e-14)
    order = np.argsort(moments, kind="stable")
    Zs = period_samples(ep)[:, order]
    c = 2 if reg == "x3" else 0
    Ic, zc = Is[c], Zs[:, c]
    psi_dot = ep.L * (2 * ep.T - Ic * zc**2) / (ep.L**2 - Ic**2 * zc**2)
    # Same spectral accuracy as above; the required 1e-10.
    assert ep.nu2 == pytest.approx(trapezoid_mean(psi_dot), rel=1e-10)
    tau = np.array([0.0, 0.37, 5.1])
    psi_a = ep.euler_angles(tau)[0]
    psi_b = ep.euler_angles(tau + ep.period)[0]
    # Π(n; am u + π) − Π(n; am u) = 2Π(n|m): exact up to the round-off of ψ ~ 10 rad.
    assert np.allclose((psi_b - psi_a) / ep.period, ep.nu2, rtol=1e-12)


@pytest.mark.parametrize("reg", ["x3", "x1"])
def test_mean_precession_rate_from_integrated_attitude(reg):
    """ν2 against the precession angle of the *integrated* attitude about L over ten periods
    (ψ unwrapped from 3-1-3 angles of L-frameᵀ · A · Pᵀ)."""
    moments = (1.0, 1.6, 2.2)
    z0 = user_state(moments, 0.6, reg, frac=0.5)
    A0 = random_attitude(11)
    ep = EulerPoinsot.from_state(moments, z0, A0)
    t, _, Q = integrate(moments, z0, A0, 10.0 * ep.period)
    C = ep.lframe.T @ quat_to_matrix(Q) @ ep.polar_frame.T
    psi = np.unwrap(matrix_to_euler313(C)[0])
    # θ stays away from 0 and π (k2 = 0.6), so ψ is well conditioned: the reference's
    # ~1e-12 attitude error over a span of ~10 periods gives ≲ 1e-12 relative.
    assert (psi[-1] - psi[0]) / t[-1] == pytest.approx(ep.nu2, rel=1e-10)


def test_frequencies_at_k2_zero_match_the_linear_roots():
    """At k = 0 (rotation about x3) ν1 = z3 ω0 and ν2 = z3 (1 + ω0), ω0 of (2.6); §12's
    thin plate (ω0 = 1) then has ν2 = 2 z3."""
    for I1, I2, I3 in [(1.0, 2.0, 2.5), (1.0, 2.0, 3.0)]:
        z3 = 0.8
        L, T = I3 * z3, 0.5 * I3 * z3**2
        omega0 = math.sqrt((I3 - I2) * (I3 - I1) / (I1 * I2))
        nu1, nu2 = fast_frequencies(I1, I2, I3, L, T)
        assert nu1 == pytest.approx(z3 * omega0, rel=1e-14)
        assert nu2 == pytest.approx(z3 * (1.0 + omega0), rel=1e-14)
    # Symmetric bodies: regular precession, ν1 = |z_c (I_a − I_c)/I_a|, ν2 = L/I_a.
    z = np.array([0.3, 0.4, 0.9])
    L, T = np.linalg.norm([1.0, 1.0, 1.5] * z), 0.5 * np.dot([1.0, 1.0, 1.5], z * z)
    assert fast_frequencies(1.0, 1.0, 1.5, L, T) == pytest.approx((0.9 * 0.5, L), rel=1e-14)


@pytest.mark.parametrize("moments", [(1.0, 1.0, 1.6), (0.8, 1.5, 1.5)])
def test_mean_square_rate_symmetric_body(moments):
    """§8 "Degenerate inertia": z⊥² = (2T I_c − L²)/(I_a (I_c − I_a)),
    z_c² = (L² − 2T I_a)/(I_c (I_c − I_a)), ⟨z²⟩ = z⊥² + z_c², and the triaxial formula
    tends to it as the two moments merge."""
    I1, I2, I3 = moments
    z = np.array([0.3, -0.4, 0.9])
    Iv = np.array(moments)
    L, T = float(np.linalg.norm(Iv * z)), 0.5 * float(np.dot(Iv, z * z))
    Ia, Ic = (I1, I3) if I1 == I2 else (I3, I1)
    zperp2 = (2 * T * Ic - L * L) / (Ia * (Ic - Ia))
    zc2 = (L * L - 2 * T * Ia) / (Ic * (Ic - Ia))
    value = mean_square_rate(I1, I2, I3, L, T)
    # The form of §8 subtracts O(1) numbers: a few ulps of L²/I².
    assert value == pytest.approx(zperp2 + zc2, rel=1e-13)
    assert value == pytest.approx(float(np.dot(z, z)), rel=1e-13)
    assert modulus_squared(I1, I2, I3, L, T) == (0.0, "symmetric")
    # Split the equal pair by 1e-9: ⟨z²⟩ moves by O(1e-9) relative, not more.
    h = 1e-9
    J = (I1 - h, I2, I3) if I1 == I2 else (I1, I2, I3 + h)
    L2, T2 = float(np.linalg.norm(np.array(J) * z)), 0.5 * float(np.dot(J, z * z))
    assert mean_square_rate(*J, L2, T2) == pytest.approx(value, rel=10 * h)


def test_mean_square_rate_sphere_and_rest():
    assert mean_square_rate(2.0, 2.0, 2.0, 3.0, 2.25) == pytest.approx(2.25, rel=1e-15)
    assert mean_square_rate(1.0, 2.0, 2.5, 0.0, 0.0) == 0.0
    assert fast_frequencies(2.0, 2.0, 2.0, 3.0, 2.25) == (0.0, 1.5)


def test_continuity_across_the_separatrix():
    """⟨z²⟩ and ν2 are continuous at L² = 2T·I2, but only logarithmically (E/K and
    Π/K − 1/(1 − n) vanish like 1/ln(4/k')): k'² = 1e-10 is still ~1 % away. So the test
    checks the asymptote, from both sides: ⟨z²⟩ − ⟨z²⟩_sep = c·E/K + O(k'² ln), with
    c = 2T(I2 − I1)(I3 − I2)/(I1 I2 I3) from (3.6) at k → 1."""
    I1, I2, I3, L = 1.0, 2.0, 2.5, 1.0
    T_sep = energy_from_modulus(I1, I2, I3, L, 1.0, "x3")
    assert T_sep == 0.5 * L * L / I2
    sep = mean_square_rate(I1, I2, I3, L, T_sep)
    assert sep == pytest.approx(2 * T_sep / I2, rel=1e-15)  # E/K = 0, no overflow
    assert fast_frequencies(I1, I2, I3, L, T_sep) == pytest.approx((0.0, L / I2), rel=1e-15)
    for reg in ("x3", "x1"):
        previous = math.inf
        for k2 in (1 - 1e-3, 1 - 1e-6, 1 - 1e-10, 1 - 1e-14):
            kc2 = 1.0 - k2  # exact (Sterbenz): the k'² actually asked for
            T = energy_from_modulus(I1, I2, I3, L, k2, reg)
            e_over_k = special.ellipe(k2) / special.ellipkm1(kc2)
            c = 2 * T * (I2 - I1) * (I3 - I2) / (I1 * I2 * I3)
            jump = mean_square_rate(I1, I2, I3, L, T) - sep
            # Remainder O(k'² ln(1/k'²)) ≤ 30 k'² here. Conditioning: T carries a few ulps,
            # i.e. 1e-15/k'² relative in k'², which moves E/K ≈ 1/K by that over 2K.
            tol = 30 * kc2 + c * e_over_k * 1e-15 / kc2 / (2 * special.ellipkm1(kc2))
            assert jump == pytest.approx(c * e_over_k, abs=tol)
            assert 0.0 < jump < previous  # monotone approach from above
            previous = jump
            nu1, nu2 = fast_frequencies(I1, I2, I3, L, T)
            assert 0.0 < nu1 and abs(nu2 - L / I2) < 1.0 / special.ellipkm1(kc2)


def _states_around_the_separatrix(I1, I2, I3, rng):
    """(L, T) pairs of every kind a run passes: both regimes, the pure rotations, the band
    around the separatrix down to |1 − k²| of 1e-14 and the separatrix itself, rest."""
    L = rng.uniform(0.1, 3.0, 40)
    r = rng.uniform(1.0 / I3, 1.0 / I1, 40)
    T = [0.5 * r * L * L]
    L_band, T_band = [0.0], [0.0]  # rest
    if min(I2 - I1, I3 - I2) > DEGENERATE_RTOL * I3:  # triaxial: k² sets T
        for reg in ("x3", "x1"):
            for k2 in (0.0, 0.5, 1 - 1e-3, 1 - 1e-9, 1 - 1e-14, 1.0):
                L_band.append(1.3)
                T_band.append(energy_from_modulus(I1, I2, I3, 1.3, k2, reg))
    return np.concatenate([L, L_band]), np.concatenate([*T, T_band])


@pytest.mark.parametrize(
    "moments",
    [(1.0, 1.6, 2.2), (1.0, 2.0, 2.5), (0.5, 0.9, 1.1), (1.0, 1.0, 1.6), (0.8, 1.5, 1.5),
     (2.0, 2.0, 2.0), (1.0, 1.0 + 1e-13, 1.6)],
)  # fmt: skip
def test_frequencies_of_many_states_are_those_of_each(moments):
    """The array form repeats the scalar one's operations in the same order: the same
    numbers to the last bit, in every regime, on the separatrix, for symmetric bodies (also
    a pair equal within the degeneracy tolerance), the sphere and rest."""
    I1, I2, I3 = moments
    L, T = _states_around_the_separatrix(I1, I2, I3, np.random.default_rng(1979))
    nu1, nu2 = fast_frequencies_of_states(I1, I2, I3, L, T)
    each = np.array([fast_frequencies(I1, I2, I3, a, b) for a, b in zip(L, T, strict=True)])
    np.testing.assert_array_equal(nu1, each[:, 0])
    np.testing.assert_array_equal(nu2, each[:, 1])
    one = fast_frequencies_of_states(I1, I2, I3, L[3], T[3])  # a scalar pair: 0-d arrays
    assert (float(one[0]), float(one[1])) == tuple(each[3])


@pytest.mark.parametrize(
    ("L", "T", "message"),
    [
        ([1.0, -1.0], [0.3, 0.3], "both must be ≥ 0"),
        ([1.0, 0.0], [0.3, 0.1], "must be 0 when L = 0"),
        ([1.0, 1.0], [0.3, 5.0], "outside the allowed range [1/I3, 1/I1]"),
        ([1.0, math.nan], [0.3, 0.3], "L"),
    ],
)
def test_frequencies_of_many_states_refuse_as_the_scalar_form(L, T, message):
    with pytest.raises(ParameterError) as many:
        fast_frequencies_of_states(1.0, 1.6, 2.2, L, T)
    with pytest.raises(ParameterError) as one:
        fast_frequencies(1.0, 1.6, 2.2, L[1], T[1])
    assert str(many.value) == str(one.value) and message in str(one.value)


@given(inertias(), vectors())
def test_modulus_in_unit_interval_and_energy_inverts_it(moments, z):
    """§16: 0 ≤ k2 ≤ 1 in the current regime; the T substitution of §8 inverts it."""
    assume(np.max(np.abs(z)) > 0.0)
    z = z / np.max(np.abs(z))  # scale-free; keeps T, L² away from the subnormal range
    I1, I2, I3 = sorted(moments)
    Iv = np.array([I1, I2, I3])
    L, T = float(np.linalg.norm(Iv * z)), 0.5 * float(np.dot(Iv, z * z))
    k2, reg = modulus_squared(I1, I2, I3, L, T)
    assert 0.0 <= k2 <= 1.0
    assert reg == regime(Iv, L, T)
    assume(reg in ("x3", "x1"))
    T_back = energy_from_modulus(I1, I2, I3, L, k2, reg)
    # k2 carries the round-off of the differences L² − 2T·I_i (~1e-16 L²); mapped back, it
    # moves 2T by ≤ that much, relative to L²/I1 ≥ 2T.
    assert T_back == pytest.approx(T, abs=1e-13 * L * L / I1)


@given(inertias(), vectors(), st.integers(0, 2**32 - 1), st.floats(-30.0, 30.0))
def test_closed_form_keeps_the_invariants(moments, z, seed, tau):
    """ω(0) = z0, A(0) = A0, and along the motion T, |L| and the inertial L are constant."""
    assume(np.linalg.norm(z) > 1e-3)
    A0 = random_attitude(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TumbleWarning)
        ep = EulerPoinsot.from_state(moments, z, A0)
    Iv = np.array(moments)
    taus = np.array([0.0, tau])
    W = ep.omega(taus)
    A = ep.attitude(taus)
    scale = np.linalg.norm(z)
    if ep.regime != "separatrix":  # on it ω(0) is the nearest separatrix point (Notes)
        assert np.allclose(W[0], z, atol=ROUNDOFF * scale)
    assert np.allclose(A[0], A0, atol=ROUNDOFF)
    L_inertial = np.einsum("...ij,...j->...i", A, Iv * W)
    assert np.allclose(L_inertial, ep.angular_momentum, atol=1e-11 * ep.L)
    assert np.allclose(0.5 * np.sum(Iv * W * W, axis=-1), ep.T, rtol=1e-11)


# I1(I2 − I1) = 4 and I3(I3 − I2) = 9/4 with z1 = 3/8, z3 = 1/2: L² − 2T·I2 = 0 exactly.
SEP_I = (2.0, 4.0, 4.5)
SEP_Z = np.array([0.375, 0.75, 0.5])


@pytest.mark.parametrize("signs", [(1, 1, 1), (-1, 1, 1), (1, -1, -1), (-1, -1, -1)])
def test_separatrix_state_warns_and_solves_eulers_equations(signs):
    """L² = 2T·I2 exactly: regime "separatrix", a TumbleWarning, period inf, and the
    asymptotic motion (3.1) with m = 1 solves Euler's equations."""
    I2 = SEP_I[1]
    z0 = SEP_Z * signs
    A0 = random_attitude(5)
    with pytest.warns(TumbleWarning, match="separatrix L² = 2T·I2"):
        ep = EulerPoinsot.from_state(SEP_I, z0, A0)
    assert (ep.regime, ep.k2, ep.period, ep.nu1) == ("separatrix", 1.0, math.inf, 0.0)
    assert ep.nu2 == pytest.approx(ep.L / I2, rel=1e-15)
    # 10/ν: long enough to approach the saddle (z1, z3 shrink by e^-10), short enough that
    # the reference's 1e-14 errors, amplified by at most e^{ντ} = 2e4, stay ≲ 1e-10.
    t, W, Q = integrate(SEP_I, z0, A0, 10.0 / ep.nu)
    assert np.max(np.abs(ep.omega(t) - W)) <= 1e-9 * np.linalg.norm(z0)
    assert np.max(np.abs(ep.attitude(t) - quat_to_matrix(Q))) <= ATTITUDE_ATOL
    # Far out the motion tends to the rotation about x2, without overflow; toward +x2 when
    # I2 ż2 = (I3 − I1) z3 z1 > 0 (z1, z3 keep their signs along a separatrix branch).
    assert euler_residual(ep, np.linspace(-20.0, 40.0, 601) / ep.nu) < 1e-11  # as above
    far = ep.omega(np.array([1e3 / ep.nu]))[0]
    assert far == pytest.approx([0.0, ep.L / I2 * np.sign(z0[0] * z0[2]), 0.0], abs=1e-12)
    # The precession rate tends to L/I2 as well: ψ̇ = L(2T − I3 z3²)/(L² − I3² z3²), z3 → 0.
    psi = ep.euler_angles(np.array([1e3, 1e3 + 1.0]) / ep.nu)[0]
    assert (psi[1] - psi[0]) * ep.nu == pytest.approx(ep.L / I2, rel=1e-12)


def test_separatrix_band_uses_the_state_own_motion():
    """Inside the band |L² − 2T·I2| ≤ SEPARATRIX_RTOL·L² but not on the separatrix, the
    label and attributes are the separatrix's, while ω(τ) is the periodic motion of the
    state itself (k'² ~ 1e-15 here), which the reference follows until the saddle."""
    z0 = SEP_Z + np.array([0.0, 0.0, 1e-15])
    with pytest.warns(TumbleWarning):
        ep = EulerPoinsot.from_state(SEP_I, z0)
    Iv = np.array(SEP_I)
    assert 0.0 < abs(np.sum(Iv * (Iv - Iv[1]) * z0 * z0)) <= SEPARATRIX_RTOL * ep.L**2
    assert (ep.regime, ep.k2, ep.period) == ("separatrix", 1.0, math.inf)
    assert np.allclose(ep.omega(0.0), z0, rtol=0.0, atol=ROUNDOFF)
    t, W, _ = integrate(SEP_I, z0, np.eye(3), 10.0 / ep.nu)
    # Same amplification argument as for the exact separatrix.
    assert np.max(np.abs(ep.omega(t) - W)) <= 1e-9 * np.linalg.norm(z0)
    # Beyond the saddle, where the reference cannot follow: the residual of Euler's equations
    # over two returns (K ≈ ½ ln(16/k'²) ≈ 19 here).
    assert euler_residual(ep, np.linspace(0.0, 160.0, 1601) / ep.nu) < 1e-11
    with pytest.warns(TumbleWarning):  # rotation about the middle axis
        still = EulerPoinsot.from_state(SEP_I, (0.0, 0.7, 0.0))
    assert still.regime == "separatrix"
    assert np.all(still.omega(np.array([0.0, 50.0])) == [0.0, 0.7, 0.0])


def test_shapes_and_scalar_tau():
    ep = EulerPoinsot.from_state((1.0, 2.0, 2.5), (0.3, 0.2, 1.0))
    assert ep.omega(1.0).shape == (3,)
    assert ep.omega(np.zeros((4, 2))).shape == (4, 2, 3)
    assert ep.attitude([0.0, 1.0]).shape == (2, 3, 3)
    assert ep.quaternion([0.0, 1.0]).shape == (2, 4)
    # The quaternion is continuous: no sign flips between close samples over many turns.
    q = ep.quaternion(np.linspace(0.0, 20 * ep.period, 20001))
    assert np.max(np.linalg.norm(np.diff(q, axis=0), axis=-1)) < 0.05


@pytest.mark.parametrize(
    "args, match",
    [
        (((1.0, 1.0, 2.5), (0.1, 0.2, 0.3)), "triangle inequality"),
        (((1.0, 2.0, 2.5), (0.1, math.nan, 0.3)), r"z0\[1\]"),
        (((1.0, 2.0, 2.5), (0.1, 0.3)), "3 components"),
        (((1.0, 2.0, 2.5), (0.1, 0.2, 0.3), np.diag([1.0, 1.0, -1.0])), "proper rotation"),
        (((1.0, 2.0, 2.5), (0.1, 0.2, 0.3), 2 * np.eye(3)), "proper rotation"),
    ],
)
def test_from_state_validates(args, match):
    with pytest.raises(ParameterError, match=match):
        EulerPoinsot.from_state(*args)


def test_module_functions_validate():
    with pytest.raises(ParameterError, match="sorted"):
        mean_square_rate(2.0, 1.0, 2.5, 1.0, 0.3)
    with pytest.raises(ParameterError, match="outside the allowed range"):
        modulus_squared(1.0, 2.0, 2.5, 1.0, 0.7)  # 2T·I1 > L²: no such motion
    with pytest.raises(ParameterError, match="k2"):
        energy_from_modulus(1.0, 2.0, 2.5, 1.0, 1.5, "x3")
    with pytest.raises(ParameterError, match="two equal moments"):
        energy_from_modulus(1.0, 1.0, 2.5, 1.0, 0.5, "x3")
    # Round-off outside [2T·I1, 2T·I3] is clipped: k = 0 exactly.
    L = 2.5
    assert modulus_squared(1.0, 2.0, 2.5, L, 0.5 * L * L / 2.5 * (1 - 1e-12)) == (0.0, "x3")


def test_modulus_squared_of_ratio_is_modulus_squared_for_many_states():
    """The vectorized k²(r) is modulus_squared at L = 1, T = r/2, regime by regime: both
    sides of the separatrix, on it, and symmetric bodies."""
    from tumble.unperturbed.euler_poinsot import modulus_squared, modulus_squared_of_ratio

    rng = np.random.default_rng(11)
    for inertia in [(1.0, 1.6, 2.2), (0.7, 1.3, 1.9), (1.0, 1.0, 1.5), (1.0, 1.5, 1.5)]:
        I1, I2, I3 = inertia
        r = np.concatenate([rng.uniform(1.0 / I3, 1.0 / I1, 200), [1.0 / I1, 1.0 / I3, 1.0 / I2]])
        if I1 < I2 < I3:  # around the separatrix, in its band and beyond
            r = np.concatenate([r, 1.0 / I2 * (1.0 + np.array([1e-13, -1e-13, 1e-9, -1e-9]))])
        one_by_one = np.array([modulus_squared(I1, I2, I3, 1.0, 0.5 * ri)[0] for ri in r])
        # The same formulas on the same numbers: equal to the bit.
        assert np.array_equal(modulus_squared_of_ratio(I1, I2, I3, r), one_by_one), inertia
