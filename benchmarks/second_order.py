"""The averaging error against ε at orders 1 and 2, for the figure and table of the
second-order averaging page (docs/second-order-averaging.md).

    .venv/bin/python benchmarks/second_order.py [-o benchmarks/second_order.json]
        [--figure docs/figures/second_order_errors.png] [--from benchmarks/second_order.json]

For each case: ``tumble verify`` from ε = 1e-2 down to 3e-4 (factors 1, 0.3, 0.1, 0.03) over
the case's slow horizon, both orders of averaging, the osculating start, rtol 1e-12; the
rotating field from ε = 3e-3 down to 1e-4 (at ε = 1e-2 every state tried lies within a few
widths of a resonance of its three frequencies, where a run of order 2 stops). Prints the fitted
slopes and the errors at ε = 1e-3 (about 5 minutes on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np

from tumble.analysis import RunRequest, verify
from tumble.io import load_scenario, parse_scenario
from tumble.io.output import atomic_write
from tumble.models import resisting_medium as rm
from tumble.models.base import AveragingOptions

FACTORS = (1.0, 0.3, 0.1, 0.03)
RTOL, ATOL = 1e-12, 1e-14
"""Integration tolerances of both runs: at rtol 1e-10 the full run's own error over the
3300 time units of ε = 3e-4 (~1e-8 in θmax) is as large as the second-order error there."""
ROOT = Path(__file__).resolve().parent.parent


def _cases() -> dict[str, tuple[RunRequest, tuple[float, ...]]]:
    # The resisting medium away from resonances and the equator: a prolate body (I3 = 0.2 I1),
    # ϑ in (0.2, 0.7) over the slow time 1 (the case of tests/models/test_rm_second_order.py).
    p = rm.Params(eps=1e-2, kappa=-0.8, a=[0.1, 0.2, 1.0], s=np.diag([0.2, 0.1, 0.3]),
                  b=[[0.3, 0.1, 0.0], [0.0, 0.4, 0.0], [0.0, 0.0, 0.5]])  # fmt: skip
    st = rm.State(k=1.0, rho=0.8, sigma=0.3, psi=0.2, theta=0.6, phi=0.4)
    medium = RunRequest(rm.MODEL, p, st, np.linspace(0.0, 100.0, 101), ("full", "averaged"),
                        RTOL, ATOL, averaging=AveragingOptions(order=2))  # fmt: skip
    nm = load_scenario(ROOT / "examples" / "nm_damped_exp.toml").request
    nm = replace(nm, averaging=replace(nm.averaging, order=2), tau=np.linspace(0.0, 100.0, 201),
                 rtol=RTOL, atol=ATOL)  # fmt: skip
    # The rotating field in regime x1 at k² = 0.2 over the slow time 0.15: clear of the
    # resonance 4ν1 = 2 that its drift reaches at the slow time 0.2 when ε = 3e-3.
    data = tomllib.loads((ROOT / "examples" / "rf_transient_x1.toml").read_text())
    data["parameters"]["eps"], data["initial"]["k2"] = 3e-3, 0.2
    rf = parse_scenario(data, "rf_transient_x1.toml").request
    rf = replace(rf, averaging=replace(rf.averaging, order=2), tau=np.linspace(0.0, 50.0, 31),
                 rtol=RTOL, atol=ATOL)  # fmt: skip
    return {
        "resisting_medium (spinner setting)": (medium, FACTORS),
        "nonlinear_moment (nutation)": (nm, FACTORS),
        "rotating_field (triaxial setting)": (rf, (1.0, 1.0 / 3.0, 0.1, 1.0 / 30.0)),
    }


def measure() -> dict[str, dict[str, object]]:
    out: dict[str, dict[str, object]] = {}
    for name, (request, factors) in _cases().items():
        result = verify(request, factors)
        per = {}
        for order, fit in result.by_order.items():
            for v, (errors, slope) in fit.items():
                per.setdefault(v, {})[f"slope_order{order}"] = slope
                per[v][f"errors_order{order}"] = [float(e) for e in errors]
        out[name] = {"eps": result.eps.tolist(), "variables": per, "verdict": result.verdict}
    return out


def figure(data: dict[str, dict[str, object]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(data), figsize=(5.2 * len(data), 4.2), squeeze=False)
    for ax, (name, case) in zip(axes[0], data.items(), strict=True):
        eps = np.asarray(case["eps"])
        rows = [(v, r) for v, r in case["variables"].items() if r.get("slope_order1")]  # type: ignore[attr-defined]
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for (v, row), color in zip(rows, colors[: len(rows)], strict=True):
            for order, style in ((1, "o--"), (2, "s-")):
                slope = row[f"slope_order{order}"]
                label = f"{v}, order {order} (slope {slope:.2f})"
                ax.loglog(eps, row[f"errors_order{order}"], style, color=color, label=label,
                          ms=4)  # fmt: skip
        ax.loglog(eps, 0.3 * eps, ":", color="grey", label="∝ ε")
        ax.loglog(eps, 3.0 * eps**2, "-.", color="grey", label="∝ ε²")
        ax.set_xlabel("ε [1]")
        ax.set_ylabel("max |full − averaged| over the slow horizon")
        ax.set_title(name)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=None)
    parser.add_argument("--figure", type=Path, default=None)
    parser.add_argument(
        "--from",
        dest="source",
        type=Path,
        default=None,
        help="print and draw an earlier run's JSON instead of measuring",
    )
    args = parser.parse_args()
    data = json.loads(args.source.read_text()) if args.source else measure()
    for name, case in data.items():
        print(name, "—", case["verdict"])
        for v, row in case["variables"].items():  # type: ignore[attr-defined]
            at = int(np.argmin(np.abs(np.log(np.asarray(case["eps"]) / 1e-3))))
            print(f"  {v}: slopes {row.get('slope_order1')} / {row.get('slope_order2')}, "
                  f"error at ε = 1e-3: {row['errors_order1'][at]:.2e} / "
                  f"{row['errors_order2'][at]:.2e}")  # fmt: skip
    if args.output is not None:
        atomic_write(args.output, (json.dumps(data, indent=2) + "\n").encode())
    if args.figure is not None:
        figure(data, args.figure)


if __name__ == "__main__":
    main()
