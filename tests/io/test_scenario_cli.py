"""Scenario files, the CLI contract, outputs and bad input."""

import json
import math
import os
import subprocess
import sys
import tomllib

import numpy as np
import pytest
from files import ROOT, read_csv, write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.io import load_scenario, parse_scenario, template
from tumble.models.base import attitude_columns

ATTITUDE = [c.name for c in attitude_columns("t")]  # every full run's last columns

runner = CliRunner()

CONTRACT = """
model = "resisting_medium"
[parameters]
eps = 0.01
kappa = 0.5
a = [0.0, 0.0, 0.3]
b = [[0.2, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, 0.0, 0.1]]
s = [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.05]]
[initial]
k = 1.0
rho = 0.4
sigma = 0.0
psi = 0.0
theta = 1.0
phi = 0.0
[run]
tau_end = 100.0
samples = 101
methods = ["full", "averaged", "closed_form"]
rtol = 1e-10
atol = 1e-12
"""


def test_run_writes_the_contract_outputs(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, CONTRACT)), "-o", str(out)])
    assert res.exit_code == 0, res.output
    header, full = read_csv(out / "full.csv")
    assert header == ["tau", "k", "theta", "rho", "sigma", "psi", "phi", *ATTITUDE]
    for method in ("averaged", "closed_form"):
        h, data = read_csv(out / f"{method}.csv")
        assert h == ["tau", "k", "theta", "rho", "sigma"]
        assert data.shape == (101, 5)
    # Values at exactly the requested times, the first row the initial state.
    assert np.array_equal(full[:, 0], np.linspace(0.0, 100.0, 101))
    assert full[0, 1:7] == pytest.approx([1.0, 1.0, 0.4, 0.0, 0.0, 0.0], abs=1e-12)
    summary = json.loads((out / "summary.json").read_text())
    for key in ("inputs", "methods", "max_differences", "predicted_limits", "warnings"):
        assert key in summary
    assert set(summary["methods"]) == {"full", "averaged", "closed_form"}
    assert summary["methods"]["full"]["wall_time_s"] > 0
    assert summary["max_differences"]["closed_form_vs_averaged"]["k"] < 1e-8
    assert summary["predicted_limits"]["theta"] == 0.0
    assert (out / "comparison.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [f for f in os.listdir(out) if f.endswith(".tmp")]
    assert (out / "full.csv").stat().st_mode & 0o044  # readable by others, as with open()


def test_explicit_times_are_honoured(tmp_path):
    text = CONTRACT.replace("tau_end = 100.0\nsamples = 101", "tau = [0.5, 3.25, 77.0]")
    sc = parse_scenario(tomllib.loads(text))
    assert sc.request.tau.tolist() == [0.5, 3.25, 77.0]


def test_degrees_keys(tmp_path):
    text = CONTRACT.replace("theta = 1.0", "theta_deg = 45.0")
    assert parse_scenario(tomllib.loads(text)).request.initial.theta == pytest.approx(math.pi / 4)


def test_physical_scenario_equals_its_normalized_twin(tmp_path):
    """A physical-units scenario and its normalized twin give the same run."""
    I1, I3 = 2.0e-3, 3.0e-3
    omega = [3.0, -4.0, 60.0]
    A = [1e-5, 0.0, 4e-4]
    B = [[2e-6, 0.0, 0.0], [0.0, 2e-6, 0.0], [0.0, 1e-7, 3e-6]]
    S = [[5e-8, 0.0, 0.0], [0.0, 5e-8, 0.0], [0.0, 0.0, 2e-8]]
    phys = f"""
model = "resisting_medium"
[physical]
I1 = {I1}
I3 = {I3}
A = {A}
B = {B}
S = {S}
[initial]
omega = {omega}
rho = 0.7
sigma = 0.2
psi = 0.1
[run]
t_end_s = 30.0
samples = 61
"""
    sc = parse_scenario(tomllib.loads(phys))
    Kb = np.array([I1 * omega[0], I1 * omega[1], I3 * omega[2]])
    K0 = float(np.linalg.norm(Kb))
    T0 = I1 / K0
    M0 = float(max(max(abs(x) for x in A), np.max(np.abs(B)) / T0, np.max(np.abs(S)) / T0**2))
    eps = float(M0 * I1 / K0**2)
    twin = f"""
model = "resisting_medium"
[parameters]
eps = {eps!r}
kappa = {I3 / I1 - 1!r}
a = {(np.array(A) / M0).tolist()}
b = {(np.array(B) / (M0 * T0)).tolist()}
s = {(np.array(S) / (M0 * T0**2)).tolist()}
[initial]
k = 1.0
rho = 0.7
sigma = 0.2
psi = 0.1
theta = {math.atan2(math.hypot(Kb[0], Kb[1]), Kb[2])!r}
phi = {math.atan2(Kb[0], Kb[1])!r}
[run]
tau = {(np.linspace(0.0, 30.0, 61) / T0).tolist()}
"""
    assert sc.request.scaling.K0 == pytest.approx(K0, rel=1e-15)
    assert sc.request.params.eps == pytest.approx(eps, rel=1e-15)
    out_p, out_n = tmp_path / "phys", tmp_path / "norm"
    for text, out in ((phys, out_p), (twin, out_n)):
        res = runner.invoke(
            app, ["run", str(write(tmp_path, text, f"{out.name}.toml")), "-o", str(out)]
        )
        assert res.exit_code == 0, res.output
    for method in ("full", "averaged", "closed_form"):
        hp, dp = read_csv(out_p / f"{method}.csv")
        hn, dn = read_csv(out_n / f"{method}.csv")
        assert hp == hn
        # Same problem up to round-off in the scaling (1e-16 relative): the integrations agree
        # far inside their tolerance.
        assert np.allclose(dp, dn, rtol=1e-9, atol=1e-9)
        h_si, d_si = read_csv(out_p / f"{method}_si.csv")
        assert h_si[:3] == ["t_s", "t_days", "K_Nms"]
        assert np.allclose(d_si[:, 0], np.linspace(0.0, 30.0, 61), rtol=1e-14)
        assert np.allclose(d_si[:, 1], d_si[:, 0] / 86400.0, rtol=1e-15)
        assert np.allclose(d_si[:, 2], K0 * dp[:, 1], rtol=1e-14)


def test_physical_attitude_by_quaternion():
    base = dict(
        model="resisting_medium",
        physical={"I1": 1.0, "I3": 1.5},
        initial={"omega": [0.0, 0.6, 0.8]},
        run={"t_end_s": 1.0},
    )
    base["initial"]["quaternion"] = [1.0, 0.0, 0.0, 0.0]
    sc = parse_scenario(base)
    st = sc.request.initial
    # Identity attitude: K = (0, 0.6, 1.2) in both frames, so ρ = atan(0.6/1.2), σ = π/2.
    assert st.rho == pytest.approx(math.atan2(0.6, 1.2), abs=1e-15)
    assert st.sigma == pytest.approx(math.pi / 2, abs=1e-15)
    assert st.theta == pytest.approx(math.atan2(0.6, 1.2), abs=1e-15)


BAD = [
    ("eps = 0.01", "eps = -0.01", "parameters.eps = -0.01 is outside the allowed range [0, inf)"),
    ("kappa = 0.5", "kappa = 1.5", "parameters.kappa = 1.5 is outside the allowed range (-1, 1]"),
    ("eps = 0.01\n", "", "parameters.eps: required key is missing"),
    ("eps = 0.01", 'eps = "small"', "parameters.eps = 'small'"),
    ("theta = 1.0", "theta = 4.0", "initial.theta = 4 is outside the allowed range [0, 3.14159]"),
    ("k = 1.0", "k = 0.0", "initial.k = 0 is outside the allowed range (0, inf)"),
    ("phi = 0.0", "phi = 0.0\nomega = 3.0", "initial.omega: unknown key (allowed here: k, rho,"),
    ('model = "resisting_medium"', 'model = "pendulum"', "model = 'pendulum' is not a known model"),
    (
        "tau_end = 100.0\nsamples = 101",
        "tau = [0.0, 2.0, 1.0]",
        "run.tau must be strictly ascending",
    ),
    ("samples = 101", "samples = 1", "run.samples = 1 is outside the allowed range [2, 1e7]"),
    (
        "samples = 101",
        "samples = 9223372036854775807",
        "run.samples = 9223372036854775807 is outside",
    ),
    ("a = [0.0, 0.0, 0.3]", "a = [0.0, 0.3]", "parameters.a = [0.0, 0.3]"),
    (
        "b = [[0.2, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, 0.0, 0.1]]",
        "b = [[0.2, 0.0, 0.0]]",
        "parameters.b",
    ),
    (
        'methods = ["full", "averaged", "closed_form"]',
        'methods = ["full", "exact"]',
        "run.methods[1] = 'exact'",
    ),
    (
        "kappa = 0.5",
        "kappa = 0.0",
        "parameters.kappa = 0 is outside the allowed range for the averaged",
    ),
    ("theta = 1.0", "theta = 1.0\ntheta_deg = 10.0", "give either theta or theta_deg"),
    ("rtol = 1e-10", "rtol = 0.5", "run.rtol = 0.5 is outside the allowed range"),
]


@pytest.mark.parametrize("old,new,message", BAD, ids=[b[2][:40] for b in BAD])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, old, new, message):
    assert old in CONTRACT
    out = tmp_path / "out"
    out.mkdir()
    (out / "full.csv").write_text("previous results\n")
    res = runner.invoke(
        app, ["run", str(write(tmp_path, CONTRACT.replace(old, new, 1))), "-o", str(out)]
    )
    assert res.exit_code == 2
    text = res.stderr.strip()
    assert message in text, text
    assert "\n" not in text and "Traceback" not in text
    assert os.listdir(out) == ["full.csv"]  # nothing written, nothing lost
    assert (out / "full.csv").read_text() == "previous results\n"


def test_unreadable_and_invalid_toml(tmp_path):
    res = runner.invoke(app, ["run", str(tmp_path / "missing.toml"), "-o", str(tmp_path)])
    assert res.exit_code == 2 and "cannot read the scenario" in res.stderr
    res = runner.invoke(app, ["run", str(write(tmp_path, "model = [")), "-o", str(tmp_path)])
    assert res.exit_code == 2 and "not valid TOML" in res.stderr


def test_models_and_init():
    res = runner.invoke(app, ["models"])
    assert res.exit_code == 0 and "resisting_medium" in res.output and "Medvedev" in res.output
    res = runner.invoke(app, ["init", "resisting_medium"])
    assert res.exit_code == 0
    sc = parse_scenario(tomllib.loads(res.output))  # the printed example is a valid scenario
    assert sc.request.methods == ("full", "averaged", "closed_form")
    assert res.output == template("resisting_medium")
    res = runner.invoke(app, ["init", "nope"])
    assert res.exit_code == 2 and "not a known model" in res.stderr


@pytest.mark.parametrize("path", sorted((ROOT / "examples").glob("*.toml")), ids=lambda p: p.name)
def test_examples_are_valid_scenarios(path):
    sc = load_scenario(path)
    assert sc.request.model.name == sc.inputs["model"]


def test_console_script_warns_on_crossing(tmp_path):
    """The installed `tumble` prints the π/2 warning and lists it in summary.json."""
    text = (
        CONTRACT.replace("a = [0.0, 0.0, 0.3]", "a = [0.2, 0.1, 0.3]")
        .replace("theta = 1.0", "theta = 2.0")
        .replace("tau_end = 100.0", "tau_end = 200.0")
    )
    out = tmp_path / "o"
    proc = subprocess.run(
        [sys.executable, "-m", "tumble.cli", "run", str(write(tmp_path, text)), "-o", str(out)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert "crosses ϑ = π/2" in proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert "theta_crossing" in [w["condition"] for w in summary["warnings"]]
