"""Every Python snippet of the README and the documentation pages runs as written.

A page's snippets run in order as one plain script (later ones use the names of earlier
ones), in a fresh process whose working directory holds the repository's ``examples/``, as
a reader who copies them into a file would run them: ``python page.py``. Pages whose
snippets are studies (tens of seconds) are slow."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
SLOW = {"docs/guide/python.md"}  # the capsule's study and the rotating field: ~40 s
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def _name(page: Path) -> str:
    return page.relative_to(ROOT).as_posix()


def _cases() -> list[object]:
    cases: list[object] = []
    for page in PAGES:
        if not BLOCK.search(page.read_text(encoding="utf-8")):
            continue
        marks = [pytest.mark.slow] if _name(page) in SLOW else []
        cases.append(pytest.param(page, id=_name(page), marks=marks))
    return cases


def test_the_pages_hold_snippets():
    # The parametrisation below is not empty by accident: the README's example is one.
    assert "README.md" in {_name(p) for p in PAGES if BLOCK.search(p.read_text(encoding="utf-8"))}


@pytest.mark.parametrize("page", _cases())
def test_the_snippets_of_a_page_run_as_written(page: Path, tmp_path: Path) -> None:
    script = "\n\n".join(BLOCK.findall(page.read_text(encoding="utf-8")))
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "page.py").write_text(script, encoding="utf-8")
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONWARNINGS": "ignore"}
    done = subprocess.run([sys.executable, "page.py"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)  # fmt: skip
    assert done.returncode == 0, f"{_name(page)}:\n{done.stderr[-3000:]}"
