"""A user's torque written as a numba function: compiled on the full path and in the general
engine's triaxial setting, equal to the same physics built in and to the Python engine."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from tumble.averaging import triaxial_average_vector, triaxial_kernel
from tumble.errors import ParameterError, UserCodeError
from tumble.integrate import simulate
from tumble.kernels import KIND_TRIAXIAL_AVERAGED, KIND_TRIAXIAL_CLOSED
from tumble.kernels.rhs import evaluate
from tumble.models import torqued_body as tb
from tumble.torques import GravityGradientTorque, UserTorque

INERTIA = np.array([1.5, 1.0, 2.2])
N, U0 = 0.3, 0.3


@numba.njit
def gravity_gradient(t, q, omega, params):  # type: ignore[no-untyped-def]
    """3n² r̂ × I r̂ of a circular orbit in the plane normal to ξ3, r̂ in body axes: the
    built-in gravity gradient written by a user; params = [n, u0, I1, I2, I3]."""
    n, u0 = params[0], params[1]
    u = n * t + u0
    x, y = math.cos(u), math.sin(u)
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    # r̂_b = Aᵀ r̂ with r̂ = (cos u, sin u, 0): the first two columns of Aᵀ.
    r1 = (1 - 2 * (q2 * q2 + q3 * q3)) * x + 2 * (q1 * q2 + q0 * q3) * y
    r2 = 2 * (q1 * q2 - q0 * q3) * x + (1 - 2 * (q1 * q1 + q3 * q3)) * y
    r3 = 2 * (q1 * q3 + q0 * q2) * x + 2 * (q2 * q3 - q0 * q1) * y
    g = 3.0 * n * n
    i1, i2, i3 = params[2], params[3], params[4]
    return np.array([g * (i3 - i2) * r2 * r3, g * (i1 - i3) * r3 * r1, g * (i2 - i1) * r1 * r2])


def _user():
    params = {"n": N, "u0": U0, "I1": INERTIA[0], "I2": INERTIA[1], "I3": INERTIA[2]}
    return UserTorque(gravity_gradient, params, "test:gravity_gradient")


def _built_in():
    return GravityGradientTorque(INERTIA, N, np.array([0.0, 0.0, 1.0]), U0)


def test_a_numba_torque_has_a_program_and_equals_the_built_in_one():
    user, built = _user(), _built_in()
    assert user.program is not None
    rng = np.random.default_rng(3)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1)[:, None]
    w = rng.normal(size=(50, 3))
    t = rng.uniform(0.0, 30.0)
    # The same formula through a C callback: equal to round-off (a few ulps of 3n²·I).
    assert np.allclose(user(t, q, w), built(t, q, w), rtol=0.0, atol=1e-14)


def test_its_params_must_be_numbers():
    with pytest.raises(ParameterError, match=r"torque_params\.n"):
        _ = UserTorque(gravity_gradient, {"n": "fast"}, "test").program


def test_the_full_run_is_compiled_and_equals_the_built_in_one():
    st = tb.State(omega=np.array([0.2, 0.3, 1.0]), q=np.array([0.9, 0.1, -0.3, 0.2]))
    tau = np.linspace(0.0, 50.0, 11)
    runs = {}
    for name, torque in (("user", _user()), ("built", _built_in())):
        p = tb.Params(inertia=INERTIA, eps=0.02, torque=torque, forcing_period=2 * math.pi / N)
        runs[name] = simulate(tb.MODEL, p, st, tau, "full", rtol=1e-10, atol=1e-12)
    assert runs["user"].integrator == runs["built"].integrator == "numba"
    for col, ref in runs["built"].columns.items():
        # One formula, two transcriptions: the runs differ by the round-off of the moment
        # (1e-16) grown over 50 time units at rtol 1e-10: within 1e-9.
        assert np.max(np.abs(runs["user"].columns[col] - ref)) < 1e-9, col


def test_the_triaxial_engine_averages_it_compiled_as_the_python_engine_does():
    user, built = _user(), _built_in()
    period = 2 * math.pi / N
    k_user = triaxial_kernel(user, INERTIA, period)
    k_built = triaxial_kernel(built, INERTIA, period)
    assert k_user is not None and k_user.kind == KIND_TRIAXIAL_AVERAGED  # the product rule
    assert k_built is not None and k_built.kind == KIND_TRIAXIAL_CLOSED  # a closed form
    rng = np.random.default_rng(9)
    I1, I2, I3 = sorted(INERTIA)
    for _ in range(10):
        y = np.array([*rng.normal(size=3), rng.uniform(1.0 / I3, 1.0 / I1)])
        if abs(y[3] * I2 - 1.0) < 1e-6:
            continue
        ref = triaxial_average_vector(built, INERTIA, y, 0.0, forcing_period=period)
        scale = float(np.max(np.abs(ref)))
        # The three quadratures stop refining when two levels agree to 1e-12 of the torque's
        # size: the user's function (general rule), the built-in term by the same rule and by
        # its closed form, and the Python engine agree to 1e-10 of the largest rate.
        # (the built-in terms by the closed form, and through the general product rule too)
        for kind, params in (
            (k_user.kind, k_user.params),
            (KIND_TRIAXIAL_AVERAGED, k_built.params),
            (k_built.kind, k_built.params),
        ):
            got = evaluate(kind, 0.0, y, params)
            assert np.max(np.abs(got - ref)) <= 1e-10 * scale, (y, got, ref)


def test_the_averaged_run_with_a_numba_torque_is_compiled():
    p = tb.Params(inertia=INERTIA, eps=0.02, torque=_user(), forcing_period=2 * math.pi / N)
    st = tb.State(omega=np.array([0.2, 0.3, 1.0]))
    tau = np.linspace(0.0, 100.0, 6)
    run = simulate(tb.MODEL, p, st, tau, "averaged", rtol=1e-10, atol=1e-12)
    ref = simulate(tb.MODEL, tb.Params(inertia=INERTIA, eps=0.02, torque=_built_in(),
                                       forcing_period=2 * math.pi / N), st, tau, "averaged",
                   rtol=1e-10, atol=1e-12)  # fmt: skip
    assert run.integrator == "numba"
    for col, values in ref.columns.items():
        # Rates equal to 1e-10 of their size, integrated at rtol 1e-10: agreement to 1e-8.
        assert np.max(np.abs(run.columns[col] - values)) < 1e-8, col


def test_a_pickled_torque_rebuilds_its_program_where_it_lands():
    # A program holds the address of this process's callback: it must not travel.
    import pickle

    p = tb.Params(inertia=INERTIA, eps=0.02, torque=_user() + _built_in(),
                  forcing_period=2 * math.pi / N)  # fmt: skip
    assert p.kernel is not None and p.torque.program is not None  # both cached here
    again = pickle.loads(pickle.dumps(p))
    assert "kernel" not in again.__dict__ and "program" not in again.torque.__dict__
    assert np.array_equal(again.torque.program, p.torque.program)  # rebuilt (same process)


@numba.njit
def _two_numbers(t, q, omega, params):  # type: ignore[no-untyped-def]
    return np.array([0.0, 0.0])


def test_a_broken_numba_torque_fails_from_python_not_inside_the_callback():
    with pytest.raises(UserCodeError, match="must return the 3 body components"):
        _ = UserTorque(_two_numbers, {}, "test:two").program
    # An exception of the function (here tumble's bounds check: the function is compiled
    # again with it) is one error naming the function, the exception and the state.
    with pytest.raises(UserCodeError, match=r"test:broken raised IndexError.* at t = 0"):
        _ = UserTorque(_broken_checked, {"a": 1.0, "b": 2.0}, "test:broken").program


@numba.njit
def _broken_checked(t, q, omega, params):  # type: ignore[no-untyped-def]
    return np.array([params[5], 0.0, 0.0])
