"""The compiled triaxial average (built-in torques) against the Python engine, and its Jacobi
functions against scipy's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from compiled_runs import numba_and_scipy
from scipy import special

from tumble.averaging import triaxial_average_vector, triaxial_kernel
from tumble.integrate import simulate
from tumble.kernels import (
    KIND_TRIAXIAL_AVERAGED,
    KIND_TRIAXIAL_CLOSED,
    KIND_TRIAXIAL_PHASE_MEANS,
)
from tumble.kernels.rhs import evaluate
from tumble.kernels.triaxial import jacobi_functions
from tumble.models import rotating_field as rf
from tumble.models import torqued_body as tb
from tumble.models.base import AveragingOptions
from tumble.torques import (
    ConstantBodyTorque,
    ConstantInertialTorque,
    EddyCurrentTorque,
    GravityGradientTorque,
    LinearDrag,
    QuadraticDrag,
)

INERTIA = np.array([1.5, 1.0, 2.2])  # unsorted on purpose: the kernel reads them through Q


# Powers of two, so that scipy, which takes m, gets exactly m = 1 − mc (near m = 1 it forms
# 1 − m itself); and down to mc = 2⁻¹⁰ only, below which scipy's own error grows (4e-13 at
# 2⁻²⁹ against 40-digit values, where the kernel's stays within 6e-15).
@pytest.mark.parametrize("mc", [1.0, 0.75, 2.0**-4, 2.0**-10])
def test_jacobi_functions_equal_scipys(mc):
    m = 1.0 - mc
    K = float(special.ellipk(m))
    u = np.linspace(0.0, 4.0 * K, 203, endpoint=False)
    got = jacobi_functions(u, mc)
    sn, cn, dn, _ = special.ellipj(u, m)
    # Both accurate to a few ulps in absolute terms (all three functions are ≤ 1).
    assert np.max(np.abs(got - np.stack([sn, cn, dn], 1))) < 2e-14


@pytest.mark.parametrize("mc", [2.0**-20, 2.0**-29, 1e-12, 1e-15])
def test_jacobi_functions_invert_the_elliptic_integral_near_the_separatrix(mc):
    # Over the first quarter period u = F(am u | m) = sn·R_F(cn², dn², 1) (DLMF 19.25.5) with
    # scipy's R_F (a few ulps for any arguments), and dn² = mc + m cn² (DLMF 22.6.1): both
    # hold to round-off in absolute terms, however close to the separatrix.
    m = 1.0 - mc
    K = float(special.elliprf(0.0, mc, 1.0))
    u = np.linspace(0.0, K, 101)
    sn, cn, dn = jacobi_functions(u, mc).T
    back = sn * special.elliprf(cn * cn, dn * dn, 1.0)
    # F(φ) = u amplifies an error δ of sn by dF/d(sn) = 1/(cn dn), up to 1/k′ near u = K:
    # the bound is a few ulps of K through that factor (measured: at most 1.4 % of it).
    assert np.all(np.abs(back - u) <= 1e-15 * K * (1.0 + 1.0 / (cn * dn + 1e-300)))
    assert np.max(np.abs(dn * dn - (mc + m * cn * cn))) < 1e-15


def _torques():
    gg = GravityGradientTorque(INERTIA, 0.3, np.array([0.2, -0.4, 0.9]), 0.3)
    return {
        "gravity gradient": (gg, gg.period),
        "eddy current": (EddyCurrentTorque(0.7, 1.0, 0.6), 2.0 * math.pi),
        "all terms": (
            gg
            + ConstantInertialTorque(np.array([0.1, -0.2, 0.05]))
            + ConstantBodyTorque(np.array([0.0, 0.1, -0.1]))
            + LinearDrag(np.diag([0.3, 0.2, 0.1]))
            + QuadraticDrag(np.diag([0.05, 0.1, 0.02])),
            gg.period,
        ),
        "harmonic": (EddyCurrentTorque(0.7, 2.0, 0.9), 2.0 * math.pi),  # two field turns a period
    }


@pytest.mark.parametrize("branch", [1.0, -1.0])
@pytest.mark.parametrize("name", sorted(_torques()))
def test_compiled_average_equals_the_python_engine(name, branch):
    # In both senses of rotation: the body moment and the drags of "all terms" tell them
    # apart (a test below holds them to the full equations).
    torque, period = _torques()[name]
    kernel = triaxial_kernel(torque, INERTIA, period, branch=branch)
    triaxial = (KIND_TRIAXIAL_CLOSED, KIND_TRIAXIAL_PHASE_MEANS, KIND_TRIAXIAL_AVERAGED)
    assert kernel is not None and kernel.kind in triaxial
    rng = np.random.default_rng(11)
    I1, I2, I3 = sorted(INERTIA)
    for _ in range(30):
        L_xi = rng.normal(size=3)
        # r over both regimes, away from the separatrix band and the pure rotations.
        r = rng.uniform(1.0 / I3, 1.0 / I1)
        if abs(r * I2 - 1.0) < 1e-6:
            continue
        y = np.array([*L_xi, r])
        got = evaluate(kernel.kind, 0.0, y, kernel.params)
        ref = triaxial_average_vector(torque, INERTIA, y, 0.0, forcing_period=period,
                                      branch=branch)  # fmt: skip
        # Both stop refining the polhode when two levels agree to 1e-12 of the torque's size;
        # the forcing phase (closed form here) and the precession (exact on 4 nodes here, 8
        # there) add round-off only: agreement to 1e-10 of the largest rate (measured 2e-14).
        scale = max(float(np.max(np.abs(ref))), 1e-300)
        assert np.max(np.abs(got - ref)) <= 1e-10 * scale, (y, got, ref)


SYMMETRIC = {
    "prolate": np.array([2.0, 1.0, 2.0]),  # a rocket body: I1 < I2 = I3 (unsorted on purpose)
    "oblate": np.array([1.2, 2.2, 1.2]),  # a disc: I1 = I2 < I3
    "sphere": np.array([1.5, 1.5, 1.5]),
}


def _symmetric_torques(inertia):
    gg = GravityGradientTorque(inertia, 0.3, np.array([0.2, -0.4, 0.9]), 0.3)
    return {
        "gravity gradient": (gg, gg.period),
        "eddy current": (EddyCurrentTorque(0.7, 1.0, 0.6), 2.0 * math.pi),
        "not axisymmetric": (
            gg
            + ConstantBodyTorque(np.array([0.0, 0.1, -0.1]))
            + LinearDrag(np.diag([0.3, 0.2, 0.1]))
            + QuadraticDrag(np.diag([0.05, 0.1, 0.02])),
            gg.period,
        ),
    }


def _flat_spin(I1, I2, I3):
    """2T/L² of the flat spin about the two equal axes (none for the sphere)."""
    return 1.0 / I3 if I3 - I2 < I2 - I1 else 1.0 / I1


@pytest.mark.parametrize("branch", [1.0, -1.0])
@pytest.mark.parametrize("body", sorted(SYMMETRIC))
def test_symmetric_bodies_average_compiled_as_the_python_engine(body, branch):
    # A rocket body, a disc and a sphere run the compiled engine (the polhode at m = 0) and
    # agree with the Python engine's symmetric Euler–Poinsot motion at every r, except on
    # the flat spin about the equal axes (below).
    inertia = SYMMETRIC[body]
    I1, I2, I3 = sorted(inertia)
    rng = np.random.default_rng(5)
    for name, (torque, period) in _symmetric_torques(inertia).items():
        kernel = triaxial_kernel(torque, inertia, period, branch=branch)
        assert kernel is not None, name
        rs = [*rng.uniform(1.0 / I3, 1.0 / I1, 8), 1.0 / I3, 1.0 / I1]
        for r in rs:
            if body != "sphere" and r == _flat_spin(I1, I2, I3):
                continue
            y = np.array([*rng.normal(size=3), r])
            got = evaluate(kernel.kind, 0.0, y, kernel.params)
            if body == "sphere" and name == "gravity gradient":
                # No gravity-gradient moment on a sphere (the Python engine's relative test
                # cannot converge on an integrand of round-off): zero to round-off.
                assert np.max(np.abs(got)) < 1e-15, got
                continue
            ref = triaxial_average_vector(torque, inertia, y, 0.0, forcing_period=period,
                                          branch=branch)  # fmt: skip
            # As for the triaxial body above: 1e-10 of the largest rate (measured ≤ 5e-15).
            scale = max(float(np.max(np.abs(ref))), 1e-300)
            assert np.max(np.abs(got - ref)) <= 1e-10 * scale, (name, y, got, ref)


@pytest.mark.parametrize("body", ["prolate", "oblate"])
def test_the_flat_spin_of_a_symmetric_body_is_the_limit_of_its_neighbours(body):
    # On the flat spin about the equal axes the polhode is a circle of pure rotations (no
    # motion along it): the compiled engine averages over the circle, the value the average
    # tends to as r approaches it, where the polhode frequency tends to 0 (the Python engine
    # takes one point of the circle). The amplitudes go as √|r − r_flat|: at 1e-14 away, a
    # relative change of ~1e-7.
    inertia = SYMMETRIC[body]
    I1, I2, I3 = sorted(inertia)
    flat = _flat_spin(I1, I2, I3)
    inward = 1e-14 if flat == 1.0 / I3 else -1e-14
    torque, period = _symmetric_torques(inertia)["not axisymmetric"]
    kernel = triaxial_kernel(torque, inertia, period)
    y = np.array([0.3, -0.5, 0.8, flat])
    at = evaluate(kernel.kind, 0.0, y, kernel.params)
    near = evaluate(kernel.kind, 0.0, np.array([*y[:3], flat * (1.0 + inward)]), kernel.params)
    assert np.all(np.isfinite(at))
    assert np.max(np.abs(at - near)) <= 1e-6 * np.max(np.abs(at)), (at, near)


def test_what_the_compiled_engine_refuses():
    gg = GravityGradientTorque(INERTIA, 0.3, np.array([0.0, 0.0, 1.0]), 0.0)
    assert triaxial_kernel(gg, INERTIA, None) is None  # time-dependent, no forcing period
    assert triaxial_kernel(gg, INERTIA, 1.5 * gg.period) is None  # not a whole number of orbits
    assert triaxial_kernel(lambda t, q, w: np.zeros(3), INERTIA, None) is None  # Python torque
    kernel = triaxial_kernel(gg, INERTIA, 2.0 * gg.period)  # two orbits a period: fine
    assert kernel is not None
    I1, I2, _ = sorted(INERTIA)
    for y in ([1.0, 0.0, 0.0, 1.2 / I1], [0.0, 0.0, 0.0, 1.0 / I2]):
        # beyond a pure rotation, L = 0: the step is rejected
        assert np.all(np.isnan(evaluate(kernel.kind, 0.0, np.array(y), kernel.params)))
    # On the separatrix, where the Python engine refuses the state, the compiled one takes the
    # motion at the edge of the band |1 − r I2| ≤ 1e-12 on the state's side (the one-sided
    # limit), so that a run creeping onto it steps across to its event instead of stalling.
    on = evaluate(kernel.kind, 0.0, np.array([1.0, 0.0, 0.0, 1.0 / I2]), kernel.params)
    edge = evaluate(kernel.kind, 0.0, np.array([1.0, 0.0, 0.0, (1.0 - 1e-12) / I2]), kernel.params)
    assert np.all(np.isfinite(on))
    # The same polhode but for r itself, which the rates read apart from it: ~1e-12 apart.
    np.testing.assert_allclose(on, edge, rtol=1e-9, atol=1e-15)


NUMERIC = AveragingOptions(averaging="numeric")


def test_compiled_engine_run_equals_the_python_one_across_the_separatrix():
    # The rotating field takes r = 2T/L² down through 1/I2 from a spin near the axis of the
    # least moment (regime x1): the compiled run stops at the event there, steps over and
    # restarts, as scipy's does with the Python engine.
    p = rf.Params(inertia=[1.0, 1.6, 2.0], eps=0.05, beta=0.6)
    st = rf.State([1.2, 0.3, 0.2], np.eye(3))
    tau = np.linspace(0.0, 150.0, 31)
    runs = numba_and_scipy(
        rf.MODEL, p, st, tau, "averaged", rtol=1e-10, atol=1e-12, averaging=NUMERIC
    )
    cols = runs["numba"].columns
    r = 2.0 * cols["T"] / cols["L"] ** 2
    assert r[0] > 1.0 / 1.6 > r[-1]  # the run crosses the separatrix
    for name, ref in runs["scipy"].columns.items():
        # The same DOP853 on rates equal to 1e-10 of their size: the runs agree to its
        # tolerance, except k² after the separatrix, where the step over it (relative
        # 1e-6 in r) leaves k² = 1 − O(1e-6) sensitive to the last digits of r (measured:
        # 1e-8 on L and T, 1.3e-7 on k²).
        assert np.max(np.abs(cols[name] - ref)) < 1e-6, name


def test_torqued_body_runs_compiled():
    p = tb.Params(inertia=INERTIA, eps=0.02, torque=_torques()["all terms"][0],
                  forcing_period=_torques()["all terms"][1])  # fmt: skip
    st = tb.State(omega=np.array([0.2, 0.3, 1.0]), q=np.array([1.0, 0.0, 0.0, 0.0]))
    tau = np.linspace(0.0, 100.0, 11)
    runs = numba_and_scipy(tb.MODEL, p, st, tau, "averaged", rtol=1e-10, atol=1e-12)
    for name, ref in runs["scipy"].columns.items():
        assert np.max(np.abs(runs["numba"].columns[name] - ref)) < 1e-7, name


def test_a_run_refused_at_its_start_says_why():
    # A spin about the intermediate axis sits on the separatrix, where the averaged equations
    # have no regime to take: the run is refused with the Python engine's reason, alone and in
    # an ensemble.
    from tumble.errors import IntegrationError
    from tumble.integrate import simulate_batch

    torque, period = _torques()["gravity gradient"]
    p = tb.Params(inertia=INERTIA, eps=0.02, torque=torque, forcing_period=period)
    st = tb.State(omega=np.array([1.0, 0.0, 0.0]))  # the first moment, 1.5, is the middle one
    tau = np.linspace(0.0, 10.0, 3)
    with pytest.raises(IntegrationError, match=r"refuse the initial state: .*separatrix"):
        simulate(tb.MODEL, p, st, tau, "averaged")
    (got,) = simulate_batch(tb.MODEL, [p], [st], tau, method="averaged")
    assert isinstance(got, IntegrationError) and "separatrix" in str(got)


def test_the_senses_differ_only_for_a_torque_the_turn_between_them_changes():
    # The turn by π about a principal axis carries one sense of rotation to the other and
    # leaves the gravity gradient, the eddy current, a diagonal drag and a damper as they are:
    # their averages are the same in both senses, to the bit. A moment fixed in the body
    # along the encircled axis is turned over: its rates differ.
    from tumble.torques import ConstantBodyTorque, InternalDissipation

    gg = GravityGradientTorque(INERTIA, 0.3, np.array([0.2, -0.4, 0.9]), 0.3)
    y = np.array([0.3, -0.5, 0.8, 0.7])  # regime x1 (r > 1/I2 = 1/1.5)
    same = {
        "gravity gradient": (gg, gg.period),
        "eddy current": (EddyCurrentTorque(0.7, 1.0, 0.6), 2.0 * math.pi),
        "drag": (LinearDrag(np.diag([0.3, 0.2, 0.1])), None),
        "damper": (InternalDissipation(INERTIA, 5.0), None),
    }
    for name, (torque, period) in same.items():
        plus, minus = (triaxial_kernel(torque, INERTIA, period, branch=b) for b in (1.0, -1.0))
        assert plus is not None and minus is not None
        a = evaluate(plus.kind, 0.0, y, plus.params)
        b = evaluate(minus.kind, 0.0, y, minus.params)
        assert np.array_equal(a, b), name
    body = ConstantBodyTorque(np.array([0.0, 0.1, 0.0]))  # along user y: the sorted least axis
    plus, minus = (triaxial_kernel(body, INERTIA, None, branch=b) for b in (1.0, -1.0))
    assert plus is not None and minus is not None
    a, b = evaluate(plus.kind, 0.0, y, plus.params), evaluate(minus.kind, 0.0, y, minus.params)
    assert np.max(np.abs(a + b)) < 1e-12 * np.max(np.abs(a))  # turned over: opposite rates
