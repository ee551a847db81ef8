"""Small file helpers shared by the scenario tests."""

import csv

import numpy as np


def write(tmp_path, text, name="s.toml"):
    """Write a scenario text into ``tmp_path`` and return its path."""
    path = tmp_path / name
    path.write_text(text)
    return path


def read_csv(path):
    """Header and float rows of an output CSV."""
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return rows[0], np.array(rows[1:], dtype=float)
