"""The benchmark of sunlight on a faceted body: a year of a dead box-wing satellite in GEO,
averaged against full, spinning about one axis and tumbling, and the cost of one evaluation of
the averaged equations with the exact and the expanded illumination.

The objects are the examples ``examples/ob_geo_box_wing.toml`` (the spin about the array's
boom) and ``examples/ob_geo_box_wing_tumbling.toml`` (a tumble); a test holds
:data:`CASES` equal to them.

* **A year.** The full run at rtol 1e-10 (tumble's default), once; the averaged run at rtol
  1e-10, 1e-8 and 1e-6, each with its largest spin-period difference from the full run and the
  largest angle between their angular momenta. The verdict: the full run's time over that of
  the loosest averaged run within :data:`PERIOD_AGREEMENT` and :data:`DIRECTION_AGREEMENT_DEG`
  (the rule of :mod:`tumble.app.bench_orbit`). The tumble's year is also run with the expanded
  illumination, whose error is the expansion's.
* **One evaluation.** The compiled averaged right-hand side (sunlight and the gravity gradient)
  at each example's initial state, in compiled code without the call from Python (the
  benchmark's rule, :func:`tumble.kernels.rhs.evaluate_repeatedly`), best of five.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble.analysis.claims.observations import GEO_BOX_WING
from tumble.io.scenario import parse_scenario

__all__ = ["CASES", "DIRECTION_AGREEMENT_DEG", "PERIOD_AGREEMENT", "markdown", "sunlight_study"]

LADDER = (1e-10, 1e-8, 1e-6)
PERIOD_AGREEMENT = 0.02
DIRECTION_AGREEMENT_DEG = 5.0
_EVALUATIONS = 20_000

_BOX_WING: dict[str, Any] = {
    "model": "orbiting_body",
    **copy.deepcopy(GEO_BOX_WING),
    "initial": {
        "spin_period": 60.0,
        "spin_axis": [0.0, 1.0, 0.0],
        "psi_deg": 0.0,
        "theta_deg": 30.0,
        "phi_deg": 0.0,
    },
    "run": {"t_end_days": 365.0, "samples": 366, "methods": ["averaged"]},
}
_TUMBLING = copy.deepcopy(_BOX_WING)
_TUMBLING["initial"]["spin_axis"] = [1.0, 0.6, 0.4]

CASES: dict[str, dict[str, Any]] = {"spin": _BOX_WING, "tumble": _TUMBLING}
"""The scenarios of examples/ob_geo_box_wing.toml ("spin") and
examples/ob_geo_box_wing_tumbling.toml ("tumble")."""


def _request(data: dict[str, Any], illumination: str = "exact") -> Any:
    data = copy.deepcopy(data)
    data["surface"]["averaged_illumination"] = illumination
    return parse_scenario(data, "geo_box_wing.toml").request


def _run(request: Any, method: str, rtol: float) -> tuple[float, Any]:
    from tumble.integrate import simulate

    start = time.perf_counter()
    run = simulate(request.model, request.params, request.initial, request.tau, method,
                   rtol=rtol, atol=request.atol)  # fmt: skip
    return time.perf_counter() - start, run


def _against(full: Any, run: Any) -> tuple[float, float]:
    """(largest |P/P_full − 1|, largest angle between the angular momenta [deg])."""
    f, a = full.columns, run.columns
    period = float(np.max(np.abs(a["period"] / f["period"] - 1.0)))
    Lf = np.stack([f[f"L{i}"] for i in (1, 2, 3)], axis=1)
    La = np.stack([a[f"L{i}"] for i in (1, 2, 3)], axis=1)
    cos = np.sum(Lf * La, axis=1) / np.linalg.norm(Lf, axis=1) / np.linalg.norm(La, axis=1)
    return period, float(np.degrees(np.max(np.arccos(np.clip(cos, -1.0, 1.0)))))


def _averaged(request: Any, full: Any, rtol: float, repeat: int) -> dict[str, Any]:
    best, run = min((_run(request, "averaged", rtol) for _ in range(repeat)),
                    key=lambda x: x[0])  # fmt: skip
    period, angle = _against(full, run)
    return {"time_s": best, "nfev": int(run.nfev), "period_error": period,
            "direction_deg": angle,
            "final_period_s": float(run.columns["period"][-1] * request.params.T0)}  # fmt: skip


def _eval_us(request: Any) -> float:
    """One evaluation of the compiled averaged right-hand side at the initial state [µs]."""
    from tumble.kernels.rhs import evaluate_repeatedly
    from tumble.models.torqued_body.model import _sense, _vector_from_slow, averaged_kernel

    kernel = averaged_kernel(request.params, _sense(request.params, request.initial))
    assert kernel is not None  # built-in terms only
    y = _vector_from_slow(request.params, request.initial)
    evaluate_repeatedly(kernel.kind, 0.0, y, kernel.params, 10, 0.0)  # compiled, warm
    best = math.inf
    for _ in range(5):
        start = time.perf_counter()
        evaluate_repeatedly(kernel.kind, 0.0, y, kernel.params, _EVALUATIONS, 0.0)
        best = min(best, time.perf_counter() - start)
    return 1e6 * best / _EVALUATIONS


def _year(name: str, repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    request = _request(CASES[name])
    log(f"sunlight, {name}: a full year at rtol 1e-10 (a few minutes)")
    full_s, full = _run(request, "full", 1e-10)
    out: dict[str, Any] = {"full_s": full_s, "full_nfev": int(full.nfev),
                           "full_final_period_s": float(full.columns["period"][-1]
                                                        * request.params.T0),
                           "full_k2_range": [float(np.min(full.columns["k2"])),
                                             float(np.max(full.columns["k2"]))],
                           "averaged": {}}  # fmt: skip
    for rtol in LADDER:
        log(f"sunlight, {name}: the averaged year at rtol {rtol:g}")
        out["averaged"][f"{rtol:g}"] = _averaged(request, full, rtol, repeat)
    ladder = out["averaged"]
    within = [
        r
        for r in LADDER
        if ladder[f"{r:g}"]["period_error"] <= PERIOD_AGREEMENT
        and ladder[f"{r:g}"]["direction_deg"] <= DIRECTION_AGREEMENT_DEG
    ]
    out["rtol"] = max(within) if within else None
    out["speedup"] = full_s / out["averaged"][f"{max(within):g}"]["time_s"] if within else 0.0
    out["eval_us"] = _eval_us(request)
    if name == "tumble":
        expanded = _request(CASES[name], "expanded")
        out["expanded"] = _averaged(expanded, full, 1e-10, repeat)
        out["expanded_eval_us"] = _eval_us(expanded)
    return out


def sunlight_study(repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Measure the two years and the evaluations (module notes); JSON-ready."""
    return {name: _year(name, repeat, log) for name in CASES}


def markdown(result: dict[str, Any]) -> str:
    """The study as a Markdown table."""
    lines = [
        "| object | full year [s] | averaged (rtol) [s] | speed-up | period error | L direction "
        "| one evaluation [µs] |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, r in result.items():
        rtol = r["rtol"]
        a = r["averaged"][f"{rtol:g}"] if rtol else None
        if a is None:
            lines.append(f"| {name} | {r['full_s']:.1f} | none within the bands | | | | |")
            continue
        lines.append(
            f"| {name} | {r['full_s']:.1f} | {a['time_s']:.3f} ({rtol:g}) | {r['speedup']:.0f}× "
            f"| {a['period_error']:.2e} | {a['direction_deg']:.3f}° | {r['eval_us']:.2f} |"
        )
        if "expanded" in r:
            e = r["expanded"]
            lines.append(
                f"| {name}, expanded illumination | | {e['time_s']:.3f} (1e-10) | "
                f"{r['full_s'] / e['time_s']:.0f}× | {e['period_error']:.2e} | "
                f"{e['direction_deg']:.3f}° | {r['expanded_eval_us']:.2f} |"
            )
    return "\n".join(lines)
