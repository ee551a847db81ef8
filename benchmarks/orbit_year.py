"""The orbiting body's benchmark alone: a year of a LEO object averaged against full, and 1000
averaged years against full 30-day runs, and a rocket body's averaged year
(:mod:`tumble.app.bench_orbit`; also part of ``tumble bench``).

    .venv/bin/python benchmarks/orbit_year.py [-o benchmarks/orbit_year.json]
    .venv/bin/python benchmarks/orbit_year.py --from benchmarks/orbit_year.json

Prints the table of docs/orbit-year-table.md (included by the performance page) as Markdown;
about 4 minutes on 2 cores. The exit status is 1 if a target is missed.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

from tumble.app.bench import TARGETS
from tumble.app.bench_orbit import markdown, orbiting_study
from tumble.io.output import atomic_write


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/orbit_year.json"))
    ap.add_argument("--from", dest="source", type=Path, help="print the table of a JSON file")
    args = ap.parse_args()
    if args.source is not None:
        result = json.loads(args.source.read_text(encoding="utf-8"))
    else:
        result = orbiting_study(3, lambda msg: print(msg, file=sys.stderr, flush=True))
        result["machine"] = {"cpu": platform.processor() or platform.machine(),
                             "python": platform.python_version()}  # fmt: skip
        atomic_write(args.output, (json.dumps(result, indent=1) + "\n").encode())
    print(markdown(result))
    mc = result.get("monte_carlo") or {}
    runs = mc.get("in_full_30_day_runs", float("inf"))
    met = result.get("speedup", 0.0) >= TARGETS["orbit_year_speedup"]
    met = met and runs <= TARGETS["orbit_monte_carlo_full_runs"]
    rocket = result.get("rocket_body") or {}
    for key, target in (("integration_s", "rocket_year_integration_s"),
                        ("year_over_one_day", "rocket_year_over_one_day"),
                        ("twin_final_period_difference", "rocket_twin_agreement")):  # fmt: skip
        met = met and rocket.get(key, float("inf")) <= TARGETS[target]
    shell = result.get("shell") or {}
    met = met and shell.get("rate_difference", float("inf")) <= TARGETS["shell_rate_agreement"]
    met = met and shell.get("speedup", 0.0) >= TARGETS["shell_year_speedup"]
    box = result.get("capture") or {}
    for run in ("full", "hybrid"):
        off = abs(box.get(f"{run}_rate_over_n", float("inf")) - 1.0)
        met = met and off <= TARGETS["capture_rate_agreement"]
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
