"""`[run] averaging = "numeric"`: each model's averaged method through the general
engine gives the same trajectory and the same files as its closed-form right-hand side."""

from __future__ import annotations

import numpy as np
import pytest
from files import read_csv, write
from typer.testing import CliRunner

from tumble.cli import app

runner = CliRunner()

RM = """
model = "resisting_medium"
[parameters]
eps = 0.02
kappa = 0.5
a = [0.05, 0.0, 0.6]
b = [[0.6, 0.0, 0.0], [0.0, 0.5, 0.0], [0.0, 0.0, 0.2]]
s = [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]]
[initial]
k = 1.0
rho = 0.8
theta = 0.9
[run]
tau_end = 40.0
samples = 5
methods = ["averaged"]
"""

RF = """
model = "rotating_field"
[parameters]
inertia = [1.0, 1.6, 2.2]
beta = 1.0
eps = 0.02
[initial]
L = 1.8
rho = 0.8
sigma = 0.3
k2 = 0.5
regime = "x3"
[run]
tau_end = 20.0
samples = 5
methods = ["averaged"]
"""


@pytest.mark.parametrize(("text", "name"), [(RM, "rm"), (RF, "rf")])
def test_numeric_averaging_reproduces_the_closed_form_run(tmp_path, text, name):
    tables = {}
    for mode in ("closed_form", "numeric"):
        out = tmp_path / f"{name}_{mode}"
        res = runner.invoke(
            app, ["run", str(write(tmp_path, text + f'averaging = "{mode}"\n')), "-o", str(out)]
        )
        assert res.exit_code == 0, res.output
        tables[mode] = read_csv(out / "averaged.csv")
    header, closed = tables["closed_form"]
    assert tables["numeric"][0] == header  # the same columns
    # Right-hand sides equal to ~1e-12 relative, both integrated at rtol 1e-10: the
    # trajectories agree to the integration tolerance (1e-8 leaves a margin over τ = 40).
    assert np.max(np.abs(tables["numeric"][1] - closed)) < 1e-8


def test_bad_averaging_value_is_one_line(tmp_path):
    res = runner.invoke(
        app, ["run", str(write(tmp_path, RM + 'averaging = "fast"\n')), "-o", str(tmp_path / "o")]
    )
    assert res.exit_code == 2
    assert "run.averaging" in res.stderr and len(res.stderr.strip().splitlines()) == 1
