"""Rotating-field scenario contract: keys, outputs, physical units, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from files import ROOT, read_csv, write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.io import parse_scenario, template
from tumble.models import rotating_field as rf
from tumble.models.base import attitude_columns

ATTITUDE = [c.name for c in attitude_columns("t")]  # every full run's last columns

runner = CliRunner()

CONTRACT = """
model = "rotating_field"
[parameters]
inertia = [1.0, 2.0, 2.5]
beta = 1.5707963267948966
eps = 0.02
[initial]
z = [0.2, 0.3, 1.2]
gamma = [[1.0, 0.0, 0.0], [0.0, 0.8, -0.6], [0.0, 0.6, 0.8]]
[run]
tau_end = 50.0
samples = 51
methods = ["full", "averaged"]
rtol = 1e-10
atol = 1e-12
"""

ELEMENTS = """
model = "rotating_field"
[parameters]
inertia = [2.5, 1.0, 2.0]
beta_deg = 60.0
eps = 0.01
[initial]
L = 1.5
rho_deg = 30.0
sigma = 0.2
k2 = 0.4
regime = "x1"
u0 = 0.3
psi0_deg = 10.0
[run]
tau = [0.0, 1.0, 2.5, 10.0]
"""


def test_run_writes_the_contract_outputs(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, CONTRACT)), "-o", str(out)])
    assert res.exit_code == 0, res.output
    header, full = read_csv(out / "full.csv")
    assert header == ["tau", "L", "rho", "sigma", "T", "k2", "z1", "z2", "z3", *ATTITUDE]
    h, avg = read_csv(out / "averaged.csv")
    assert h == ["tau", "L", "rho", "sigma", "T", "k2"]
    assert np.array_equal(full[:, 0], np.linspace(0.0, 50.0, 51))
    assert np.array_equal(avg[:, 0], full[:, 0])
    # First row: the initial state's slow variables, identical for both methods.
    assert np.allclose(full[0, 1:6], avg[0, 1:], rtol=1e-12, atol=1e-14)
    assert full[0, 6:9] == pytest.approx([0.2, 0.3, 1.2], abs=1e-15)
    assert np.all((full[:, 5] >= 0.0) & (full[:, 5] <= 1.0))
    summary = json.loads((out / "summary.json").read_text())
    assert summary["model"] == "rotating_field"
    assert set(summary["diagnostics"]["averaged"]) == {"nu1", "nu2"}
    assert summary["predicted_limits"]["L"] == 2.5
    h, _ = read_csv(out / "averaged_diagnostics.csv")
    assert h == ["tau", "nu1", "nu2"]
    assert (out / "evolution.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_slow_elements_and_degrees():
    sc = parse_scenario(__import__("tomllib").loads(ELEMENTS))
    p, st0 = sc.request.params, sc.request.initial
    assert p.beta == pytest.approx(math.radians(60.0))
    s = rf.slow_elements(p, st0)
    # The elements come back through (3.1) and a rotation: round-off.
    assert s["L"] == pytest.approx(1.5, rel=1e-13)
    assert s["rho"] == pytest.approx(math.radians(30.0), abs=1e-13)
    assert s["sigma"] == pytest.approx(0.2, abs=1e-13)
    assert s["k2"] == pytest.approx(0.4, abs=1e-12)
    assert list(sc.request.tau) == [0.0, 1.0, 2.5, 10.0]
    assert sc.request.methods == ("full", "averaged")


def test_physical_scenario_equals_its_normalized_twin(tmp_path):
    """SI input normalized by τ = ωt, z = Ω/ω, moments over max I, ε = k_f H²/(ω I_ref)."""
    omega, I_ref = 2.0, 4.0
    k_f, H = 0.01, 3.0
    physical = f"""
model = "rotating_field"
[physical]
inertia = [2.0, 3.2, {I_ref}]
k_f = {k_f}
H = {H}
omega = {omega}
beta_deg = 70.0
[initial]
Omega = [0.4, -0.2, 2.6]
gamma = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
[run]
t_end_s = 20.0
samples = 11
"""
    eps = k_f * H**2 / (omega * I_ref)
    twin = f"""
model = "rotating_field"
[parameters]
inertia = [0.5, 0.8, 1.0]
beta_deg = 70.0
eps = {eps!r}
[initial]
z = [0.2, -0.1, 1.3]
gamma = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
[run]
tau_end = 40.0
samples = 11
"""
    out_p, out_n = tmp_path / "p", tmp_path / "n"
    assert (
        runner.invoke(
            app, ["run", str(write(tmp_path, physical, "p.toml")), "-o", str(out_p)]
        ).exit_code
        == 0
    )
    assert (
        runner.invoke(
            app, ["run", str(write(tmp_path, twin, "n.toml")), "-o", str(out_n)]
        ).exit_code
        == 0
    )
    for m in ("full", "averaged"):
        _, a = read_csv(out_p / f"{m}.csv")
        _, b = read_csv(out_n / f"{m}.csv")
        # Same equations up to the scaling of the inputs: integration tolerance (rtol 1e-10).
        assert np.allclose(a, b, rtol=1e-8, atol=1e-9)
        h, si = read_csv(out_p / f"{m}_si.csv")
        assert h[:3] == ["t_s", "t_days", "L_kgm2_s"]
        assert np.allclose(si[:, 0], np.linspace(0.0, 20.0, 11))
        assert np.allclose(si[:, 1], si[:, 0] / 86400.0, rtol=1e-15)
        assert np.allclose(si[:, 2], I_ref * omega * a[:, 1], rtol=1e-15)


BAD = [
    ("inertia = [1.0, 2.0, 2.5]", "inertia = [1.0, 1.0, 2.5]", "triangle inequality"),
    ("eps = 0.02", "eps = 0.0", "parameters.eps = 0"),
    ("eps = 0.02", "eps = -1.0", "parameters.eps = -1"),
    ("beta = 1.5707963267948966", "beta = 4.0", "parameters.beta = 4"),
    ("[0.0, 0.6, 0.8]]", "[0.0, 0.6, 0.9]]", "initial.gamma is not a rotation"),
    ("[0.0, 0.6, 0.8]]", "[0.0, 0.6, 0.8]]\nL = 1.0", "not both"),
    ('methods = ["full", "averaged"]', 'methods = ["closed_form"]', "closed_form"),
    ("z = [0.2, 0.3, 1.2]", "z = [0.2, 0.3]", "initial.z"),
    ("eps = 0.02", "eps = 0.02\nkappa = 1.0", "unknown key"),
]


@pytest.mark.parametrize(("old", "new", "message"), BAD)
def test_bad_input_is_one_line_exit_2_nothing_written(tmp_path, old, new, message):
    assert old in CONTRACT
    out = tmp_path / "out"
    res = runner.invoke(
        app, ["run", str(write(tmp_path, CONTRACT.replace(old, new))), "-o", str(out)]
    )
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.stderr.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and message in lines[0], res.stderr
    assert "Traceback" not in res.output
    assert not out.exists()


def test_template_and_examples_validate():
    parse_scenario(__import__("tomllib").loads(template("rotating_field")))
    for path in sorted(ROOT.glob("examples/rf_*.toml")):
        parse_scenario(__import__("tomllib").loads(path.read_text()))


def test_state_validates_gamma_to_1e_9():
    """Γ is accepted when it is a rotation to 1e-9 (then re-orthonormalized), refused beyond."""
    G = np.eye(3)
    G[0, 0] += 4e-10
    st0 = rf.State([0.0, 0.0, 1.0], G)
    assert np.allclose(st0.gamma @ st0.gamma.T, np.eye(3), atol=1e-15)
    G[0, 0] += 2e-9
    with pytest.raises(Exception, match="not a rotation"):
        rf.State([0.0, 0.0, 1.0], G)
