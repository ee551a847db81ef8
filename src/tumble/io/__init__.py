"""Files and formats: scenario files in, CSV and JSON out."""

from tumble.io.output import (
    atomic_write,
    csv_text,
    output_dir,
    render_outputs,
    summary,
    verify_outputs,
    write_outputs,
)
from tumble.io.scenario import Scenario, load_scenario, parse_scenario, template

__all__ = [
    "Scenario",
    "atomic_write",
    "csv_text",
    "load_scenario",
    "output_dir",
    "parse_scenario",
    "render_outputs",
    "summary",
    "template",
    "verify_outputs",
    "write_outputs",
]
