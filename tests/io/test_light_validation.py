"""A scenario is validated before the numerics load: an input error is reported by a process
that has imported neither numba nor scipy (nor xarray, dask, matplotlib), whatever the model
and whichever table holds the error — the structural half of the start-up target, whose time
``tumble bench`` measures."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

from tumble.catalogue import CATALOGUE
from tumble.io.toml import template

HEAVY = ("numba", "scipy", "xarray", "dask", "matplotlib", "llvmlite")

_PROBE = r"""
import json, sys
from tumble.io.scenario import parse_scenario
from tumble.io.toml import read_file
from tumble.errors import TumbleError
try:
    parse_scenario(read_file(sys.argv[1]), sys.argv[1])
    message = None
except TumbleError as exc:
    message = str(exc)
heavy = sorted({m.split(".")[0] for m in sys.modules} & set(sys.argv[2].split(",")))
print(json.dumps({"message": message, "heavy": heavy}))
"""


def _probe(path) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, str(path), ",".join(HEAVY)],
        capture_output=True, text=True, check=True, timeout=120,
    )  # fmt: skip
    return json.loads(done.stdout.strip().splitlines()[-1])


# (model, the edit of its template, the start of the expected one-line error)
CASES = [
    ("resisting_medium", (r"(?m)^kappa = \S+", "kappa = -5.0"), "parameters.kappa = -5"),
    ("resisting_medium", (r"(?m)^theta = \S+", "theta = 4.0"), "initial.theta = 4"),
    ("rotating_field", (r"(?m)^eps = \S+", "eps = -1.0"), "parameters.eps = -1"),
    ("rotating_field", (r"(?m)^k2 = \S+", "k2 = 1.5"), "initial.k2 = 1.5"),
    ("nonlinear_moment", (r"(?m)^mu = \S+", "mu = 3.0"), "parameters.mu = 3"),
    ("nonlinear_moment", (r"(?m)^eps = \S+", "eps = 2.0"), "perturbation.eps = 2"),
    ("torqued_body", (r"(?m)^eps = \S+", "eps = -1.0"), "parameters.eps = -1"),
    ("torqued_body", (r"(?m)^n = \S+", "n = -0.3"), "torque[0].n = -0.3"),
    ("torqued_body", (r"(?m)^methods = .*$", 'methods = ["bogus"]'), "run.methods[0]"),
    ("resisting_medium", (r"(?m)^\[initial\]", "[inital]"), "inital: unknown key"),
    # The orbiting body's inputs import the torqued body's: a package's submodule, which must
    # not load the package's numerics on the way.
    (
        "orbiting_body",
        (r"(?m)^conductivity = \S+", "conductivity = -1.0"),
        "conductor.conductivity [S/m] = -1",
    ),
]


@pytest.mark.parametrize(("name", "edit", "expected"), CASES)
def test_an_input_error_loads_no_numerics(tmp_path, name, edit, expected):
    text, n = re.subn(edit[0], edit[1], template(name), count=1)
    assert n == 1, "the template changed: update the edit"
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    found = _probe(path)
    assert found["message"] is not None and found["message"].startswith(expected), found
    assert found["heavy"] == [], found


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_a_valid_template_validates_and_then_loads_its_model(tmp_path, name):
    """The light path is only the front: a valid scenario still becomes a full request."""
    path = tmp_path / f"{name}.toml"
    path.write_text(template(name))
    assert _probe(path)["message"] is None


SWEEPS = [
    # (the sweep file's own lines after ``base``, the start of the expected error)
    ("[[axis]]\nkey = \"parameters.eps\"\nvalues = [0.01, 0.02]\nbogus = 1\n", "axis[0].bogus"),
    ("[[axis]]\nkey = \"parameters.eps\"\nlinspace = [0.1, 0.2, 0.5]\n", "axis"),
    ("[monte_carlo]\nsamples = 4\nseed = 1\n[[monte_carlo.draw]]\nkey = \"parameters.eps\"\n"
     "uniform = [0.2, 0.1]\n", "draw"),
]  # fmt: skip


@pytest.mark.parametrize(("lines", "expected"), SWEEPS)
def test_a_sweep_input_error_loads_no_numerics(tmp_path, lines, expected):
    """A sweep file is checked, its keys against the base scenario's data, before Dask,
    xarray or the models' numerics load."""
    (tmp_path / "base.toml").write_text(template("resisting_medium"))
    path = tmp_path / "sweep.toml"
    path.write_text('base = "base.toml"\n' + lines)
    probe = _PROBE.replace(
        "parse_scenario(read_file(sys.argv[1]), sys.argv[1])",
        "__import__('tumble.io.sweep', fromlist=['x']).load_sweep(sys.argv[1])",
    )
    done = subprocess.run(
        [sys.executable, "-c", probe, str(path), ",".join(HEAVY)],
        capture_output=True, text=True, check=True, timeout=120,
    )  # fmt: skip
    found = json.loads(done.stdout.strip().splitlines()[-1])
    message = found["message"] or ""
    assert expected in message.split(": ", 1)[-1][: len(expected) + 40], found
    assert found["heavy"] == [], found
