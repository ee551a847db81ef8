"""A seeded fuzz corpus of hostile scenarios: every mutation is accepted or refused with one
clean line (a TumbleError of bounded length), never an internal error.

Mutations of each model's template: numeric extremes (NaN, ±inf, ±1e308, subnormals, huge
integers) at one or several keys, values of the wrong type (a 100 000-character string, lists,
tables, booleans), deleted keys and misspelt tables; and whole files that are not UTF-8 TOML
(random bytes, UTF-16, deep nesting) through the command line.
"""

from __future__ import annotations

import copy
import math
import random
import tomllib

import pytest
from files import write
from typer.testing import CliRunner

from tumble.cli import app
from tumble.errors import TumbleError
from tumble.io.scenario import parse_scenario, template
from tumble.models import MODELS

EXTREMES = [math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -5e-324, 0.0, -1.0, 1e20,
            2**63 - 1, -(2**63), 10**30]  # fmt: skip
WRONG_TYPES = ["x" * 100_000, [1.0, 2.0], {"a": 1}, True, "", [], [[1.0]] * 5]
MUTATIONS_PER_MODEL = 200
LONGEST_MESSAGE = 400  # one line: the key, ≤ 80 characters of the value, the allowed range


def _leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _leaves(v, (*path, k))
    elif isinstance(d, list):
        for i, v in enumerate(d):
            yield from _leaves(v, (*path, i))
    else:
        yield path


def _set(d, path, value):
    for p in path[:-1]:
        d = d[p]
    d[path[-1]] = value


def _mutate(base, rng):
    d = copy.deepcopy(base)
    paths = [p for p in _leaves(d) if p]
    p = rng.choice(paths)
    kind = rng.randrange(5)
    if kind == 0:
        _set(d, p, rng.choice(EXTREMES))
    elif kind == 1:
        _set(d, p, rng.choice(WRONG_TYPES))
    elif kind == 2:
        parent = d
        for q in p[:-1]:
            parent = parent[q]
        if isinstance(parent, dict):
            del parent[p[-1]]
    elif kind == 3 and len(str(p[0])) > 2:
        key = str(p[0])
        i = rng.randrange(len(key) - 1)
        d[key[:i] + key[i + 1] + key[i] + key[i + 2 :]] = d.pop(p[0])
    else:
        value = rng.choice(EXTREMES)
        for q in rng.sample(paths, min(3, len(paths))):
            _set(d, q, value)
    return d


@pytest.mark.parametrize("name", sorted(n for n in MODELS if MODELS[n].scenario is not None))
def test_mutated_scenarios_are_accepted_or_refused_in_one_line(name, tmp_path):
    base = tomllib.loads(template(name))
    rng = random.Random(f"fuzz-{name}")
    refused = 0
    for i in range(MUTATIONS_PER_MODEL):
        data = _mutate(base, rng)
        try:
            parse_scenario(data, str(tmp_path / f"{name}.toml"))
        except TumbleError as exc:
            refused += 1
            text = str(exc)
            assert "\n" not in text and len(text) <= LONGEST_MESSAGE, (i, text[:200])
        except Exception as exc:  # an internal error: the defect this corpus looks for
            pytest.fail(f"mutation {i} of {name}: {type(exc).__name__}: {str(exc)[:200]}")
    assert refused > MUTATIONS_PER_MODEL // 2  # the corpus does reach the checks


BAD_FILES = {
    "random_bytes": bytes(random.Random(3).randrange(256) for _ in range(400)),
    "utf16": 'model = "resisting_medium"\n'.encode("utf-16"),
    "deep_nesting": ("a = " + "[" * 3000 + "]" * 3000 + "\n").encode(),
    "truncated": b'model = "resisting_medium"\n[parameters\n',
    "nul": b"model = \x00\n",
}


@pytest.mark.parametrize("case", list(BAD_FILES))
def test_files_that_are_not_toml_are_one_line_exit_2(tmp_path, case):
    path = tmp_path / "s.toml"
    path.write_bytes(BAD_FILES[case])
    res = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error:"), res.output


def test_a_misspelt_table_is_named_with_a_suggestion(tmp_path):
    text = template("resisting_medium").replace("[initial]", "[inital]")
    res = CliRunner().invoke(app, ["run", str(write(tmp_path, text)), "-o", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "inital: unknown key (did you mean initial?" in res.output, res.output
