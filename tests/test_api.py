"""The public API at ``tumble``: every documented name resolves, loads lazily, and the verbs
do what the CLI does."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from files import EXAMPLES
from typer.testing import CliRunner

import tumble
from tumble.cli import app


@pytest.mark.parametrize("name", sorted(set(tumble.__all__) - {"__version__"}))
def test_every_public_name_resolves(name):
    assert getattr(tumble, name) is not None
    assert name in dir(tumble)


def test_all_lists_exactly_the_lazy_names():
    assert set(tumble.__all__) == set(tumble._EXPORTS)  # __version__ too: it loads on use


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'simulate_all'"):
        _ = tumble.simulate_all


def test_import_tumble_loads_no_numerics():
    """``import tumble`` alone imports neither numba nor scipy: the names load on first use."""
    code = "import sys, tumble; print(sorted(m for m in ('numba', 'scipy') if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


@pytest.mark.filterwarnings("ignore::tumble.errors.TumbleWarning")  # the example warns by design
def test_run_in_memory_and_to_files_agree(tmp_path):
    """tumble.run without a directory writes nothing; with one, the files of `tumble run`."""
    scenario = tumble.load_scenario(EXAMPLES / "quadratic_only.toml")
    in_memory = tumble.run(scenario)
    written = tumble.run(EXAMPLES / "quadratic_only.toml", tmp_path / "out")
    assert sorted(in_memory.trajectories) == sorted(written.trajectories)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert set(summary["methods"]) == set(written.trajectories)
    for method, traj in in_memory.trajectories.items():
        other = written.trajectories[method]
        # The same computation twice: identical results.
        for name, column in traj.columns.items():
            assert (column == other.columns[name]).all(), (method, name)


def test_version_option():
    res = CliRunner().invoke(app, ["--version"])
    assert res.exit_code == 0
    assert res.output.strip() == f"tumble {tumble.__version__}"


def test_dir_of_the_package_shows_its_public_names_only():
    # Not what the package imports for its own use (TYPE_CHECKING, annotations, the lazy
    # loader): its exports, its loaded public submodules and the dunders.
    import tumble

    shown = {n for n in dir(tumble) if not n.startswith("__")}
    assert set(tumble.__all__) - {"__version__"} <= shown
    assert not shown & {"TYPE_CHECKING", "annotations", "lazy_exports", "_lazy", "_EXPORTS"}


def test_a_warning_points_at_the_users_call_not_inside_tumble():
    # Python prints a warning's file and line: the user's own call, never a line of tumble.
    import warnings

    import numpy as np

    from tumble.integrate import simulate
    from tumble.models import torqued_body as tb
    from tumble.torques import CallableTorque

    p = tb.Params(np.array([1.0, 1.6, 2.0]), 0.01, CallableTorque(lambda t, q, w: 0.0 * w))
    st = tb.State(np.array([0.3, 0.9, 0.4]), np.array([1.0, 0.0, 0.0, 0.0]))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        simulate(tb.MODEL, p, st, np.linspace(0.0, 1.0, 3), "averaged")
    ours = [w for w in seen if issubclass(w.category, tumble.TumbleWarning)]
    assert ours and all(w.filename == __file__ for w in ours), [w.filename for w in ours]
