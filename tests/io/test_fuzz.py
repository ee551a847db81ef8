"""A seeded fuzz corpus of hostile scenarios: every mutation is accepted or refused with one
clean line (a TumbleError of bounded length), never an internal error; every accepted one runs
to finite columns or fails with one line; as sweep points, a bad one fails alone.

Mutations of each model's template: numeric extremes (NaN, ±inf, ±1e308, subnormals, huge
integers) at one or several keys, values of the wrong type (a 100 000-character string, lists,
tables, booleans), deleted keys and misspelt tables; and whole files that are not UTF-8 TOML
(random bytes, UTF-16, deep nesting) through the command line.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import random
import tomllib
import warnings

import numpy as np
import pytest
from files import EXAMPLES, leaves, write
from typer.testing import CliRunner

from tumble.analysis import run
from tumble.analysis.sweep import Keep
from tumble.app.sweep import compute_chunk
from tumble.cli import app
from tumble.errors import TumbleError, TumbleWarning
from tumble.io.scenario import parse_scenario, template
from tumble.io.sweep import parse_sweep
from tumble.models import MODELS

EXTREMES = [math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -5e-324, 0.0, -1.0, 1e20,
            2**63 - 1, -(2**63), 10**30]  # fmt: skip
WRONG_TYPES = ["x" * 100_000, [1.0, 2.0], {"a": 1}, True, "", [], [[1.0]] * 5]
MUTATIONS_PER_MODEL = 200
LONGEST_MESSAGE = 400  # one line: the key, ≤ 80 characters of the value, the allowed range


def _set(d, path, value):
    for p in path[:-1]:
        d = d[p]
    d[path[-1]] = value


def _mutate(base, rng):
    d = copy.deepcopy(base)
    paths = [p for p in leaves(d) if p]
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


NAMES = sorted(n for n in MODELS if MODELS[n].scenario is not None)
FUZZ_STEPS = 200_000  # the runs' step budget: a run that needs more fails in one line


def _one_line(exc: TumbleError, what: str) -> None:
    text = str(exc)
    assert "\n" not in text and len(text) <= LONGEST_MESSAGE, (what, text[:200])


@pytest.mark.parametrize("name", NAMES)
def test_mutated_scenarios_are_accepted_or_refused_in_one_line_and_run(name, tmp_path):
    base = tomllib.loads(template(name))
    rng = random.Random(f"fuzz-{name}")
    accepted = []
    for i in range(MUTATIONS_PER_MODEL):
        data = _mutate(base, rng)
        try:
            accepted.append((i, parse_scenario(data, str(tmp_path / f"{name}.toml")).request))
        except TumbleError as exc:
            _one_line(exc, f"mutation {i}")
        except Exception as exc:  # an internal error: the defect this corpus looks for
            pytest.fail(f"mutation {i} of {name}: {type(exc).__name__}: {str(exc)[:200]}")
    assert len(accepted) < MUTATIONS_PER_MODEL // 2  # the corpus does reach the checks
    # Every accepted mutation runs: finite columns that move, or one line (~25 s in all).
    ran = 0
    for i, req in accepted:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", TumbleWarning)
                result = run(dataclasses.replace(req, max_steps=FUZZ_STEPS))
        except TumbleError as exc:
            _one_line(exc, f"run of mutation {i}")
            continue
        except Exception as exc:
            pytest.fail(f"run of mutation {i} of {name}: {type(exc).__name__}: {exc}"[:300])
        ran += 1
        for method, ds in result.datasets.items():
            for v in ds.data_vars:
                assert np.all(np.isfinite(ds[v].values)), (i, method, v)
        full = result.datasets.get("full")
        if full is not None:  # a frozen run: no column of the full motion moves
            assert any(np.ptp(full[v].values) > 0.0 for v in full.data_vars), i
    assert ran > len(accepted) // 2, (ran, len(accepted))


def _numeric_keys(d):
    """The sweep keys (``parameters.b[2][2]``) of every number of a template but ``[run]``."""
    for path in leaves(d):
        value = d
        for p in path:
            value = value[p]
        if isinstance(value, int | float) and not isinstance(value, bool) and path[0] != "run":
            names = ".".join(str(p) for p in path if isinstance(p, str))
            yield names + "".join(f"[{p}]" for p in path if isinstance(p, int))


@pytest.mark.parametrize("name", NAMES)
def test_a_chunk_of_hostile_sweep_points_fails_only_the_bad_ones(name, tmp_path):
    # 200 seeded points (one key set to an extreme, or to a mild change) in chunks of 50, as a
    # worker runs them: every point gets a record, a bad one fails alone with one reason line,
    # and every good one ends with finite values.
    base = tomllib.loads(template(name))
    base["run"]["max_steps"] = FUZZ_STEPS
    base["run"]["samples"] = 101  # the points, not the length of their runs, are under test
    keys = list(_numeric_keys(base))
    for end in ("t_end", "tau_end", "t_end_s", "t_end_days"):
        if end in base["run"]:
            base["run"][end] /= 4.0
    rng = random.Random(f"sweep-fuzz-{name}")
    mild = [0.5, 0.9, 1.1, 2.0]
    points = []
    for _ in range(MUTATIONS_PER_MODEL):
        key = rng.choice(keys)
        value = rng.choice(EXTREMES) if rng.random() < 0.6 else rng.choice(mild)
        points.append({key: value})
    keep = Keep(final=True, differences=False, limits=False, stability=False, verify=False)
    records = []
    for start in range(0, len(points), 50):
        chunk = points[start : start + 50]
        records += compute_chunk(base, str(tmp_path / f"{name}.toml"), chunk, keep)
    assert len(records) == len(points)
    ok = 0
    for point, rec in zip(points, records, strict=True):
        assert rec["status"] in (0, 1), (point, rec)
        if rec["status"] == 1:
            reason = rec["reason"]
            assert reason and "\n" not in reason and len(reason) <= LONGEST_MESSAGE, reason
            assert not reason.startswith("internal error"), (point, reason)
            continue
        ok += 1
        finals = [x for by_var in rec["final"].values() for x in by_var.values()]
        assert np.all(np.isfinite(finals)), (point, rec["final"])
    assert 0 < ok < len(points), ok  # the corpus has both kinds


SWEEPS = sorted((EXAMPLES / "sweeps").glob("*.toml"))


@pytest.mark.parametrize("path", SWEEPS, ids=[p.stem for p in SWEEPS])
def test_mutated_sweep_files_are_accepted_or_refused_in_one_line(path):
    # The same mutations of the example sweep files: grids of 1e20 points, counts of ±inf,
    # NaN bounds, 100 000-character names; never an internal error.
    base = tomllib.loads(path.read_text())
    rng = random.Random(f"fuzz-{path.name}")
    for i in range(MUTATIONS_PER_MODEL):
        data = _mutate(base, rng)
        try:
            parse_sweep(data, path)
        except TumbleError as exc:
            _one_line(exc, f"mutation {i}")
        except Exception as exc:
            pytest.fail(f"mutation {i} of {path.name}: {type(exc).__name__}: {str(exc)[:200]}")


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
