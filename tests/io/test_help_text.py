"""`tumble COMMAND --help` reads as written at any width: each paragraph wrapped by the
terminal (not broken again where the docstring's own lines end), units in brackets kept (rich
would read ``[rad]`` as markup and drop it), and no ``<bool>`` beside a flag."""

from __future__ import annotations

import itertools
import re

import pytest
from typer.testing import CliRunner

from tumble.cli import app

COMMANDS = ["run", "verify", "stability", "bench", "sweep", "reproduce"]


def _help(command: str, width: int) -> list[str]:
    res = CliRunner().invoke(app, [command, "--help"], env={"COLUMNS": str(width)})
    assert res.exit_code == 0, res.output
    return res.output.splitlines()


@pytest.mark.parametrize("command", COMMANDS)
def test_the_description_is_wrapped_by_the_terminal(command):
    lines = _help(command, 80)
    body = [ln.strip() for ln in lines[: next(i for i, ln in enumerate(lines) if "─" in ln)]]
    for line, following in itertools.pairwise(body):
        # A line far shorter than the width followed by more of the same paragraph is a
        # docstring line wrapped again.
        if following and not following.startswith("Usage"):
            assert len(line) > 50 or not line, (line, following)


def test_units_in_brackets_are_printed():
    text = "\n".join(_help("stability", 100))
    assert "[rad]" in text and "[units of the moments]" in text
    assert "[time units]" in "\n".join(_help("bench", 100))


@pytest.mark.parametrize("command", COMMANDS)
def test_no_flag_shows_a_value(command):
    for line in _help(command, 120):
        if "<bool>" in line:
            assert re.search(r"--help\b", line), line  # click's own --help option
