"""Nonlinear-moment scenario contract: keys, output files and columns, bad input."""

from __future__ import annotations

import csv
import itertools
import json
import math

import numpy as np
import pytest
from files import read_csv, write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.errors import ParameterError
from tumble.io import parse_scenario, template
from tumble.models import nonlinear_moment as nm
from tumble.models.base import attitude_columns

ATTITUDE = [c.name for c in attitude_columns("t")]  # every full run's last columns

runner = CliRunner()

UNPERTURBED = """
model = "nonlinear_moment"
[parameters]
mu = 0.8
a = -1.0
b = -0.3
[initial]
theta = 1.0
theta_dot = 0.3
psi = 0.2
phi = -0.1
R = 0.4
G = 0.6
[run]
t_end = 30.0
samples = 61
"""

PERTURBED = """
model = "nonlinear_moment"
[parameters]
mu = 0.8
a = -1.0
b = -0.3
[perturbation]
eps = 0.02
d = 0.5
nu = 0.2
pressure = "exp"
[initial]
theta_deg = 60.0
theta_dot = 0.3
R = 0.4
G = 0.6
[run]
t_end = 40.0
samples = 81
methods = ["full", "averaged"]
averaged_init = "corrected"
"""


def _rows(path):
    with open(path) as fh:
        return list(csv.reader(fh))


def test_unperturbed_run_writes_the_contract_outputs(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, UNPERTURBED)), "-o", str(out)])
    assert res.exit_code == 0, res.output
    for method in ("full", "closed_form"):
        header, data = read_csv(out / f"{method}.csv")
        # A full run adds its attitude and body rate (every model's full runs do).
        attitude = ATTITUDE if method == "full" else []
        assert header == ["t", "theta", "psi", "phi", "theta_dot", *attitude]
        assert np.array_equal(data[:, 0], np.linspace(0.0, 30.0, 61))
        # ψ, φ continuous from their initial values (theory §14).
        assert data[0, 2:4] == pytest.approx([0.2, -0.1], abs=1e-12)
    _, full = read_csv(out / "full.csv")
    _, closed = read_csv(out / "closed_form.csv")
    # The closed form against the run's own integration at rtol 1e-10 over ~5 periods: the
    # integration error (≈ 1e-10 per unit time, accumulated) dominates; 1e-7 rad is generous.
    assert np.max(np.abs(full[:, 1:5] - closed[:, 1:])) < 1e-7
    summary = json.loads((out / "summary.json").read_text())
    for key in ("root_case", "roots", "k2", "E", "theta_min", "theta_max", "period"):
        assert key in summary, key
    assert summary["root_case"] in (1, 2)
    assert set(summary["roots"]) == {"u1", "u2", "u3", "u4"}
    assert summary["theta_min"] <= 1.0 <= summary["theta_max"]
    assert math.isfinite(summary["mean_psidot"]) and math.isfinite(summary["mean_phidot"])
    assert (out / "envelope.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_perturbed_run_writes_the_contract_outputs(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, PERTURBED)), "-o", str(out)])
    assert res.exit_code == 0, res.output
    header, full = read_csv(out / "full.csv")
    assert header == ["t", "theta", "psi", "phi", "R", "G", "a", "b", *ATTITUDE]
    assert full[0, 1] == pytest.approx(math.radians(60.0), abs=1e-12)
    header, avg = read_csv(out / "averaged.csv")
    assert header == ["t", "theta_max", "theta_min", "R", "G", "a", "b"]
    assert np.all(avg[:, 1] >= avg[:, 2])
    # a(t) = a·Q(εt)/Q(0) with Q = e^τ, both methods (the averaged one integrates it at rtol
    # 1e-10).
    t = full[:, 0]
    assert np.allclose(full[:, 6], -np.exp(0.02 * t), rtol=1e-14)
    assert np.allclose(avg[:, 5], -np.exp(0.02 * t), rtol=1e-8)
    rows = _rows(out / "full_extrema.csv")
    assert rows[0] == ["kind", "k", "t", "theta", "R", "G"]
    kinds = [r[0] for r in rows[1:]]
    assert set(kinds) == {"max", "min"}
    for kind in ("max", "min"):
        ks = [int(r[1]) for r in rows[1:] if r[0] == kind]
        assert ks == list(range(1, len(ks) + 1))
    times = np.array([float(r[2]) for r in rows[1:]])
    assert np.all(np.diff(times) > 0.0) and times[0] > 0.0
    # Maxima and minima alternate.
    assert all(a != b for a, b in itertools.pairwise(kinds))
    summary = json.loads((out / "summary.json").read_text())
    assert 0.0 < summary["max_envelope_discrepancy"] < 0.05
    assert set(summary["wall_time_s"]) == {"full", "averaged"}
    assert summary["averaged_init"] == "corrected"
    h, _ = read_csv(out / "averaged_diagnostics.csv")
    assert h == ["t", "k2", "period", "root_case", "E"]
    assert (out / "envelope.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_pressure_table_both_spellings():
    base = PERTURBED.replace('pressure = "exp"', "{}")
    pairs = parse_scenario(_toml(base.format("pressure = [[0.0, 1.0], [0.5, 2.0], [1.0, 2.5]]")))
    table = parse_scenario(
        _toml(base.format("pressure = {tau = [0.0, 0.5, 1.0], Q = [1.0, 2.0, 2.5]}"))
    )
    for sc in (pairs, table):
        p = sc.request.params
        assert p.pressure.kind == "table"
        assert p.ab(25.0)[0] == pytest.approx(-2.0)  # τ = 0.5
        assert p.ab_rate(0.75)[0] == pytest.approx(-1.0)  # slope (2.5 − 2)/0.5


def _toml(text):
    import tomllib

    return tomllib.loads(text)


def test_template_parses():
    sc = parse_scenario(_toml(template("nonlinear_moment")))
    assert sc.request.params.perturbed
    assert sc.request.methods == ("full", "averaged")


def test_default_methods_follow_the_perturbation():
    assert parse_scenario(_toml(UNPERTURBED)).request.methods == ("full", "closed_form")
    text = PERTURBED.replace('methods = ["full", "averaged"]\n', "")
    assert parse_scenario(_toml(text)).request.methods == ("full", "averaged")


BAD = [
    (UNPERTURBED.replace("theta = 1.0", "theta = 3.2"), "initial.theta"),
    (UNPERTURBED.replace("theta = 1.0", "theta = 0.0"), "initial.theta"),
    (UNPERTURBED.replace("mu = 0.8", "mu = 0.0"), "parameters.mu"),
    (UNPERTURBED.replace("mu = 0.8", "mu = 2.5"), "parameters.mu"),
    (PERTURBED.replace("eps = 0.02", "eps = 0.0"), "perturbation.eps"),
    (PERTURBED.replace("eps = 0.02", "eps = -0.1"), "perturbation.eps"),
    (PERTURBED.replace('["full", "averaged"]', '["full", "closed_form"]'), "closed_form"),
    (UNPERTURBED + 'methods = ["averaged"]\n', "averaged"),
    (PERTURBED.replace('pressure = "exp"', 'pressure = "linear"'), "perturbation.pressure"),
    (
        PERTURBED.replace('pressure = "exp"', "pressure = [[0.0, 1.0], [0.2, 2.0]]"),
        "perturbation.pressure",
    ),
    (
        PERTURBED.replace('pressure = "exp"', "pressure = [[0.0, 1.0], [1.0, -2.0]]"),
        "perturbation.pressure",
    ),
    (PERTURBED.replace('averaged_init = "corrected"', 'averaged_init = "x"'), "averaged_init"),
    (UNPERTURBED.replace("[run]", "[run]\ntau_end = 3.0"), "run.tau_end"),
    (UNPERTURBED.replace("G = 0.6", "G = 0.6\nomega = 1.0"), "initial.omega"),
    (UNPERTURBED.replace("t_end = 30.0", "t_end = -1.0"), "run.t_end"),
]


@pytest.mark.parametrize(("text", "field"), BAD)
def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, text, field):
    out = tmp_path / "out"
    res = runner.invoke(app, ["run", str(write(tmp_path, text)), "-o", str(out)])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and field in lines[0], res.stderr
    assert "Traceback" not in res.output
    assert not out.exists()


def test_params_refuse_a_perturbation_without_eps():
    with pytest.raises(ParameterError, match=r"perturbation\.eps"):
        nm.Params(mu=1.0, a=-1.0, b=0.0, d=0.5)


def test_numeric_averaging_reproduces_the_closed_form_run(tmp_path):
    # [run] averaging = "numeric": the engine (damping as a torque, averaged over ψ, φ and the
    # nutation) instead of K, E, Π; same files and columns, same trajectory to the solver's
    # tolerance (the right-hand sides agree to ~1e-12).
    text = PERTURBED.replace('averaged_init = "corrected"', 'averaged_init = "exact"')
    text = text.replace("samples = 81", "samples = 9").replace("t_end = 40.0", "t_end = 10.0")
    text = text.replace('methods = ["full", "averaged"]', 'methods = ["averaged"]')
    outs = {}
    for mode in ("closed_form", "numeric"):
        out = tmp_path / mode
        res = runner.invoke(
            app, ["run", str(write(tmp_path, text + f'averaging = "{mode}"\n')), "-o", str(out)]
        )
        assert res.exit_code == 0, res.output
        outs[mode] = read_csv(out / "averaged.csv")
    assert outs["numeric"][0] == outs["closed_form"][0]
    assert np.max(np.abs(outs["numeric"][1] - outs["closed_form"][1])) < 1e-8
