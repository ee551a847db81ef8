"""The torqued body in SI units: a scenario given in kg·m², rad/s, km and seconds is the
normalised one (t = T0 τ, T0 = 1/|ω(0)|, moments of inertia over the largest, ε = 1) and
writes its columns in SI beside the normalised ones."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest
import xarray as xr
from files import EXAMPLES, read_csv, write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.integrate import simulate
from tumble.io import load_scenario
from tumble.models.inputs.torqued_body import EARTH_MU, EARTH_RADIUS, orbital_rate

LEO = EXAMPLES / "tb_gravity_gradient_leo.toml"


def test_the_orbital_rate_of_a_circular_orbit():
    # Kepler's third law at r = R + h; 700 km: one orbit in 98.77 min (the period of the
    # sun-synchronous orbits flown there).
    n = orbital_rate(700.0)
    assert n == pytest.approx(math.sqrt(EARTH_MU / (EARTH_RADIUS + 7e5) ** 3), rel=1e-15)
    assert 2.0 * math.pi / n / 60.0 == pytest.approx(98.77, abs=0.01)


def test_the_physical_scenario_is_the_normalised_one(tmp_path):
    sc = load_scenario(LEO)
    p, st, scaling = sc.request.params, sc.request.initial, sc.request.scaling
    omega = np.array([0.01, 0.02, 0.03])  # the example's [initial] omega [rad/s]
    T0 = 1.0 / float(np.linalg.norm(omega))
    assert scaling.T0 == pytest.approx(T0, rel=1e-15) and scaling.I0 == 18.0
    assert p.eps == 1.0 and np.allclose(p.inertia, np.array([10.0, 14.0, 18.0]) / 18.0)
    assert np.allclose(st.omega, omega * T0, rtol=1e-15)
    # The same run written by hand in normalised units: n T0 and t/T0.
    text = (
        'model = "torqued_body"\n'
        + f"""
[parameters]
inertia = {(np.array([10.0, 14.0, 18.0]) / 18.0).tolist()}
eps = 1.0

[[torque]]
kind = "gravity_gradient"
n = {orbital_rate(700.0) * T0!r}
normal = [0.0, -0.98978, -0.14263]

[initial]
omega = {(omega * T0).tolist()}
psi_deg = 0.0
theta_deg = 40.0
phi_deg = 30.0

[run]
t_end = {86400.0 / T0!r}
samples = 401
"""
    )
    by_hand = load_scenario(write(tmp_path, text)).request
    assert np.allclose(by_hand.tau, sc.request.tau, rtol=1e-14)
    tau = sc.request.tau[:41]  # the first 2.4 hours: ~320 normalised time units
    a = simulate(sc.request.model, p, st, tau, "full", rtol=1e-11, atol=1e-13)
    b = simulate(by_hand.model, by_hand.params, by_hand.initial, tau, "full", rtol=1e-11,
                 atol=1e-13)  # fmt: skip
    # Equal inputs up to the round-off of the conversions (1e-16 relative), integrated at
    # rtol 1e-11: the trajectories agree to the tolerance, not to round-off.
    for name in ("L1", "L2", "L3", "T", "q0", "omega1"):
        assert np.allclose(a.columns[name], b.columns[name], rtol=0.0, atol=1e-9), name


def test_a_physical_run_writes_si_columns(tmp_path):
    result = CliRunner().invoke(app, ["run", str(LEO), "--out", str(tmp_path / "leo")])
    assert result.exit_code == 0, result.output
    header, rows = read_csv(tmp_path / "leo" / "full_si.csv")
    first = dict(zip(header, rows[0], strict=True))
    # |L| = |I ω| = |(0.1, 0.28, 0.54)| kg·m²/s, T = ½ ω·Iω = 0.0114 J at t = 0.
    assert first["L_kgm2_s"] == pytest.approx(math.sqrt(0.1**2 + 0.28**2 + 0.54**2), rel=1e-12)
    assert first["T_J"] == pytest.approx(0.0114, rel=1e-12)
    assert first["omega3_rad_s"] == pytest.approx(0.03, rel=1e-12)
    assert rows[-1][header.index("t_s")] == pytest.approx(86400.0, rel=1e-12)
    # The NetCDF holds both: the normalised columns and the SI ones with their units.
    nc = tmp_path / "leo" / "full.nc"
    ds = xr.open_dataset(io.BytesIO(nc.read_bytes()), engine="scipy")
    assert ds["T_J"].attrs["units"] == "J" and ds["t_s"].attrs["units"] == "s"
    assert float(ds["T_J"].values[0]) == pytest.approx(0.0114, rel=1e-12)
    assert "T" in ds and ds["T"].attrs["units"] == "1"  # the normalised energy beside it


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        ("altitude = 700.0 ", "altitude = -10.0 ", "altitude"),
        ("altitude = 700.0 ", "altitude = 700.0\nn = 0.001 ", "altitude"),
        ("omega = [0.01, 0.02, 0.03]", "omega = [0.0, 0.0, 0.0]", "initial.omega"),
        ('kind = "gravity_gradient"', 'kind = "user"', "torque[0].kind"),
        ("inertia = [10.0, 14.0, 18.0]", "inertia = [10.0, 14.0, 30.0]", "inertia"),
    ],
)
def test_bad_physical_input_is_one_line(tmp_path, old, new, field):
    text = LEO.read_text()
    assert old in text
    path = write(tmp_path, text.replace(old, new))
    result = CliRunner().invoke(app, ["run", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert field in result.output and "Traceback" not in result.output
