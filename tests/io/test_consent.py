"""No user code before consent: a scenario that names a function of the user's file runs
nothing of that file until the whole scenario (or sweep file) is valid and the command line
has printed ``runs user code from <file>``.

The code-execution scenario: ``payload.py`` writes a marker file when it is imported. Refused
for any reason (a missing function, found from the file's syntax tree; a bad key anywhere; a
body at rest for the averaged method; a bad key of the sweep file around it), the marker is
never written; accepted, the notice comes first.
"""

from __future__ import annotations

import io
import tomllib

import pytest
from rich.console import Console
from typer.testing import CliRunner

from tumble import cli
from tumble.cli import app
from tumble.errors import ScenarioError, TumbleError
from tumble.io.scenario import load_scenario
from tumble.io.sweep import parse_sweep
from tumble.io.user_code import check_defines
from tumble.models import get_model

runner = CliRunner()

PAYLOAD = """import pathlib
pathlib.Path(__file__).with_name("MARKER").write_text("ran")


def torque(t, q, omega, params):
    return [0.0, 0.0, 1.0] + 0.0 * omega
"""

SCENARIO = """model = "torqued_body"
torque = "{reference}"
[parameters]
inertia = [1.0, 1.6, 2.0]
eps = 0.01
[initial]
omega = {omega}
[run]
t_end = 1.0
samples = 3
{run}
"""


def _scenario(folder, reference="payload:torque", omega="[0.3, 0.9, 0.4]", run=""):
    folder.mkdir(exist_ok=True)
    (folder / "payload.py").write_text(PAYLOAD)
    path = folder / "scenario.toml"
    path.write_text(SCENARIO.format(reference=reference, omega=omega, run=run))
    return path


REFUSED = {
    "missing function": ({"reference": "payload:nonexistent_function"}, "has no function"),
    "body at rest": ({"omega": "[0.0, 0.0, 0.0]"}, "needs a rotating body"),
    "tolerance": ({"run": "rtol = 1.0"}, "run.rtol"),
    "steps": ({"run": "max_steps = 0"}, "run.max_steps"),
    "method": ({"run": 'methods = ["closed_form"]'}, "run.methods"),
    "unknown key": ({"run": "sample = 3"}, "unknown key"),
    "no file": ({"reference": "absent:torque"}, "no file absent.py"),
    "NUL byte": ({"reference": "pay\\u0000load:torque"}, "control character"),
}
"""Refusals before the model's keys (the run's tolerance), among them (a missing function,
the methods) and after them (the steps, a body at rest for the averaged method)."""


@pytest.mark.parametrize("loaded", [False, True], ids=["declared", "registered"])
@pytest.mark.parametrize("case", REFUSED)
def test_a_refused_scenario_never_runs_the_users_file(tmp_path, case, loaded):
    changes, words = REFUSED[case]
    if loaded:  # the model's numerics already loaded: its checks come from the model itself
        get_model("torqued_body")
    path = _scenario(tmp_path, **changes)
    res = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2 and words in res.stderr, res.stderr
    assert "runs user code" not in res.stderr
    assert not (tmp_path / "MARKER").exists()


def test_a_bad_torque_table_after_a_user_term_never_runs_the_file(tmp_path):
    path = _scenario(tmp_path)
    text = path.read_text().replace(
        'torque = "payload:torque"',
        'torque = [{kind = "user", function = "payload:torque"}, {kind = "solar"}]',
    )
    path.write_text(text)
    res = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2 and "torque[1].kind" in res.stderr, res.stderr
    assert not (tmp_path / "MARKER").exists()


class _Watched(io.StringIO):
    """A terminal that notes, for each line written, whether the marker existed then."""

    def __init__(self, marker):
        super().__init__()
        self.marker, self.lines = marker, []

    def write(self, text):
        self.lines.append((text, self.marker.exists()))
        return super().write(text)


def test_an_accepted_scenario_prints_the_notice_before_the_file_runs(tmp_path, monkeypatch):
    path = _scenario(tmp_path)
    terminal = _Watched(tmp_path / "MARKER")
    monkeypatch.setattr(cli, "err", Console(file=terminal, width=80))
    sc = cli._load(path, None)  # what run and verify do before their work
    notice = f"runs user code from {tmp_path / 'payload.py'}"
    assert terminal.getvalue() == notice + "\n"
    assert [ran for text, ran in terminal.lines if "runs user code" in text] == [False]
    assert (tmp_path / "MARKER").exists()  # loaded, and called once at the initial state
    assert sc.user_code == (str(tmp_path / "payload.py"),)


def test_a_folder_with_brackets_is_named_as_written(tmp_path, monkeypatch):
    path = _scenario(tmp_path / "[red]runs[bold]")  # tags rich would read
    buffer = io.StringIO()
    monkeypatch.setattr(cli, "err", Console(file=buffer, width=80))
    cli._load(path, None)
    assert buffer.getvalue() == f"runs user code from {path.parent / 'payload.py'}\n"


def test_the_library_asks_for_consent_once_the_scenario_is_valid(tmp_path):
    path = _scenario(tmp_path)
    asked = []
    load_scenario(path, consent=lambda files: asked.append((files, (tmp_path / "MARKER").exists())))
    assert asked == [((str(tmp_path / "payload.py"),), False)]
    refused = _scenario(tmp_path / "b", run="rtol = 1.0")
    with pytest.raises(TumbleError):
        load_scenario(refused, consent=lambda files: asked.append(files))
    assert len(asked) == 1 and not (tmp_path / "b" / "MARKER").exists()


SWEEP = """base = "scenario.toml"
[[axis]]
key = "parameters.eps"
values = [0.01, 0.02]
[plot]
method = "{method}"
"""


def test_a_refused_sweep_never_runs_its_bases_file(tmp_path):
    _scenario(tmp_path)
    sweep = tmp_path / "sweep.toml"
    # The base is valid; the sweep file's plot.method, checked after it, is not.
    sweep.write_text(SWEEP.format(method="closed_form"))
    res = runner.invoke(app, ["sweep", str(sweep), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2 and "plot.method" in res.stderr, res.stderr
    assert not (tmp_path / "MARKER").exists()
    sweep.write_text(SWEEP.format(method="full"))
    asked = []
    parse_sweep(tomllib.loads(sweep.read_text()), sweep, consent=asked.append)
    assert asked == [(str(tmp_path / "payload.py"),)] and (tmp_path / "MARKER").exists()


BINDINGS = {
    "def": "def f(t, q, omega, params):\n    return omega\n",
    "assignment": "f = g = lambda t, q, omega, params: omega\n",
    "unpacking": "f, g = (print, print)\n",
    "import": "from math import hypot as f\n",
    "dotted import": "import os.path as f\n",
    "star import": "from math import *\n",
    "conditional": "try:\n    import numba\nexcept ImportError:\n    pass\nelse:\n"
    "    @numba.njit\n    def f(t, q, omega, params):\n        return omega\n",
    "if": "if True:\n    def f(t, q, omega, params):\n        return omega\n",
}


@pytest.mark.parametrize("case", BINDINGS)
def test_a_function_is_found_in_the_syntax_tree(tmp_path, case):
    path = tmp_path / "user.py"
    path.write_text("raise SystemExit('never run')\n" + BINDINGS[case])
    check_defines(path, "f", "torque")  # found without running the file


NOT_FOUND = {
    "inside a function": ("def outer():\n    def f():\n        pass\n", "has no function f"),
    "a method": ("class C:\n    def f(self):\n        pass\n", "has no function f"),
    "another name": ("def g():\n    pass\n", "has no function f"),
    "not Python": ("def f(:\n", "is not valid Python at line 2"),
    "a NUL byte": ("def f():\n    pass\n\0", "is not valid Python"),
}


@pytest.mark.parametrize("case", NOT_FOUND)
def test_a_missing_function_is_refused_without_running_the_file(tmp_path, case):
    source, words = NOT_FOUND[case]
    path = tmp_path / "user.py"
    path.write_text("raise SystemExit('never run')\n" + source)
    with pytest.raises(ScenarioError, match=words):
        check_defines(path, "f", "torque")
