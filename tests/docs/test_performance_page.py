"""The performance page's tables are the committed benchmark run's: docs/performance-tables.md
is ``benchmarks/performance.py --from benchmarks/performance.json``, so a new run's JSON and
its tables cannot drift apart."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

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


def test_the_orbit_table_is_the_committed_runs():
    from tumble.app.bench_orbit import markdown

    run = json.loads((ROOT / "benchmarks" / "orbit_year.json").read_text(encoding="utf-8"))
    page = (ROOT / "docs" / "orbit-year-table.md").read_text(encoding="utf-8")
    assert page.rstrip("\n") == markdown(run).rstrip("\n"), (
        "docs/orbit-year-table.md is stale: python benchmarks/orbit_year.py --from "
        "benchmarks/orbit_year.json > docs/orbit-year-table.md"
    )


def test_the_sunlight_table_is_the_committed_runs():
    from tumble.app.bench_sunlight import markdown

    run = json.loads((ROOT / "benchmarks" / "geo_sunlight.json").read_text(encoding="utf-8"))
    runs = {k: v for k, v in run.items() if k != "machine"}
    page = (ROOT / "docs" / "sunlight-year-table.md").read_text(encoding="utf-8")
    assert page.rstrip("\n") == markdown(runs).rstrip("\n"), (
        "docs/sunlight-year-table.md is stale: python benchmarks/geo_sunlight.py --from "
        "benchmarks/geo_sunlight.json > docs/sunlight-year-table.md"
    )


def test_the_crossings_table_is_the_committed_runs():
    from tumble.app.bench_crossings import markdown

    run = json.loads((ROOT / "benchmarks" / "crossings.json").read_text(encoding="utf-8"))
    runs = {k: v for k, v in run.items() if k not in ("machine", "capture")}
    page = (ROOT / "docs" / "crossings-table.md").read_text(encoding="utf-8")
    assert page.rstrip("\n") == markdown(runs).rstrip("\n"), (
        "docs/crossings-table.md is stale: python benchmarks/crossings.py --from "
        "benchmarks/crossings.json > docs/crossings-table.md"
    )


def test_the_capture_table_is_the_committed_runs():
    from tumble.app.bench_crossings import capture_markdown

    run = json.loads((ROOT / "benchmarks" / "crossings.json").read_text(encoding="utf-8"))
    page = (ROOT / "docs" / "capture-table.md").read_text(encoding="utf-8")
    assert page.rstrip("\n") == capture_markdown(run["capture"]).rstrip("\n"), (
        "docs/capture-table.md is stale: python benchmarks/crossings.py --from "
        "benchmarks/crossings.json --capture > docs/capture-table.md"
    )
