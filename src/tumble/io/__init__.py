"""Files and formats: scenario files in; CSV, JSON and output sets out.

Names load their module on first use, so that ``tumble.io.fileset`` comes without xarray or
the models.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tumble._lazy import lazy_exports

# Public name → the module that defines it.
_EXPORTS: dict[str, str] = {
    "Scenario": "tumble.io.scenario",
    "load_scenario": "tumble.io.scenario",
    "parse_scenario": "tumble.io.scenario",
    "template": "tumble.io.toml",
    "atomic_write": "tumble.io.fileset",
    "csv_text": "tumble.io.output",
    "render_outputs": "tumble.io.output",
    "summary": "tumble.io.output",
    "verify_outputs": "tumble.io.output",
    "output_set": "tumble.io.fileset",
}

__all__ = [
    "Scenario",
    "atomic_write",
    "csv_text",
    "load_scenario",
    "output_set",
    "parse_scenario",
    "render_outputs",
    "summary",
    "template",
    "verify_outputs",
]

if TYPE_CHECKING:
    from tumble.io.fileset import atomic_write, output_set
    from tumble.io.output import csv_text, render_outputs, summary, verify_outputs
    from tumble.io.scenario import Scenario, load_scenario, parse_scenario
    from tumble.io.toml import template


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
