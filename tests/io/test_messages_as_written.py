"""What the command line prints is the message as written: rich reads no markup in an error,
a warning, a path or a failure reason, so bracketed words (a unit ``[km]``, a table
``[conductor]``, an index ``torque[0]``, a range ``[1e-100, 1e100]``) reach the terminal.

The corpus: every leaf key of every model's template given a few bad values, deleted, or
misspelt, each file refused by ``tumble run``; the orbiting body's messages that name a table
or a unit; sweep files refused by ``tumble sweep``. The line printed must be the library's
message itself (after ``error:``), character for character.
"""

from __future__ import annotations

import copy
import io
import json
import tomllib

import pytest
import typer
from rich.console import Console
from typer.testing import CliRunner

from tumble import cli
from tumble.cli import _shortened, app
from tumble.errors import TumbleError
from tumble.io.scenario import parse_scenario, template
from tumble.io.sweep import parse_sweep
from tumble.models import names

runner = CliRunner()

BAD_VALUES = [-100, -1e300, "oops"]
"""Out of range (an orbit's altitude), beyond the largest magnitude (its message gives the
range in brackets), the wrong type."""


def _toml(value):
    """``value`` as a TOML value (tables and lists inline): the test needs no TOML writer."""
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    return repr(value)


def _file(data):
    return "".join(f"{json.dumps(k)} = {_toml(v)}\n" for k, v in data.items())


def _leaves(d, path=()):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from _leaves(v, (*path, k))
        else:
            yield (*path, k)


def _mutations(base):
    """Each leaf key with each bad value, deleted, and misspelt."""
    for path in _leaves(base):
        if path == ("model",):
            continue
        for value in BAD_VALUES:
            data = copy.deepcopy(base)
            _at(data, path)[path[-1]] = value
            yield data
        data = copy.deepcopy(base)
        table = _at(data, path)
        table[path[-1] + "x"] = table.pop(path[-1])
        yield data
        data = copy.deepcopy(base)
        del _at(data, path)[path[-1]]
        yield data


def _at(data, path):
    for key in path[:-1]:
        data = data[key]
    return data


def _refusal(data, source):
    """The library's error for ``data``, or None if it is accepted."""
    try:
        parse_scenario(copy.deepcopy(data), str(source))
    except TumbleError as exc:
        return exc
    return None


def _printed(tmp_path, data):
    path = tmp_path / "s.toml"
    path.write_text(_file(data))
    res = runner.invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    return res.exit_code, res.stderr


def _orbiting_body_messages():
    """The orbiting body's own bracketed messages: a tensor beside a [conductor], an orbit's
    altitude [km] below 0, no initial rate (omega [rad/s] or another)."""
    base = tomllib.loads(template("orbiting_body"))
    tensor = copy.deepcopy(base)
    tensor["body"]["magnetic_tensor"] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    altitude = copy.deepcopy(base)
    altitude["orbit"]["altitude"] = -100.0
    rate = copy.deepcopy(base)
    del rate["initial"]["omega_deg_s"]
    return [(tensor, "[conductor]"), (altitude, "[km]"), (rate, "[rad/s]")]


@pytest.mark.parametrize("case", range(3), ids=["conductor", "km", "rad_s"])
def test_the_orbiting_body_messages_keep_their_brackets(tmp_path, case):
    data, word = _orbiting_body_messages()[case]
    message = str(_refusal(data, tmp_path / "s.toml"))
    assert word in message
    code, stderr = _printed(tmp_path, data)
    assert code == 2
    assert stderr == f"error: {_shortened(message)}\n"


def _printed_by_the_cli(exc, monkeypatch):
    """What the command line's error handler prints for ``exc`` (as every command does)."""
    buffer = io.StringIO()
    monkeypatch.setattr(cli, "err", Console(file=buffer, width=80))

    def fail():
        raise exc

    with pytest.raises(typer.Exit):
        cli._guarded(fail)
    return buffer.getvalue()


END_TO_END_EVERY = 10
"""Every tenth bracketed refusal also goes through ``tumble run`` itself (about 25 ms each;
the handler alone takes well under a millisecond)."""


def test_every_refusal_of_every_models_keys_is_printed_as_written(tmp_path, monkeypatch):
    refused, bracketed = 0, []
    for name in names(scenario=True):
        base = tomllib.loads(template(name))
        for data in _mutations(base):
            exc = _refusal(data, tmp_path / "s.toml")
            if exc is None:  # accepted: nothing to print (the fuzz corpus runs these)
                continue
            refused += 1
            message = str(exc)
            assert _printed_by_the_cli(exc, monkeypatch) == f"error: {_shortened(message)}\n"
            if "[" in message:
                bracketed.append((data, message))
    # The corpus is about brackets: about half of the refusals name a unit, a range, an index
    # or a table in them (355 refusals, 154 bracketed when written).
    assert refused > 300 and len(bracketed) > 100, (refused, len(bracketed))
    monkeypatch.undo()
    for data, message in bracketed[::END_TO_END_EVERY]:
        code, stderr = _printed(tmp_path, data)
        assert code == 2 and stderr == f"error: {_shortened(message)}\n"


SWEEPS = {
    "two spacings": '[[axis]]\nkey = "orbit.raan_deg"\nvalues = [1.0]\nlinspace = [0.0, 1.0, 3]\n',
    "one bound": (
        "[monte_carlo]\nsamples = 2\nseed = 1\n[[monte_carlo.draw]]\n"
        'key = "orbit.raan_deg"\nuniform = [1.0]\n'
    ),
    "unknown key": '[[axis]]\nkeyx = "orbit.raan_deg"\nvalues = [1.0]\n',
}
"""Sweep files refused on their own keys (an axis or a draw named by its index in brackets)."""


@pytest.mark.parametrize("case", SWEEPS)
def test_sweep_refusals_are_printed_as_written(tmp_path, case):
    (tmp_path / "s.toml").write_text(template("orbiting_body"))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('base = "s.toml"\n' + SWEEPS[case])
    with pytest.raises(TumbleError) as refused:
        parse_sweep(tomllib.loads(sweep.read_text()), sweep)
    message = str(refused.value)
    assert "[0]" in message
    res = runner.invoke(app, ["sweep", str(sweep), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2
    assert res.stderr == f"error: {_shortened(message)}\n"


def test_a_refused_base_of_a_sweep_keeps_its_unit(tmp_path):
    base = tomllib.loads(template("orbiting_body"))
    base["orbit"]["altitude"] = -100.0
    (tmp_path / "s.toml").write_text(_file(base))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('base = "s.toml"\n[[axis]]\nkey = "orbit.raan_deg"\nvalues = [1.0]\n')
    res = runner.invoke(app, ["sweep", str(sweep), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2
    assert "orbit.altitude [km] = -100" in res.stderr, res.stderr


def test_a_warning_and_a_sweeps_failure_reasons_are_printed_as_written(monkeypatch):
    import types
    import warnings

    import xarray as xr

    from tumble.errors import TumbleWarning

    buffer = io.StringIO()
    monkeypatch.setattr(cli, "err", Console(file=buffer, width=80))
    monkeypatch.setattr(cli, "out", Console(file=buffer, width=80))
    text = "averaging near a resonance [1·ν1 = 2·Ω_f] from t [s] = 210"
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        warnings.warn(text, TumbleWarning, stacklevel=1)
    cli._print_warnings(caught)
    assert buffer.getvalue() == f"warning: {text}\n"
    reason = "invalid input: body.magnetic_tensor and [conductor]: give one of them"
    ds = xr.Dataset(
        {"status": (("point",), [1, 0]), "reason": (("point",), [reason, ""])},
        attrs={"points": 2},
    )
    result = types.SimpleNamespace(
        dataset=ds, computed=2, resumed=0, failed=1, wall_time=1.0, workers=1, throughput=2.0,
        files=["out/[bold]/sweep.nc"],
    )  # fmt: skip
    buffer.truncate(0)
    buffer.seek(0)
    cli._report_sweep(result)
    lines = buffer.getvalue().splitlines()
    assert lines[1:] == [f"failed ×1: {reason}", "written: out/[bold]/sweep.nc"]
