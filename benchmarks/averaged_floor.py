"""The compiled floor of the averaged runs on the benchmark's short cases: their compiled
integration and columns against the time their speed-up target allows
(:mod:`tumble.app.bench_floor`).

    .venv/bin/python benchmarks/averaged_floor.py [-o benchmarks/averaged_floor.json]
    .venv/bin/python benchmarks/averaged_floor.py --from benchmarks/averaged_floor.json

Prints the table of the performance page as Markdown; about a minute on 2 cores. The exit
status is 1 if the floor (evaluations and columns) of a case exceeds its budget: its target is
out of reach of the method, whatever the Python around it.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

from tumble.app.bench_floor import floor_study, markdown, over_budget
from tumble.io.output import atomic_write


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/averaged_floor.json"))
    ap.add_argument("--from", dest="source", type=Path, help="print the table of a JSON file")
    args = ap.parse_args()
    if args.source is not None:
        result = json.loads(args.source.read_text(encoding="utf-8"))
    else:
        log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
        result = floor_study(5, log)
        result["machine"] = {"cpu": platform.processor() or platform.machine(),
                             "python": platform.python_version()}  # fmt: skip
        atomic_write(args.output, (json.dumps(result, indent=1) + "\n").encode())
    runs = {k: v for k, v in result.items() if k != "machine"}
    print(markdown(runs))
    return 1 if over_budget(runs) else 0


if __name__ == "__main__":
    sys.exit(main())
