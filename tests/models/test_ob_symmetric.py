"""A symmetric orbiting body (a rocket body, I2 = I3) on the compiled averaging engine: its
year is the limit of the slightly triaxial bodies' years."""

from __future__ import annotations

import warnings

import numpy as np
from files import EXAMPLES

from tumble.integrate import simulate
from tumble.io import load_scenario

ROCKET = EXAMPLES / "ob_rocket_body.toml"


def _year(tmp_path, i2):
    text = ROCKET.read_text().replace("[2160.0, 5580.0, 5580.0]", f"[2160.0, {i2!r}, 5580.0]")
    path = tmp_path / f"rocket_{i2}.toml"
    path.write_text(text)
    r = load_scenario(path).request
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the validity checks are not under test here
        traj = simulate(r.model, r.params, r.initial, r.tau, "averaged", rtol=r.rtol, atol=r.atol)
    assert traj.integrator == "numba"
    return traj.columns["period"]


def test_a_rocket_body_year_is_the_limit_of_slightly_triaxial_ones(tmp_path):
    symmetric = _year(tmp_path, 5580.0)
    # The spin period after a year against a body 1.4 % from symmetric: within 0.1 %
    # (measured 0.060 %).
    assert abs(symmetric[-1] / _year(tmp_path, 5500.0)[-1] - 1.0) < 1e-3
    # As I2 → I3 the triaxial year tends to the symmetric one linearly in I3 − I2: the
    # largest period difference over the year at 1 and 0.1 kg m² from symmetric (measured
    # 5.856e-5 and 5.862e-6, a ratio of 9.99; the runs' own error at rtol 1e-10 is far below).
    far, near = (np.max(np.abs(_year(tmp_path, i2) / symmetric - 1.0)) for i2 in (5579.0, 5579.9))
    assert 9.5 < far / near < 10.5 and near < 1e-5, (far, near)


def test_a_rocket_body_warns_of_no_spin_phase_it_does_not_have(tmp_path):
    # Its torques (the eddy current of a conductor along its axis, the gravity gradient) are
    # symmetric about its axis: the spin about the axis, ν1 = 0 at its flat spin, drops out
    # of the averages, and no warning speaks of it (before: "slowest fast frequency (0 rad/t)"
    # from t = 0, "1·ν1 + 0·ν2 = 0" later). A spin-rate resonance with the orbit may remain.
    r = load_scenario(ROCKET).request
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        from tumble.analysis.run import run

        run(r)
    said = [str(w.message) for w in seen]
    assert not [s for s in said if "slowest fast frequency" in s or "1·ν1" in s], said


def test_the_spin_phase_counts_where_the_torque_is_not_symmetric_about_the_axis():
    from tumble.models import torqued_body as tb
    from tumble.models.torqued_body.model import _spin_free
    from tumble.torques import ConstantBodyTorque, LinearDrag

    symmetric = np.array([2.0, 1.0, 2.0])  # axis 2 the unequal one
    on_axis = ConstantBodyTorque(np.array([0.0, 0.3, 0.0])) + LinearDrag(np.diag([0.2, 0.5, 0.2]))
    assert _spin_free(tb.Params(symmetric, 0.01, on_axis))
    off_axis = ConstantBodyTorque(np.array([0.1, 0.3, 0.0]))
    assert not _spin_free(tb.Params(symmetric, 0.01, off_axis))
    drag = LinearDrag(np.diag([0.3, 0.5, 0.2]))  # not symmetric about axis 2
    assert not _spin_free(tb.Params(symmetric, 0.01, drag))
    assert not _spin_free(tb.Params(np.array([1.0, 1.6, 2.0]), 0.01, on_axis))  # triaxial
