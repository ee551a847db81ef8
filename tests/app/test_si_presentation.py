"""A scenario given in SI is shown in SI: its figure and its printed table have the time in
seconds (days beyond two days) and each physical column in its SI unit, while its files keep
the normalised columns with the SI ones beside them."""

from __future__ import annotations

import numpy as np
import pytest
from files import EXAMPLES
from typer.testing import CliRunner

from tumble.analysis import run as run_request
from tumble.app.runner import in_si
from tumble.cli import app
from tumble.io import load_scenario

# These scenarios enter regions the models warn about (resonances, co-rotation); the
# warnings are the runs' business, not these tests'.
pytestmark = pytest.mark.filterwarnings("ignore::tumble.errors.TumbleWarning")


def _run(name: str):
    sc = load_scenario(EXAMPLES / f"{name}.toml")
    return run_request(sc.request)


def test_the_figure_data_of_a_physical_run_are_in_si():
    result = _run("rf_physical")
    scaling = result.request.scaling
    si = in_si(result)
    full, full_si = result.datasets["full"], si.datasets["full"]
    # Time τ = ω t: the last sample is the scenario's t_end_s = 120 s.
    assert full_si["tau"].attrs["units"] == "s"
    assert full_si["tau"].values[-1] == pytest.approx(120.0, rel=1e-12)
    # L in kg·m²/s = I_ref ω L̃; angles and k² unchanged.
    assert full_si["L"].attrs["units"] == "kg m²/s"
    assert np.allclose(full_si["L"].values, scaling.I_ref * scaling.omega * full["L"].values)
    assert np.array_equal(full_si["rho"].values, full["rho"].values)
    # The warnings' times move with the axis.
    for mark, mark_si in zip(result.issues, si.issues, strict=True):
        assert mark_si["tau"] == pytest.approx(mark["tau"] / scaling.omega, rel=1e-12)
    # A normalised scenario is left as it is.
    plain = _run("rf_transient_x1")
    assert in_si(plain) is plain


def test_a_run_beyond_two_days_is_shown_in_days(tmp_path):
    text = (EXAMPLES / "tb_gravity_gradient_leo.toml").read_text()
    path = tmp_path / "leo.toml"
    path.write_text(text.replace("t_end_s = 86400.0 ", "t_end_s = 259200.0 "))
    result = run_request(load_scenario(path).request)
    full_si = in_si(result).datasets["full"]
    assert full_si["tau"].attrs["units"] == "d"
    assert full_si["tau"].values[-1] == pytest.approx(3.0, rel=1e-12)
    assert full_si["T"].attrs["units"] == "J"


def test_the_printed_table_is_in_si(tmp_path):
    out = CliRunner().invoke(app, ["run", str(EXAMPLES / "rf_physical.toml"), "--out",
                                   str(tmp_path / "rf")], env={"COLUMNS": "160"})  # fmt: skip
    assert out.exit_code == 0, out.output
    assert "final T [J]" in out.output and "wall time [s]" in out.output
    assert " J, " in out.output  # the differences, with their units
