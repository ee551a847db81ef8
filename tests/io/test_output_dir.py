"""The output directory is checked and held before a run computes anything."""

from __future__ import annotations

import fcntl
import time

from files import EXAMPLES
from typer.testing import CliRunner

from tumble.cli import app

SCENARIO = str(EXAMPLES / "a3_positive.toml")


def _run(out):
    start = time.perf_counter()
    res = CliRunner().invoke(app, ["run", SCENARIO, "-o", str(out)])
    return res, time.perf_counter() - start


def test_an_output_path_that_is_a_file_fails_before_the_run(tmp_path):
    target = tmp_path / "results"
    target.write_text("keep me")
    res, _ = _run(target)
    assert res.exit_code == 2
    assert "exists and is not a directory" in res.output, res.output
    assert target.read_text() == "keep me"


def test_a_second_run_into_a_held_directory_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    with open(out / ".tumble.lock", "a+") as lock:  # another run holding the directory
        fcntl.flock(lock.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        res, _ = _run(out)
    assert res.exit_code == 2
    assert "another tumble run is writing there" in res.output, res.output
    assert sorted(p.name for p in out.iterdir()) == [".tumble.lock"]  # nothing written


def test_temporaries_of_a_killed_run_are_removed_by_the_next(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".full.csv.x1y2.tmp").write_text("half a file")
    res, _ = _run(out)
    assert res.exit_code == 0, res.output
    assert not list(out.glob(".*.tmp"))
    assert (out / "summary.json").exists()
