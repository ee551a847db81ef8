"""The crossings benchmark alone: the examples whose slow motion crosses a separatrix or a
resonance, at ε = 1e-3 and 1e-4, the default averaged method against the full equations over
the whole run (:mod:`tumble.app.bench_crossings`; also part of ``tumble bench``).

    .venv/bin/python benchmarks/crossings.py [-o benchmarks/crossings.json]
    .venv/bin/python benchmarks/crossings.py --from benchmarks/crossings.json [--capture]

Also runs the capture ensembles (three of 1000 full runs of a body driven across the
separatrix, and the averaged runs of each). Prints the table of the performance page as
Markdown (``--capture``: the capture table); about 5 minutes on 2 cores, most of it the
averaged runs of the ensemble whose torque reads the attitude. The exit status is 1 if a
target is missed.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

from tumble.app.bench_crossings import (
    CAPTURE_AGREEMENT,
    ERROR_IN_EPS,
    SPEEDUP,
    capture_markdown,
    capture_study,
    crossing_study,
    markdown,
)
from tumble.io.output import atomic_write


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", type=Path, default=Path("benchmarks/crossings.json"))
    ap.add_argument("--from", dest="source", type=Path, help="print the table of a JSON file")
    ap.add_argument("--capture", action="store_true", help="print the capture table instead")
    args = ap.parse_args()
    if args.source is not None:
        result = json.loads(args.source.read_text(encoding="utf-8"))
    else:
        log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
        result = crossing_study(3, log)
        result["capture"] = capture_study(log)
        result["machine"] = {"cpu": platform.processor() or platform.machine(),
                             "python": platform.python_version()}  # fmt: skip
        atomic_write(args.output, (json.dumps(result, indent=1) + "\n").encode())
    runs = {k: v for k, v in result.items() if k not in ("machine", "capture")}
    if args.capture:
        print(capture_markdown(result["capture"]))
        return 0
    print(markdown(runs))
    met = all(
        r["error_in_eps"] <= ERROR_IN_EPS and (r["eps"] > 1e-4 or r["speedup"] >= SPEEDUP)
        for by_eps in runs.values()
        for r in by_eps.values()
    )
    met = met and all(max(e["difference"], e["averaged_difference"]) <= CAPTURE_AGREEMENT
                      for e in result["capture"].values())  # fmt: skip
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
