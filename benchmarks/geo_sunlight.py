"""The sunlight benchmark alone: a year of a dead box-wing satellite in GEO, spinning about its
array's boom and tumbling, averaged against full, and one evaluation of the averaged equations
(:mod:`tumble.app.bench_sunlight`; also part of ``tumble bench``).

    .venv/bin/python benchmarks/geo_sunlight.py [-o benchmarks/geo_sunlight.json]
    .venv/bin/python benchmarks/geo_sunlight.py --from benchmarks/geo_sunlight.json

Prints the table of the sunlight theory page as Markdown; about 5 minutes on one core. The exit
status is 1 if a target is missed.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

from tumble.app.bench_sunlight import markdown, sunlight_study
from tumble.app.bench_verdicts import TARGETS
from tumble.io.output import atomic_write


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/geo_sunlight.json"))
    ap.add_argument("--from", dest="source", type=Path, help="print the table of a JSON file")
    args = ap.parse_args()
    if args.source is not None:
        result = json.loads(args.source.read_text(encoding="utf-8"))
    else:
        result = sunlight_study(3, lambda msg: print(msg, file=sys.stderr, flush=True))
        result["machine"] = {"cpu": platform.processor() or platform.machine(),
                             "python": platform.python_version()}  # fmt: skip
        atomic_write(args.output, (json.dumps(result, indent=1) + "\n").encode())
    runs = {k: v for k, v in result.items() if k != "machine"}
    print(markdown(runs))
    met = True
    for sun in runs.values():
        chosen = sun["averaged"].get(f"{sun['rtol']:g}") if sun["rtol"] else None
        met = met and chosen is not None
        met = met and sun["speedup"] >= TARGETS["sunlight_year_speedup"]
        met = met and sun["eval_us"] <= TARGETS["sunlight_eval_us"]
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
