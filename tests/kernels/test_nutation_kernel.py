"""The compiled nutation well and averaged equations against the Python orbit and run."""

from __future__ import annotations

import math

import numpy as np
import pytest
from compiled_runs import numba_and_scipy

from tumble.errors import IntegrationError, ParameterError
from tumble.integrate import simulate
from tumble.kernels import KIND_NUTATION_ENGINE
from tumble.kernels.nutation import (
    POLE_CLEARANCE,
    evaluate_separatrix_distance,
    evaluate_well,
    orbit_nodes,
)
from tumble.kernels.rhs import evaluate
from tumble.models import nonlinear_moment as nm
from tumble.models.base import AveragingOptions
from tumble.unperturbed.symmetric_body import NutationOrbit

OK, U1, U2, M1, M2, K2, MC, K, BETA, CASE = range(10)

# The compiled well finds the same roots of f as the orbit (its fast path refines them about
# the start, the kernel about 0: both to a few ulps, measured 5e-15), and the closed forms
# of ⟨u⟩, ⟨u²⟩ and the period amplify that by at most ~10 away from a separatrix (measured
# 3.5e-14 over 3000 random states): 1e-12 is a decade and a half above.
TOL = 1e-12


def _compare(orbit: NutationOrbit, u_hint: float, tol: float = TOL) -> None:
    w = evaluate_well(orbit.R, orbit.G, orbit.a, orbit.b, orbit.E, u_hint)
    assert w[OK] == 1.0
    assert w[U1] == pytest.approx(orbit.u1, abs=tol)
    assert w[U2] == pytest.approx(orbit.u2, abs=tol)
    assert w[M1] == pytest.approx(orbit.mean_u_power(1), abs=tol)
    assert w[M2] == pytest.approx(orbit.mean_u_power(2), abs=tol)
    assert w[K2] == pytest.approx(orbit.k2, abs=tol)
    assert w[CASE] == orbit.root_case
    period = (2.0 if w[CASE] == 1.0 else 4.0) * w[K] / w[BETA]
    assert period == pytest.approx(orbit.period, rel=tol)


def test_well_and_averages_equal_the_orbit_at_random_states():
    rng = np.random.default_rng(7)
    compared = 0
    for _ in range(1500):
        # a and b of order one, small, or zero: both root cases, the cubic (b = 0), the free
        # body (a = b = 0) and outer roots far away, where ⟨u²⟩ takes the trapezoid rule.
        a = float(rng.normal() * rng.choice([1.0, 1e-3, 0.0]))
        b = float(rng.normal() * rng.choice([1.0, 1e-3, 0.0]))
        mu, R, G = rng.uniform(0.2, 2.0), rng.normal(), rng.normal()
        theta, theta_dot = rng.uniform(0.05, math.pi - 0.05), rng.normal()
        try:
            orbit = NutationOrbit.from_state(mu, a, b, R, G, theta, theta_dot)
        except ParameterError:
            continue  # a separatrix or a body at rest: no orbit to compare with
        if orbit.kind == "steady":
            continue
        _compare(orbit, math.cos(theta))
        compared += 1
    assert compared > 1000


@pytest.mark.parametrize("gap", [1e-2, 1e-4, 1e-6])
@pytest.mark.parametrize("side", ["inside", "above"])
def test_well_near_a_separatrix(gap, side):
    # The double well b < 0 with its barrier at energy Eb: inside one well (case 1, the outer
    # root next to the motion) or above the barrier (case 2), 1 − k² down to ~1e-6.
    mu, a, b, R, G = 0.8, -0.2, -1.0, 0.1, 0.15
    Eb = float(np.min(nm.barrier_energies(R, G, a, b)))
    E = Eb - gap * abs(Eb) if side == "inside" else Eb + gap * abs(Eb)
    orbit = NutationOrbit.from_energy(mu, a, b, R, G, E, u_hint=0.9)
    # Two roots ∝ 1 − k² apart, each good to a few ulps, fix 1 − k² only to ~1e-15/(1 − k²)
    # relative; the closed forms amplify that by up to ~10 (as above).
    _compare(orbit, 0.9, tol=max(TOL, 1e-14 / orbit.mc))


def test_no_motion_below_the_minimum_of_the_potential():
    w = evaluate_well(0.4, 0.6, -1.0, -0.3, -5.0, 0.5)
    assert w[OK] == 0.0 and np.all(np.isnan(w[1:]))


def test_separatrix_distance_is_the_lowest_barrier_minus_the_energy():
    rng = np.random.default_rng(3)
    with_barrier = 0
    for _ in range(400):
        a, b = rng.normal() * rng.choice([1.0, 0.0]), rng.normal()
        R, G, H = 0.3 * rng.normal(), 0.3 * rng.normal(), rng.normal()
        barriers = nm.barrier_energies(R, G, a, b)
        expected = float(np.min(barriers)) - H if barriers.size else 1.0
        got = evaluate_separatrix_distance(np.array([H, R, G, a, b]))
        # The same barriers: the roots of one quintic (numpy's companion matrix against
        # bracketed Newton) agree to ~1e-12, and W is flat at them (a maximum).
        assert got == pytest.approx(expected, abs=1e-10)
        with_barrier += barriers.size > 0
    assert with_barrier > 100


def _capsule(pressure: nm.Pressure) -> tuple[nm.Params, nm.State]:
    p = nm.Params(mu=0.8, a=-1.0, b=-0.3, eps=1e-3, d=0.5, nu=0.2, pressure=pressure)
    return p, nm.State(1.0, 0.3, 0.2, -0.1, 0.4, 0.6)


@pytest.mark.parametrize(
    "pressure",
    [nm.Pressure("exp"), nm.Pressure("table", tau=(0.0, 0.4, 1.0, 2.0), Q=(1.0, 1.5, 1.2, 2.0))],
    ids=["exp", "table"],
)
def test_compiled_averaged_run_equals_the_python_one(pressure):
    p, s0 = _capsule(pressure)
    t = np.linspace(0.0, 1500.0, 31)
    runs = numba_and_scipy(nm.MODEL, p, s0, t, "averaged", rtol=1e-10, atol=1e-12)
    for key in ("theta_max", "theta_min", "k2", "period", "E", "R", "G", "a", "b"):
        # The same DOP853 on the same equations (the averages equal to 1e-12): measured 5e-14
        # apart; 1e-9 is the runs' own tolerance.
        assert np.max(np.abs(runs["numba"].columns[key] - runs["scipy"].columns[key])) < 1e-9, key


def test_compiled_run_stops_at_the_separatrix_where_the_python_one_does():
    # Negative pitch damping pumps a planar swing (R = G = 0, f(±1) = 0) up to the barrier
    # of the double well at θ = π/2.
    p = nm.Params(mu=1.0, a=0.0, b=-1.0, eps=0.05, d=-1.0)
    s0 = nm.State(0.6, 0.0, 0.0, 0.0, 0.0, 0.0)
    times = []
    for integrator in ("numba", "scipy"):
        with pytest.raises(IntegrationError, match="reaches a separatrix at t = ") as info:
            simulate(nm.MODEL, p, s0, np.linspace(0.0, 400.0, 11), "averaged",
                     integrator=integrator)  # fmt: skip
        times.append(float(str(info.value).split("at t = ")[1].split()[0]))
    # Both locate the same zero (of different functions with the same sign) to the event
    # tolerance; the message prints six digits.
    assert times[0] == pytest.approx(times[1], rel=1e-5)


def _engine_kernel(p: nm.Params, st: nm.State):
    numeric = nm.MODEL.averaged.check(AveragingOptions(averaging="numeric"))
    form = nm.MODEL.averaged.form(p, st, numeric)
    kernel = form.kernel(p)
    assert kernel is not None and kernel.kind == KIND_NUTATION_ENGINE
    return kernel, float(kernel.params[9 + 2 * int(kernel.params[8])])


@pytest.mark.parametrize(
    "pressure", [nm.Pressure("exp"), nm.Pressure("constant")], ids=["exp", "constant"]
)
def test_compiled_engine_equals_the_python_engine(pressure):
    # The general engine's nutation setting on the capsule's damping (a moment of the body
    # rate): compiled (time average as a rule in the angle of u, 8 spin nodes) against Python
    # (rule uniform in time): both converged to 1e-12 of the integrand's size.
    p, s0 = _capsule(pressure)
    kernel, u_hint = _engine_kernel(p, s0)
    engine = nm.engine_perturbation(p)
    orbit = nm.orbit_of(p, s0)
    rng = np.random.default_rng(2)
    compared = 0
    for _ in range(60):
        y = np.array([orbit.E, s0.R, s0.G, p.a, p.b]) * (1.0 + 0.05 * rng.normal(size=5))
        try:
            ref = nm.averaged_rhs(0.3, y, p, u_hint=u_hint, perturbation=engine)
        except IntegrationError:
            continue  # no motion at that energy in this well
        got = evaluate(kernel.kind, 0.3, y, kernel.params)
        assert np.max(np.abs(got - ref)) <= 1e-12 * float(np.max(np.abs(ref)))
        compared += 1
    assert compared > 30


def test_compiled_engine_near_a_separatrix():
    # 1 − k² ~ 1e-4: the rule in the angle of u needs ~1/√(1 − k²) more nodes than away from
    # it, and still converges to the same averages.
    p = nm.Params(mu=0.8, a=-0.2, b=-1.0, eps=1e-3, d=0.5, nu=0.2)
    R, G = 0.1, 0.15
    Eb = float(np.min(nm.barrier_energies(R, G, p.a, p.b)))
    E = Eb - 1e-7 * abs(Eb)
    orbit = NutationOrbit.from_energy(p.mu, p.a, p.b, R, G, E, u_hint=0.9)
    assert orbit.mc < 1e-3
    st = nm.State(orbit.theta_min, 0.0, 0.0, 0.0, R, G)
    kernel, _ = _engine_kernel(p, st)
    params = kernel.params.copy()
    params[9 + 2 * int(params[8])] = 0.9  # the well of ``orbit``
    y = np.array([E, R, G, p.a, p.b])
    ref = nm.averaged_rhs(0.0, y, p, u_hint=0.9, perturbation=nm.engine_perturbation(p))
    got = evaluate(kernel.kind, 0.0, y, params)
    # Both stop at 1e-12 of the integrand's mean magnitude, which near a separatrix exceeds
    # the averages themselves (measured 2e-11 of them apart).
    assert np.max(np.abs(got - ref)) <= 1e-10 * float(np.max(np.abs(ref)))


def test_compiled_engine_run_equals_the_python_one():
    p, s0 = _capsule(nm.Pressure("exp"))
    numeric = AveragingOptions(averaging="numeric")
    t = np.linspace(0.0, 1500.0, 16)
    runs = numba_and_scipy(
        nm.MODEL, p, s0, t, "averaged", rtol=1e-10, atol=1e-12, averaging=numeric
    )
    for key, ref in runs["scipy"].columns.items():
        # The same DOP853 on averages equal to 1e-12: measured 1e-13 apart.
        assert np.max(np.abs(runs["numba"].columns[key] - ref)) < 1e-9, key


def test_orbit_nodes_equal_the_orbit_at_random_states():
    # θ and θ' at the nodes uniform in time from θmax, and ν, of the compiled chart against
    # the Python orbit from the same energy: the roots agree to a few ulps (above) and the
    # chart is the same formula, so the nodes agree to round-off, amplified near a turning
    # point by 1/sin θ in θ' (measured 2.3e-13 over these states, ν 1.5e-13 relative; the
    # tolerances are 40 and 7 times that).
    rng = np.random.default_rng(11)
    served = cases = 0
    seen: set[int] = set()
    for _ in range(400):
        a = float(rng.normal() * rng.choice([1.0, 1e-3]))
        b = float(rng.normal() * rng.choice([1.0, 1e-3]))
        mu, R, G = rng.uniform(0.2, 2.0), rng.normal(), rng.normal()
        theta, theta_dot = rng.uniform(0.05, math.pi - 0.05), rng.normal()
        try:
            state = NutationOrbit.from_state(mu, a, b, R, G, theta, theta_dot)
            orbit = NutationOrbit.from_energy(mu, a, b, R, G, state.E, math.cos(theta))
        except ParameterError:
            continue
        if orbit.kind == "steady":
            continue
        cases += 1
        th, thd, info = orbit_nodes(np.array([[orbit.E, R, G, a, b]]), math.cos(theta), 24)
        if np.isnan(info[0, 0]):  # a turning point next to a pole: the Python orbit's part
            assert min(1.0 - orbit.u1, 1.0 + orbit.u2) < POLE_CLEARANCE
            continue
        _, p_th, p_thd, _ = orbit.nodes(24)
        assert np.max(np.abs(th[0] - p_th)) < 1e-11
        assert np.max(np.abs(thd[0] - p_thd)) < 1e-11 * max(1.0, np.max(np.abs(p_thd)))
        assert info[0, 0] == pytest.approx(2.0 * math.pi / orbit.period, rel=1e-12)
        assert (info[0, 1], info[0, 2]) == pytest.approx((orbit.u1, orbit.u2), abs=1e-12)
        served += 1
        seen.add(orbit.root_case)
    assert served > 0.8 * cases and seen == {1, 2}


def test_orbit_nodes_refuse_what_they_cannot_serve():
    # No motion at this energy, and the free body: NaN rows, for the Python orbit to answer.
    th, thd, info = orbit_nodes(np.array([[-5.0, 0.4, 0.6, -1.0, -0.3],
                                          [1.0, 0.4, 0.6, 0.0, 0.0]]), 0.5, 8)  # fmt: skip
    assert np.all(np.isnan(th)) and np.all(np.isnan(thd)) and np.all(np.isnan(info))
