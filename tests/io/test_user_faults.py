"""A user's torque that fails (raises, divides by zero, reads out of bounds, returns NaN, the
wrong shape or the wrong types, takes the wrong arguments), compiled with numba or in Python,
early or in the middle of a run: tumble answers in one line naming the function, exit 2, never
an internal error, a flood of ignored exceptions, a crash or a wrong result with exit 0."""

from __future__ import annotations

import numpy as np
import pytest

from tumble.cli import app

FAULTS = """
import numba
import numpy as np


def late(t):
    return t > 5.0


@numba.njit
def ok(t, q, omega, params):
    return np.array([1e-3 * params[0], 0.0, 0.0])


@numba.njit
def nb_raise_early(t, q, omega, params):
    raise ValueError("refused at once")


@numba.njit
def nb_raise_late(t, q, omega, params):
    if t > 5.0:
        raise ValueError("refused later")
    return np.array([1e-3, 0.0, 0.0])


@numba.njit
def nb_divide_early(t, q, omega, params):
    return np.array([1.0 / (t - t), 0.0, 0.0])


@numba.njit
def nb_divide_late(t, q, omega, params):
    d = 0.0 if t > 5.0 else 1.0
    return np.array([1e-3 / d, 0.0, 0.0])


@numba.njit
def nb_nan_late(t, q, omega, params):
    return np.array([np.nan if t > 5.0 else 1e-3, 0.0, 0.0])


@numba.njit
def nb_inf_early(t, q, omega, params):
    return np.array([np.inf, 0.0, 0.0])


@numba.njit
def nb_out_of_bounds_early(t, q, omega, params):
    return np.array([params[7], 0.0, 0.0])


@numba.njit
def nb_out_of_bounds_late(t, q, omega, params):
    i = 1000000 if t > 5.0 else 0
    return np.array([1e-3 * params[i], 0.0, 0.0])


@numba.njit
def nb_wrong_shape(t, q, omega, params):
    return np.array([1e-3, 0.0])


@numba.njit
def nb_scalar(t, q, omega, params):
    return 1e-3


@numba.njit
def nb_wrong_signature(t, q, omega):
    return np.array([1e-3, 0.0, 0.0])


@numba.njit
def nb_untyped(t, q, omega, params):
    return np.array([len({"a": object()}), 0.0, 0.0])


def py_raise_early(t, q, omega, params):
    raise RuntimeError("refused at once")


def py_raise_late(t, q, omega, params):
    if np.any(np.asarray(t) > 5.0):
        raise RuntimeError("refused later")
    return 1e-3 * np.ones_like(omega)


def py_divide_late(t, q, omega, params):
    scale = 1e-3 / (0.0 if float(np.max(t)) > 5.0 else 1.0)  # a Python float: ZeroDivisionError
    return scale * np.ones_like(omega)


def py_nan_late(t, q, omega, params):
    return np.where(np.asarray(t)[..., None] > 5.0, np.nan, 1e-3) * np.ones_like(omega)


def py_wrong_shape(t, q, omega, params):
    return np.zeros(2)


def py_wrong_signature(t, q, omega):
    return np.zeros(3)


def py_none(t, q, omega, params):
    return None


def py_text(t, q, omega, params):
    return "north"
"""

SCENARIO = """model = "torqued_body"
torque = "faults:{name}"
[torque_params]
a = 1.0
[parameters]
inertia = [1.0, 1.6, 2.0]
eps = 0.01
[initial]
omega = [0.3, 0.9, 0.4]
[run]
t_end = 10.0
samples = 5
methods = ["full"]
"""

CORPUS = [
    name
    for name in (
        "nb_raise_early nb_raise_late nb_divide_early nb_divide_late nb_nan_late nb_inf_early "
        "nb_out_of_bounds_early nb_out_of_bounds_late nb_wrong_shape nb_scalar "
        "nb_wrong_signature nb_untyped py_raise_early py_raise_late py_divide_late "
        "py_nan_late py_wrong_shape py_wrong_signature py_none py_text"
    ).split()
]


def _run(tmp_path, capsys, name, method="full"):
    (tmp_path / "faults.py").write_text(FAULTS)
    scenario = tmp_path / f"{name}.toml"
    scenario.write_text(SCENARIO.format(name=name).replace('["full"]', f'["{method}"]'))
    with pytest.raises(SystemExit) as stop:
        app(["run", str(scenario), "--out", str(tmp_path / f"out_{name}")])
    captured = capsys.readouterr()
    return stop.value.code, captured.err


def test_a_sound_torque_runs(tmp_path, capsys):
    code, err = _run(tmp_path, capsys, "ok")
    assert code == 0, err


@pytest.mark.parametrize("name", CORPUS)
def test_a_faulty_torque_is_one_line_exit_2(tmp_path, capsys, name):
    code, err = _run(tmp_path, capsys, name)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == 2, err
    assert "internal error" not in err and "Exception ignored" not in err, err
    # The notice that user code runs, then the one line of the error (rich may fold it).
    assert len(lines) <= 5, err
    assert f"faults:{name}" in err.replace("\n", " "), err


@pytest.mark.parametrize("name", ["nb_divide_late", "nb_out_of_bounds_late", "py_raise_late"])
def test_a_late_fault_names_the_time_and_the_state(tmp_path, capsys, name):
    code, err = _run(tmp_path, capsys, name)
    text = " ".join(err.split())
    assert code == 2 and "at t = 5." in text and "omega = " in text, err


@pytest.mark.parametrize("name", ["nb_raise_late", "py_raise_late", "nb_nan_late"])
def test_the_averaged_run_stops_on_a_fault_too(tmp_path, capsys, name):
    code, err = _run(tmp_path, capsys, name, method="averaged")
    assert code == 2 and "internal error" not in err and f"faults:{name}" in err, err


def test_what_an_averaged_run_computed_before_a_fault_is_written(tmp_path, capsys):
    import json

    # The compiled averaged run meets the fault (t > 5) in its first chunk of steps: the
    # samples that chunk passed before it (every 1 time unit) are kept, none after it.
    (tmp_path / "faults.py").write_text(FAULTS)
    scenario = tmp_path / "avg.toml"
    text = SCENARIO.format(name="nb_raise_late").replace('["full"]', '["averaged"]')
    scenario.write_text(text.replace("t_end = 10.0", "t_end = 1000.0").replace("= 5\n", "= 1001\n"))
    with pytest.raises(SystemExit) as stop:
        app(["run", str(scenario), "--out", str(tmp_path / "out")])
    ended = json.loads((tmp_path / "out" / "summary.json").read_text())["ended_early"]
    rows = (tmp_path / "out" / "averaged.csv").read_text().strip().splitlines()
    assert stop.value.code == 2 and ended["method"] == "averaged"
    assert 1.0 <= ended["t"] <= 5.0 and len(rows) == 1 + int(ended["t"]) + 1, rows


def test_the_reproduced_exception_is_the_users(tmp_path, capsys):
    _, err = _run(tmp_path, capsys, "nb_divide_late")
    assert "ZeroDivisionError" in err
    _, err = _run(tmp_path, capsys, "nb_raise_late")
    assert "ValueError: refused later" in " ".join(err.split())
    _, err = _run(tmp_path, capsys, "nb_out_of_bounds_late")
    assert "IndexError" in err


def test_the_torque_evaluated_from_python_reports_its_fault(tmp_path):
    """UserTorque called from Python (a notebook): the same one error."""
    import importlib.util

    from tumble.errors import UserCodeError
    from tumble.torques import UserTorque

    (tmp_path / "faults.py").write_text(FAULTS)
    spec = importlib.util.spec_from_file_location("faults_for_python", tmp_path / "faults.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    torque = UserTorque(module.nb_divide_late, {"a": 1.0}, name="nb_divide_late")
    torque.compiled_terms()
    q = np.array([1.0, 0.0, 0.0, 0.0])
    assert np.isfinite(torque(1.0, q, np.zeros(3))).all()
    with pytest.raises(UserCodeError, match="ZeroDivisionError"):
        torque(6.0, q, np.zeros(3))


def test_what_ran_before_a_fault_is_written_and_marked(tmp_path, capsys):
    import json

    code, err = _run(tmp_path, capsys, "nb_raise_late")
    out = tmp_path / "out_nb_raise_late"
    summary = json.loads((out / "summary.json").read_text())
    ended = summary["ended_early"]
    # The fault comes at t > 5: the samples at t = 0, 2.5 and 5 were passed or not depending
    # on the last step taken before it; every one kept lies before the fault.
    assert code == 2 and ended["method"] == "full" and "faults:nb_raise_late" in ended["reason"]
    rows = (out / "full.csv").read_text().strip().splitlines()
    assert 2 <= len(rows) <= 4 and ended["t"] <= 5.0  # the header and the samples before t = 5
    assert "ending early" in " ".join(err.split())


def test_what_ran_before_a_python_torques_fault_is_written_too(tmp_path, capsys):
    import json

    code, err = _run(tmp_path, capsys, "py_raise_late")
    out = tmp_path / "out_py_raise_late"
    ended = json.loads((out / "summary.json").read_text())["ended_early"]
    rows = (out / "full.csv").read_text().strip().splitlines()
    # scipy's steps before the fault, retaken: the samples at t = 0 and 2.5 (the fault at 5.03)
    assert code == 2 and ended["t"] == 2.5 and len(rows) == 3, err
    assert "faults:py_raise_late raised RuntimeError" in ended["reason"]


def test_a_spent_step_budget_keeps_what_ran(tmp_path, capsys):
    import json

    (tmp_path / "faults.py").write_text(FAULTS)
    scenario = tmp_path / "budget.toml"
    text = SCENARIO.format(name="ok").replace("t_end = 10.0", "t_end = 1000.0")
    scenario.write_text(text + "max_steps = 200\n")
    with pytest.raises(SystemExit) as stop:
        app(["run", str(scenario), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert stop.value.code == 3 and "run.max_steps" in summary["ended_early"]["reason"], err


LOOPS = """
import numba
import numpy as np


@numba.njit
def nb_forever(t, q, omega, params):
    x = 0.0
    while t > 2.0 * params[0] or x < 0.0:  # never ends once t > 2a
        x += 1.0
        if x > 1e300:
            x = 0.0
    return np.array([1e-3, 0.0, 0.0])


def py_forever(t, q, omega, params):
    while float(np.max(t)) > 2.0:
        pass
    return 1e-3 * np.ones_like(omega)
"""


def _loop_scenario(tmp_path, name):
    (tmp_path / "loops.py").write_text(LOOPS)
    scenario = tmp_path / f"{name}.toml"
    text = SCENARIO.format(name=name).replace("faults:", "loops:")
    scenario.write_text(text + "user_code_timeout = 1.0\n")
    return scenario


def test_a_python_torque_that_never_returns_is_stopped(tmp_path, capsys):
    scenario = _loop_scenario(tmp_path, "py_forever")
    with pytest.raises(SystemExit) as stop:
        app(["run", str(scenario), "--out", str(tmp_path / "out")])
    err = " ".join(capsys.readouterr().err.split())
    assert stop.value.code == 2, err
    assert "loops:py_forever did not return within 1 s (run.user_code_timeout)" in err, err


def _cli(*args, **kw):
    import subprocess
    import sys

    return subprocess.Popen([sys.executable, "-m", "tumble.cli", *args], stderr=subprocess.PIPE,
                            stdout=subprocess.DEVNULL, text=True, **kw)  # fmt: skip


def test_a_compiled_torque_that_never_returns_is_stopped(tmp_path):
    # In compiled code no exception reaches the function: its run is stopped from outside the
    # compiled call, which is left behind (a fresh process, which the command line ends).
    import json

    scenario = _loop_scenario(tmp_path, "nb_forever")
    run = _cli("run", str(scenario), "--out", str(tmp_path / "out"))
    # (compiling the function and loading the kernels take a few seconds; then 1 s of guard)
    _, err = run.communicate(timeout=120)
    text = " ".join(err.split())
    assert run.returncode == 2, err
    assert "loops:nb_forever did not return within 1 s" in text and len(err.splitlines()) <= 5
    # What ran before the chunk that never ended is written and marked: the function loops
    # from t = 2, the first sample is at t = 0.
    ended = json.loads((tmp_path / "out" / "summary.json").read_text())["ended_early"]
    rows = (tmp_path / "out" / "full.csv").read_text().strip().splitlines()
    assert ended["method"] == "full" and "did not return" in ended["reason"]
    assert ended["t"] == 0.0 and len(rows) == 2, rows
    assert "ending early" in text


def test_a_compiled_torque_that_never_returns_late_keeps_the_run_until_then(tmp_path):
    # The same function looping from t = 2000 (a = 1000), reached after thousands of steps:
    # the chunks before the one it hangs in are kept, the samples up to there.
    import json

    scenario = _loop_scenario(tmp_path, "nb_forever")
    text = scenario.read_text().replace("a = 1.0", "a = 1000.0")
    text = text.replace("samples = 5", "samples = 41").replace("t_end = 10.0", "t_end = 4000.0")
    scenario.write_text(text)
    run = _cli("run", str(scenario), "--out", str(tmp_path / "out"))
    _, err = run.communicate(timeout=120)
    assert run.returncode == 2, err
    ended = json.loads((tmp_path / "out" / "summary.json").read_text())["ended_early"]
    rows = (tmp_path / "out" / "full.csv").read_text().strip().splitlines()
    # Samples every 100: those of every chunk before the last (at least half of the steps
    # to t = 2000, as the chunks double), none past it.
    assert 1000.0 <= ended["t"] <= 2000.0 and len(rows) == 1 + round(ended["t"] / 100) + 1, rows


def test_ctrl_c_stops_a_compiled_torque_that_never_returns(tmp_path):
    import signal
    import time

    scenario = _loop_scenario(tmp_path, "nb_forever")
    scenario.write_text(scenario.read_text().replace("user_code_timeout = 1.0", ""))
    run = _cli("run", str(scenario), "--out", str(tmp_path / "out"))
    for _ in range(600):  # until the run has started ("runs user code from …")
        line = run.stderr.readline()
        if "runs user code" in line or not line:
            break
    time.sleep(3.0)  # in the loop by then (the guard's timeout is 60 s)
    run.send_signal(signal.SIGINT)
    start = time.monotonic()
    _, err = run.communicate(timeout=30)
    # The deferred Ctrl-C waits a second for the compiled call, then the guard ends it.
    assert run.returncode == 130 and "interrupted" in err, err
    assert time.monotonic() - start < 10.0
