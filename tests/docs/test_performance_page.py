"""The performance page's tables are the committed benchmark run's: docs/performance-tables.md
is ``benchmarks/performance.py --from benchmarks/performance.json``, so a new run's JSON and
its tables cannot drift apart."""

from __future__ import annotations

import importlib
import importlib.util
import json
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_the_tables_are_the_committed_runs():
    found = importlib.util.spec_from_file_location(
        "performance", ROOT / "benchmarks" / "performance.py"
    )
    assert found is not None and found.loader is not None
    module = importlib.util.module_from_spec(found)
    found.loader.exec_module(module)
    run = json.loads((ROOT / "benchmarks" / "performance.json").read_text(encoding="utf-8"))
    page = (ROOT / "docs" / "performance-tables.md").read_text(encoding="utf-8")
    assert page.rstrip("\n") == module.markdown(run).rstrip("\n"), (
        "docs/performance-tables.md is stale: python benchmarks/performance.py --from "
        "benchmarks/performance.json > docs/performance-tables.md"
    )


def _runs(run: dict) -> dict:
    """A study's runs: its JSON without the machine and the capture ensembles."""
    return {k: v for k, v in run.items() if k not in ("machine", "capture")}


TABLES = [
    # (page, JSON, the study's Markdown of the JSON, the command that writes the page)
    ("orbit-year-table.md", "orbit_year.json", "bench_orbit.markdown", lambda r: r,
     "benchmarks/orbit_year.py"),
    ("sunlight-year-table.md", "geo_sunlight.json", "bench_sunlight.markdown", _runs,
     "benchmarks/geo_sunlight.py"),
    ("crossings-table.md", "crossings.json", "bench_crossings.markdown", _runs,
     "benchmarks/crossings.py"),
    ("capture-table.md", "crossings.json", "bench_crossings.capture_markdown",
     lambda r: r["capture"], "benchmarks/crossings.py --capture"),
    ("averaged-floor-table.md", "averaged_floor.json", "bench_floor.markdown", _runs,
     "benchmarks/averaged_floor.py"),
]  # fmt: skip


@pytest.mark.parametrize(("page", "source", "writer", "part", "command"), TABLES)
def test_a_studys_table_is_the_committed_runs(page, source, writer, part, command):
    module, name = writer.split(".")
    markdown = getattr(importlib.import_module(f"tumble.app.{module}"), name)
    run = json.loads((ROOT / "benchmarks" / source).read_text(encoding="utf-8"))
    text = (ROOT / "docs" / page).read_text(encoding="utf-8")
    assert text.rstrip("\n") == markdown(part(run)).rstrip("\n"), (
        f"docs/{page} is stale: python {command.split()[0]} --from benchmarks/{source}"
        f"{command.removeprefix(command.split()[0])} > docs/{page}"
    )
