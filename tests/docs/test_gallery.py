"""The gallery and the figures: every file of docs/figures/ is drawn by a command listed in
docs/figures.py, those commands name scenarios, scripts and pages that exist, and
docs/gallery.md is the page generated from that list."""

from __future__ import annotations

import importlib.util
import shlex
import sys
from pathlib import Path

from tumble.cli import app

ROOT = Path(__file__).resolve().parents[2]


def _figures_module():
    found = importlib.util.spec_from_file_location("figures", ROOT / "docs" / "figures.py")
    assert found is not None and found.loader is not None
    module = importlib.util.module_from_spec(found)
    sys.modules["figures"] = module  # its dataclass looks its module up there
    found.loader.exec_module(module)
    return module


def test_the_gallery_page_is_generated_from_the_list():
    figures = _figures_module()
    page = (ROOT / "docs" / "gallery.md").read_text(encoding="utf-8")
    assert page == figures.gallery(), "docs/gallery.md is stale: python docs/figures.py --gallery"


def test_every_figure_file_has_its_command():
    figures = _figures_module()
    on_disk = {p.name for p in (ROOT / "docs" / "figures").iterdir()}
    assert on_disk == {f.name for f in figures.FIGURES}


def test_the_commands_name_what_exists():
    figures = _figures_module()
    commands = {c.name for c in app.registered_commands}
    for f in figures.FIGURES:
        assert (ROOT / "docs" / f"{f.page}.md").is_file(), f.page
        for command in f.commands:
            words = shlex.split(command)
            if words[0].endswith("/tumble"):
                assert words[1] in commands, command
            # every path the command reads (examples, benchmark scripts and results) is there
            for word in words[1:]:
                if word.startswith(("examples/", "benchmarks/")):
                    assert (ROOT / word).is_file(), command
