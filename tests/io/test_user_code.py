"""User functions a scenario names: loaded from a file beside it, one module per file, only
after the scenario is valid, never from an installed module unless allowed."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from tumble.errors import ScenarioError, TumbleError
from tumble.io import load_scenario

SCENARIO = """model = "torqued_body"
torque = "{reference}"
[parameters]
inertia = [1.0, 1.6, 2.0]
eps = {eps}
[initial]
omega = [0.3, 0.9, 0.4]
[run]
t_end = 1.0
samples = 3
"""

TORQUE = """import pathlib
pathlib.Path(__file__).with_suffix(".loaded").write_text("yes")


def constant(t, q, omega, params):
    return [{value}, 0.0, 0.0] + 0.0 * omega
"""


def _folder(root, name, value, reference="user_torques:constant", eps="0.01"):
    folder = root / name
    folder.mkdir()
    (folder / "user_torques.py").write_text(TORQUE.format(value=value))
    path = folder / "scenario.toml"
    path.write_text(SCENARIO.format(reference=reference, eps=eps))
    return path


def _moment(scenario):
    torque = scenario.request.params.torque
    return float(torque(0.0, np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3))[0])


def test_same_named_files_in_two_folders_give_their_own_functions(tmp_path):
    a = load_scenario(_folder(tmp_path, "a", 1.0))
    b = load_scenario(_folder(tmp_path, "b", 2.0))
    # Each file's own constant (the torque before its factor ε): no module shared through
    # sys.modules.
    assert _moment(a) == 1.0 and _moment(b) == 2.0
    assert a.user_code == (str((tmp_path / "a" / "user_torques.py").resolve()),)


def test_an_edited_file_is_loaded_anew(tmp_path):
    path = _folder(tmp_path, "a", 1.0)
    assert _moment(load_scenario(path)) == 1.0
    (path.parent / "user_torques.py").write_text(TORQUE.format(value=3.0))
    assert _moment(load_scenario(path)) == 3.0


def test_nothing_is_loaded_for_a_refused_scenario(tmp_path):
    path = _folder(tmp_path, "a", 1.0, eps="-1.0")
    with pytest.raises(TumbleError, match="eps"):
        load_scenario(path)
    assert not (path.parent / "user_torques.loaded").exists()
    load_scenario(_folder(tmp_path, "b", 1.0))
    assert (tmp_path / "b" / "user_torques.loaded").exists()  # the marker works


def test_an_installed_module_runs_only_when_allowed(tmp_path):
    path = _folder(tmp_path, "a", 1.0, reference="builtins:print")
    with pytest.raises(ScenarioError, match="only with --allow-module builtins"):
        load_scenario(path)
    # Allowed, it is imported and called at the initial state: print returns None, refused.
    with pytest.raises(ScenarioError, match="must return the 3 body components"):
        load_scenario(path, allow_modules=["builtins"])


def test_a_path_relative_to_the_scenario_and_pickling(tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "torques.py").write_text(TORQUE.format(value=5.0))
    path = tmp_path / "scenario.toml"
    path.write_text(SCENARIO.format(reference="lib/torques.py:constant", eps="0.1"))
    sc = load_scenario(path)
    assert _moment(sc) == 5.0
    # A Dask worker receives the function as its file and name, and loads the file itself.
    torque = pickle.loads(pickle.dumps(sc.request.params.torque))
    assert float(torque(0.0, np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3))[0]) == 5.0
