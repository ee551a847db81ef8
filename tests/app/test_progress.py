"""A command that works for long is never silent on a terminal: a progress display names its
stage and how far an integration has got; none with --quiet or when stderr is not a terminal.
"""

from __future__ import annotations

import re

import pytest
from files import EXAMPLES
from typer.testing import CliRunner

from tumble import _progress, cli

SCENARIO = EXAMPLES / "tb_gravity_gradient.toml"


@pytest.fixture
def heard(monkeypatch):
    """Every (stage, fraction) a display set by the command hears."""
    calls: list[tuple[str, float | None]] = []
    real = _progress.set_display

    def spy(display, close=None):
        if display is None:
            return real(None, close)

        def recorded(stage, fraction):
            calls.append((stage, fraction))
            display(stage, fraction)

        return real(recorded, close)

    monkeypatch.setattr(_progress, "set_display", spy)
    monkeypatch.setattr(cli, "PROGRESS_AFTER_S", 0.0)  # shown at once: the run is short
    return calls


def _run(tmp_path, *extra):
    return CliRunner().invoke(cli.app, ["run", str(SCENARIO), "-o", str(tmp_path / "o"), *extra])


def test_a_run_on_a_terminal_shows_its_stages(monkeypatch, tmp_path, heard):
    monkeypatch.setenv("TTY_COMPATIBLE", "1")  # rich treats stderr as a terminal
    result = _run(tmp_path)
    assert result.exit_code == 0, result.output
    stages = [s for s, _ in heard]
    for expected in ("averaged", "full", "writing the outputs", "drawing the figure"):
        assert expected in stages, stages
    for method in ("averaged", "full"):
        fractions = [f for s, f in heard if s == method and f is not None]
        assert fractions, method  # the integration reported where it had got to
        assert fractions == sorted(fractions) and 0.0 <= fractions[0]
        assert fractions[-1] == pytest.approx(1.0)  # it reached the horizon
    # Drawn on the terminal (at least its first frame: how many more depends on the speed).
    assert any(stage in result.stderr for stage in {*stages, "reading the scenario"})


@pytest.mark.parametrize("quiet", [True, False])
def test_no_display_with_quiet_or_off_a_terminal(monkeypatch, tmp_path, heard, quiet):
    if quiet:
        monkeypatch.setenv("TTY_COMPATIBLE", "1")
    else:
        monkeypatch.setenv("TTY_COMPATIBLE", "0")  # a pipe, a log file
    result = _run(tmp_path, *(["--quiet"] if quiet else []))
    assert result.exit_code == 0, result.output
    assert heard == []
    assert not re.search(r"drawing the figure|reading the scenario", result.stderr)
