"""Small file helpers shared by the tests, and the repository's folders located from this
file (never from the working directory)."""

import csv
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
"""The repository root."""
EXAMPLES = ROOT / "examples"
"""The example scenarios."""


def write(tmp_path, text, name="s.toml"):
    """Write a scenario text into ``tmp_path`` and return its path."""
    path = tmp_path / name
    path.write_text(text)
    return path


def one_line_error(tmp_path, example, old, new):
    """``tumble run`` on the example file with ``old`` replaced by ``new``: it must exit 2 with
    one line, which is returned."""
    from typer.testing import CliRunner

    from tumble.cli import app

    text = example.read_text(encoding="utf-8")
    assert old in text
    path = write(tmp_path, text.replace(old, new))
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    lines = [line for line in result.output.strip().splitlines() if line.strip()]
    assert len(lines) == 1, result.output
    return lines[0]


def read_csv(path):
    """Header and float rows of an output CSV."""
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)


def leaves(d, path=()):
    """The paths (tuples of keys and list indices) of every leaf of a nested scenario table."""
    if isinstance(d, dict):
        for k, v in d.items():
            yield from leaves(v, (*path, k))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from leaves(v, (*path, i))
    else:
        yield path
