"""Peak memory of a long full run: the compiled integrator keeps its samples, not its steps.

    .venv/bin/python benchmarks/memory.py [--t-end 1e7] [--samples 1000] [--json]

A torqued body under the gravity gradient (~2.7 steps per unit of time at rtol 1e-10) is
run by ``tumble.integrate.simulate`` from the Python API, each case in a fresh interpreter:

* ``imports``: the interpreter after importing the model and the integrator, and one short
  run (the compiled code loaded) — the floor every run starts from;
* ``streamed``: the full run to ``--t-end`` with ``--samples`` samples (the default);
* ``dense``: the run that keeps its dense output (``simulate(..., dense=True)``) to a horizon
  100 times shorter, for comparison: its memory grows with the steps.

Peak RSS is ``ru_maxrss`` of the child process. Target: a 1e7-unit run with 1000 samples
peaks at ≤ 200 MB. The exit status is 1 if it does not.

Measured on 2 shared cores (t_end 1e7, 1000 samples, ≈ 2.7e7 steps): imports 184 MB; the
streamed run peaks at 196 MB (40 s); the dense run to 1e5 peaks at 409 MB, ≈ 830 bytes per
step with its buffers, so 1e7 kept dense would need ≈ 22 GB. The floor is the imports
(numpy, scipy, numba and the compiled code): the run itself adds ≈ 12 MB.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import textwrap

TARGET_MB = 200.0

_CHILD = textwrap.dedent(
    """
    import json, resource, sys, time
    import numpy as np
    from tumble.integrate import simulate
    from tumble.models import torqued_body as tb
    from tumble.torques import GravityGradientTorque

    mode, t_end, samples = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
    inertia = np.array([1.0, 1.6, 2.0])
    p = tb.Params(inertia, 0.003, GravityGradientTorque(inertia, 0.05), 2.0 * np.pi / 0.05)
    st = tb.State(np.array([0.3, 0.9, 0.4]))
    simulate(tb.MODEL, p, st, np.linspace(0.0, 1.0, 3), "full")  # compiled code loaded
    start = time.perf_counter()
    if mode != "imports":
        tau = np.linspace(0.0, t_end, samples)
        run = simulate(tb.MODEL, p, st, tau, "full", dense=(mode == "dense"))
        assert run.integrator == "numba"
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(json.dumps({"mode": mode, "t_end": t_end, "peak_mb": peak,
                      "seconds": time.perf_counter() - start}))
    """
)


def _child(mode: str, t_end: float, samples: int) -> dict[str, float]:
    out = subprocess.run(
        [sys.executable, "-c", _CHILD, mode, repr(t_end), str(samples)],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])  # type: ignore[no-any-return]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=1e7)
    parser.add_argument("--samples", type=int, default=1000)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    rows = [
        _child("imports", 0.0, args.samples),
        _child("streamed", args.t_end, args.samples),
        _child("dense", args.t_end / 100.0, args.samples),
    ]
    met = rows[1]["peak_mb"] <= TARGET_MB
    if args.json:
        print(json.dumps({"rows": rows, "target_mb": TARGET_MB, "met": met}, indent=2))
    else:
        print(f"{'case':<10} {'t_end':>10} {'peak MB':>9} {'run s':>8}")
        for r in rows:
            print(f"{r['mode']:<10} {r['t_end']:>10.3g} {r['peak_mb']:>9.0f} {r['seconds']:>8.1f}")
        print(f"streamed peak {rows[1]['peak_mb']:.0f} MB (target ≤ {TARGET_MB:.0f}): "
              f"{'met' if met else 'missed'}")  # fmt: skip
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
