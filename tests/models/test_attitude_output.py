"""Every full run writes its attitude (quaternion, scalar first, body → inertial) and its
body angular velocity; both forms of a model write the same ones, and they carry the model's
own angular momentum: R(q) (I ω) is the inertial angular momentum its slow columns give."""

from __future__ import annotations

import io

import numpy as np
import pytest
import xarray as xr
from files import EXAMPLES

import tumble
from tumble.errors import ParameterError
from tumble.integrate import simulate
from tumble.models import nonlinear_moment as nm
from tumble.models import resisting_medium as rm
from tumble.models import rotating_field as rf
from tumble.models import torqued_body as tb
from tumble.rotations import quat_to_matrix
from tumble.torques import GravityGradientTorque

RTOL = 1e-11  # the runs' tolerance; the checks below allow 1e3 of it over the few periods run


def _attitude(cols):
    q = np.stack([cols[f"q{i}"] for i in range(4)], axis=1)
    w = np.stack([cols[f"omega{i}"] for i in (1, 2, 3)], axis=1)
    return q, w


def _inertial(q, inertia, w):
    return np.einsum("nij,nj->ni", quat_to_matrix(q), inertia * w)


def _direction(rho, sigma):
    return np.stack([np.sin(rho) * np.cos(sigma), np.sin(rho) * np.sin(sigma), np.cos(rho)], 1)


def _run(model, p, st, t, form=None):
    return simulate(model, p, st, t, "full", rtol=RTOL, atol=1e-13, form=form).columns


def _check_quaternion(q):
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-14)
    assert np.all(q[:, 0] >= 0.0)


def test_resisting_medium_both_forms():
    p = rm.Params(eps=0.02, kappa=0.5, a=[0.05, 0.0, 0.6], b=np.diag([0.6, 0.6, 0.2]))
    st = rm.State(k=1.0, rho=0.8, sigma=0.3, psi=0.2, theta=0.9, phi=0.1)
    t = np.linspace(0.0, 20.0, 41)
    euler, osculating = _run(rm.MODEL, p, st, t), _run(rm.MODEL, p, st, t, "osculating")
    for cols in (euler, osculating):
        q, w = _attitude(cols)
        _check_quaternion(q)
        # K in the inertial frame: k e_K(ρ, σ), I = (1, 1, 1 + κ).
        K = cols["k"][:, None] * _direction(cols["rho"], cols["sigma"])
        assert np.allclose(_inertial(q, p.inertia, w), K, atol=1e3 * RTOL)
    q1, w1 = _attitude(euler)
    q2, w2 = _attitude(osculating)
    assert np.allclose(q1, q2, atol=1e3 * RTOL) and np.allclose(w1, w2, atol=1e3 * RTOL)


def test_rotating_field_both_forms():
    p = rf.Params(inertia=[1.0, 1.6, 2.2], beta=1.0, eps=0.01)
    st = rf.state_from_elements(p, L=1.8, rho=0.8, sigma=0.3, k2=0.5, regime="x3")
    t = np.linspace(0.0, 20.0, 41)
    rotating, inertial = _run(rf.MODEL, p, st, t), _run(rf.MODEL, p, st, t, "inertial")
    for cols in (rotating, inertial):
        q, w = _attitude(cols)
        _check_quaternion(q)
        L = cols["L"][:, None] * _direction(cols["rho"], cols["sigma"])
        assert np.allclose(_inertial(q, p.inertia, w), L, atol=1e3 * RTOL)
        assert np.array_equal(w[:, 0], cols["z1"])  # ω is z, the paper's body rate
    # The rotating form's Γ is in the field's frame: A = Rz(τ) Γ must be the inertial one.
    q1, _ = _attitude(rotating)
    q2, _ = _attitude(inertial)
    assert np.allclose(q1, q2, atol=1e3 * RTOL)


def test_nonlinear_moment_both_forms():
    p = nm.Params(mu=0.8, a=-1.0, b=-0.3, eps=0.01, d=0.5, nu=0.2)
    st = nm.State(theta=1.0, theta_dot=0.3, psi=0.2, phi=0.1, R=0.4, G=0.6)
    t = np.linspace(0.0, 20.0, 41)
    quaternion, reduced = _run(nm.MODEL, p, st, t), _run(nm.MODEL, p, st, t, "reduced")
    for cols in (quaternion, reduced):
        q, w = _attitude(cols)
        _check_quaternion(q)
        # G = K·e_z/A with K/A = (ω1, ω2, μ ω3) in body axes.
        K = _inertial(q, np.array([1.0, 1.0, p.mu]), w)
        assert np.allclose(K[:, 2], cols["G"], atol=1e3 * RTOL)
    q1, w1 = _attitude(quaternion)
    q2, w2 = _attitude(reduced)
    assert np.allclose(q1, q2, atol=1e3 * RTOL) and np.allclose(w1, w2, atol=1e3 * RTOL)


def test_torqued_body_and_the_rotation_object():
    p = tb.Params(
        inertia=[1.0, 2.0, 3.0],
        eps=0.01,
        torque=GravityGradientTorque(inertia=[1.0, 2.0, 3.0], n=0.3),
    )
    st = tb.State(omega=[0.3, 1.0, 0.2], q=[0.9, 0.1, 0.3, 0.2])
    t = np.linspace(0.0, 20.0, 41)
    traj = simulate(tb.MODEL, p, st, t, "full", rtol=RTOL, atol=1e-13)
    q, w = _attitude(traj.columns)
    _check_quaternion(q)
    L = np.stack([traj.columns[f"L{i}"] for i in (1, 2, 3)], axis=1)
    assert np.allclose(_inertial(q, p.inertia, w), L, atol=1e3 * RTOL)
    # The same attitude as a scipy Rotation: its matrix maps body to inertial.
    R = traj.attitude().as_matrix()
    assert np.allclose(np.einsum("nij,nj->ni", R, p.inertia * w), L, atol=1e3 * RTOL)
    averaged = simulate(tb.MODEL, p, st, t, "averaged")
    with pytest.raises(ParameterError, match="only full runs"):
        averaged.attitude()


@pytest.mark.filterwarnings("ignore::tumble.errors.TumbleWarning")  # the example's resonance
def test_a_runs_netcdf_holds_the_attitude_with_units(tmp_path):
    tumble.run(EXAMPLES / "a3_positive.toml", tmp_path / "a3")
    ds = xr.open_dataset(io.BytesIO((tmp_path / "a3" / "full.nc").read_bytes()), engine="scipy")
    q = np.stack([ds[f"q{i}"].values for i in range(4)], axis=1)
    assert np.allclose(np.linalg.norm(q, axis=1), 1.0, atol=1e-14)
    assert ds["omega1"].attrs["units"] == "rad/τ"
    assert "body → inertial" in ds["q0"].attrs["long_name"]
    assert "q0" in (tmp_path / "a3" / "full.csv").read_text().splitlines()[0]
    assert "q0" not in xr.open_dataset(io.BytesIO((tmp_path / "a3" / "averaged.nc").read_bytes()),
                                       engine="scipy")  # fmt: skip
