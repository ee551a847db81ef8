"""Every ``tumble`` command the README, the getting-started page and the tutorials give runs as
written, from a directory holding the repository's ``examples/`` (as on a fresh clone, once
``source .venv/bin/activate`` has put ``tumble`` on the PATH), and ends with exit 0.

A command is taken from a shell block, an indented block or an inline code span when it is
complete: a
sub-command and arguments with no placeholder (``tumble run SCENARIO -o DIR`` is a pattern,
not a command) and every scenario it names present in ``examples/``.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [
    ROOT / "README.md",
    ROOT / "docs" / "getting-started.md",
    *sorted((ROOT / "docs" / "tutorials").glob("*.md")),
]
TUMBLE = Path(sys.executable).with_name("tumble")
# Verification of a year of the Envisat-like object: three full runs at ε, ε/2, ε/4 (~2 min);
# the Monte Carlo of 200 objects over a year on Dask (~2 min); four GEO decades on Dask (~40 s);
# the B-dot law's verification
# (11-15 s, the default suite's longest command: verify itself is tested on other scenarios).
SLOW = {
    "tumble verify examples/ob_envisat_like.toml",
    "tumble verify examples/tb_bdot.toml -o out/tb_bdot_verify",
    "tumble sweep examples/sweeps/ob_envisat_monte_carlo.toml -o out/envisat_mc",
    "tumble sweep examples/sweeps/ob_geo_decade_damper.toml -o out/geo_damper",
}
_CODE = re.compile(r"`(tumble [^`\n]+)`|^(?: {4}|\$ )?(tumble [^\n#`]+)", re.M)


def _complete(command: str) -> bool:
    try:
        words = shlex.split(command)
    except ValueError:  # prose that begins with "tumble" (an apostrophe)
        return False
    if len(words) < 2 or not re.fullmatch(r"[a-z-]+|--help", words[1]):
        return False
    if any(re.fullmatch(r"[A-Z][A-Z_-]*", w) for w in words[2:]):  # a placeholder
        return False
    scenarios = [w for w in words[2:] if w.endswith(".toml")]
    return all((ROOT / s).is_file() for s in scenarios) and (
        words[1] in ("--help", "models", "init") or bool(scenarios)
    )


def _commands() -> list[object]:
    found: dict[str, str] = {}
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for m in _CODE.finditer(text):
            command = " ".join((m.group(1) or m.group(2)).split())
            if _complete(command):
                found.setdefault(command, page.relative_to(ROOT).as_posix())
    return [
        pytest.param(c, id=f"{page}: {c}", marks=[pytest.mark.slow] if c in SLOW else [])
        for c, page in sorted(found.items())
    ]


def test_the_pages_give_commands():
    commands = {p.values[0] for p in _commands()}  # type: ignore[attr-defined]
    assert "tumble run examples/a3_positive.toml -o out/a3" in commands  # the README's
    assert len(commands) >= 8


@pytest.mark.parametrize("command", _commands())
def test_a_command_of_the_pages_runs_as_written(command: str, tmp_path: Path) -> None:
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    words = shlex.split(command)
    env = {**os.environ, "MPLBACKEND": "Agg"}
    done = subprocess.run([str(TUMBLE), *words[1:]], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)  # fmt: skip
    assert done.returncode == 0, f"{command}:\n{done.stderr[-2000:]}"
