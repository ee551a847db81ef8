"""The orbiting body's benchmark: one simulated year of a LEO object, averaged against full,
and a 1000-sample Monte Carlo of averaged years against full 30-day runs; then three objects
of other shapes (:func:`rocket_study`: a rocket body with two equal moments; :func:`shell_study`:
a shell's year through its floor; :func:`capture_study`: a box to its capture by the gravity
gradient), each held equal to its example by a test.

The object is the example ``examples/ob_envisat_like.toml`` (a test holds :data:`YEAR_CASE`
equal to it): a large defunct triaxial satellite (I ~ 1e5 kg m²) spinning at 2.9°/s in a
766 km sun-synchronous orbit, under eddy currents and the gravity gradient.

* **A year.** The full run at rtol 1e-10 (tumble's default) and at 1e-8; the averaged run at
  rtol 1e-10, 1e-8 and 1e-6, each with its largest spin-period difference from the full run at
  1e-10. The verdict: the full run's time over that of the loosest averaged run whose period
  agrees within 1 %.
* **Monte Carlo.** :data:`MC_SAMPLES` averaged years at that tolerance, on one thread of the
  ensemble runner a sweep uses (:func:`tumble.integrate.simulate_batch`), with the
  conductivity, wall thickness, the moments of inertia (by a common factor) and the initial
  spin period drawn uniformly within ±20 %; against one full 30-day run on one core. The
  verdict: the ensemble's time in units of full 30-day runs.

Times are the best of ``repeat`` calls (the full year: one call; the ensemble: one pass).
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import json
import math
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble.integrate import Trajectory, simulate, simulate_batch
from tumble.io.scenario import parse_scenario

__all__ = ["MC_SAMPLES", "ROCKET_CASE", "YEAR_CASE", "markdown", "orbiting_study", "rocket_study"]

DAY = 86400.0
MC_SAMPLES = 1000
AVERAGED_LADDER = (1e-10, 1e-8, 1e-6)
PERIOD_AGREEMENT = 0.01

YEAR_CASE: dict[str, Any] = {
    "model": "orbiting_body",
    "body": {"mass": 7828.0, "inertia": [17023.0, 124826.0, 129112.0]},
    "conductor": {
        "shape": "thin_cylindrical_shell",
        "axis": [1.0, 0.0, 0.0],
        "conductivity": 2.5e7,
        "radius": 1.3,
        "length": 10.0,
        "thickness": 0.002,
    },
    "orbit": {"altitude": 766.0, "sun_synchronous": True, "epoch": "2013-09-25T00:00:00Z"},
    "initial": {
        "spin_period": 124.7,
        "spin_axis": [0.0, 0.0, 1.0],
        "psi_deg": 0.0,
        "theta_deg": 98.46,
        "phi_deg": 0.0,
    },
    "run": {"t_end_days": 365.0, "samples": 366, "methods": ["averaged"]},
}
"""The scenario of examples/ob_envisat_like.toml."""


ROCKET_CASE: dict[str, Any] = {
    "model": "orbiting_body",
    "body": {"mass": 1400.0, "inertia": [2160.0, 5580.0, 5580.0]},
    "conductor": {
        "shape": "thin_cylindrical_shell",
        "axis": [1.0, 0.0, 0.0],
        "conductivity": 2.5e7,
        "radius": 1.2,
        "length": 6.5,
        "thickness": 0.003,
    },
    "orbit": {"altitude": 800.0, "sun_synchronous": True, "epoch": "2025-03-20T00:00:00Z"},
    "initial": {
        "spin_period": 36.0,
        "spin_axis": [0.0, 0.0, 1.0],
        "psi_deg": 0.0,
        "theta_deg": 60.0,
        "phi_deg": 0.0,
    },
    "run": {"t_end_days": 365.0, "samples": 366, "methods": ["averaged"]},
}
"""The scenario of examples/ob_rocket_body.toml: a symmetric body (I2 = I3)."""

SHELL_CASE: dict[str, Any] = {
    "model": "orbiting_body",
    "body": {"mass": 20.0, "inertia": [0.8, 0.8, 0.8]},
    "conductor": {"shape": "thin_spherical_shell", "conductivity": 2.5e7, "radius": 0.3,
                  "thickness": 0.003},
    "orbit": {"altitude": 700.0, "sun_synchronous": True, "epoch": "2025-03-20T00:00:00Z"},
    "initial": {"omega_rpm": [2.0, 3.0, 9.3], "psi_deg": 30.0, "theta_deg": 60.0,
                "phi_deg": 0.0},
    "run": {"t_end_days": 365.0, "samples": 366, "methods": ["full", "averaged"]},
}  # fmt: skip
"""The 20 kg aluminium shell of examples/ob_aluminium_sphere.toml, over a year: through its
floor near twice the orbital rate."""

BOX_CASE: dict[str, Any] = {
    "model": "orbiting_body",
    "body": {"mass": 4.2, "inertia": [0.09, 0.12, 0.15]},
    "conductor": {"shape": "thin_cylindrical_shell", "axis": [1.0, 0.0, 0.0],
                  "conductivity": 2.5e7, "radius": 0.15, "length": 0.4, "thickness": 0.003},
    "orbit": {"altitude": 700.0, "sun_synchronous": True, "epoch": "2025-03-20T00:00:00Z"},
    "initial": {"omega_rpm": [2.0, 3.0, 9.3], "psi_deg": 30.0, "theta_deg": 60.0,
                "phi_deg": 0.0},
    "run": {"t_end_days": 365.0, "samples": 3651, "methods": ["full", "averaged"],
            "averaged_method": "hybrid"},
}  # fmt: skip
"""The 4 kg box of examples/ob_small_box.toml: spun down and captured by the gravity
gradient."""

CAPTURED = 0.01
"""A body turning at the orbital rate to within this fraction over its last 30 days is locked
to the orbit (captured)."""

ROCKET_TWIN = [2160.0, 5500.0, 5580.0]
"""The rocket body's slightly triaxial twin (I2 1.4 % below I3)."""


def _request(data: dict[str, Any], days: float, samples: int) -> Any:
    data = copy.deepcopy(data)
    data["run"] = {"t_end_days": days, "samples": samples}
    return parse_scenario(data, "orbiting_body.toml").request


def _timed(request: Any, method: str, rtol: float, repeat: int) -> tuple[float, Any]:
    """Best time of ``repeat`` runs of ``method`` (the benchmark's rule, :func:`bench._best`)
    and the trajectory."""
    from tumble.app.bench import _best

    run = functools.partial(simulate, request.model, request.params, request.initial,
                            request.tau, method, rtol=rtol, atol=request.atol)  # fmt: skip
    return _best(run, repeat)


def _sample(rng: np.random.Generator) -> dict[str, Any]:
    data = copy.deepcopy(YEAR_CASE)

    def spread(x: float) -> float:
        return float(x * rng.uniform(0.8, 1.2))

    c = data["conductor"]
    c["conductivity"], c["thickness"] = spread(c["conductivity"]), spread(c["thickness"])
    # The moments by a common factor (the mass): I2 and I3 differ by 3.4 %, and independent
    # draws would swap them, making the spin axis the middle one (a separatrix start, which
    # the averaged equations refuse in one line), a different body rather than an uncertain one.
    scale = rng.uniform(0.8, 1.2)
    data["body"]["inertia"] = [float(v * scale) for v in data["body"]["inertia"]]
    data["initial"]["spin_period"] = spread(data["initial"]["spin_period"])
    return data


def _ensemble(samples: list[Any], rtol: float) -> list[Any]:
    """The averaged runs of ``samples`` on one thread, each at its own sample times (the
    times are a year for all, but each point has its own time unit)."""
    first = samples[0]
    return simulate_batch(first.model, [s.params for s in samples], [s.initial for s in samples],
                          np.stack([s.tau for s in samples]), rtol=rtol, atol=first.atol,
                          method="averaged", threads=1)  # fmt: skip


def orbiting_study(repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Measure the year and the Monte Carlo (module notes); JSON-ready."""
    year = _request(YEAR_CASE, 365.0, 366)
    log("orbiting body: warming the kernels")
    warm = _request(YEAR_CASE, 1.0, 3)
    for method in ("full", "averaged"):
        _timed(warm, method, 1e-10, 1)
    full: dict[str, Any] = {}
    reference = None
    for rtol in (1e-10, 1e-8):
        log(f"orbiting body: a full year at rtol {rtol:g}")
        seconds, traj = _timed(year, "full", rtol, 1)
        period = traj.columns["period"]
        if reference is None:
            reference = period
        error = float(np.max(np.abs(period / reference - 1.0)))
        full[f"{rtol:g}"] = {"time_s": seconds, "nfev": traj.nfev, "period_error": error}
    assert reference is not None
    averaged: dict[str, Any] = {}
    chosen = None
    for rtol in AVERAGED_LADDER:
        log(f"orbiting body: an averaged year at rtol {rtol:g}")
        seconds, traj = _timed(year, "averaged", rtol, repeat)
        error = float(np.max(np.abs(traj.columns["period"] / reference - 1.0)))
        averaged[f"{rtol:g}"] = {"time_s": seconds, "nfev": traj.nfev, "period_error": error}
        if error <= PERIOD_AGREEMENT:
            chosen = rtol
    full_s = full[f"{1e-10:g}"]["time_s"]
    out: dict[str, Any] = {
        "case": "examples/ob_envisat_like.toml: I = 17,023 / 124,826 / 129,112 kg m², spin "
        "period 124.7 s, 766 km sun-synchronous, eddy current + gravity gradient, 365 days",
        "full": full,
        "averaged": averaged,
        "rtol": chosen,
        "rocket_body": rocket_study(repeat, log),
        "shell": shell_study(log),
        "capture": capture_study(log),
    }
    if chosen is None:
        return out
    out["speedup"] = full_s / averaged[f"{chosen:g}"]["time_s"]
    out["speedup_vs_full_1e-8"] = full[f"{1e-8:g}"]["time_s"] / averaged[f"{chosen:g}"]["time_s"]
    log("orbiting body: a full 30-day run")
    month_s, _ = _timed(_request(YEAR_CASE, 30.0, 31), "full", 1e-10, repeat)
    rng = np.random.default_rng(2013)
    samples = [_request(_sample(rng), 365.0, 366) for _ in range(MC_SAMPLES)]
    ensemble = functools.partial(_ensemble, rtol=chosen)
    ensemble(samples[:2])  # compiles the ensemble's integrator for this kernel
    log(f"orbiting body: {MC_SAMPLES} averaged years")
    start = time.perf_counter()
    runs = ensemble(samples)
    mc_s = time.perf_counter() - start
    finals = [
        float(run.columns["period"][-1] * req.params.T0)
        for run, req in zip(runs, samples, strict=True)
        if isinstance(run, Trajectory)
    ]
    failed = MC_SAMPLES - len(finals)
    out["monte_carlo"] = {
        "samples": MC_SAMPLES,
        "failed": failed,
        "time_s": mc_s,
        "full_30_days_s": month_s,
        "in_full_30_day_runs": mc_s / month_s,
        "final_period_percentiles_s": {
            str(q): float(np.percentile(finals, q)) for q in (5, 50, 95)
        } if finals else {},
    }  # fmt: skip
    return out


_RUN_IN_A_PROCESS = (
    "import json, sys; from tumble.app.runner import run; "
    "from tumble.io.scenario import parse_scenario; "
    "run(parse_scenario(json.loads(sys.argv[1]), 'rocket.toml'), sys.argv[2], overwrite=True)"
)


def _process_seconds(case: dict[str, Any], days: float, repeat: int) -> float:
    """Best wall time of ``repeat`` fresh processes that run ``case`` over ``days`` and write
    its outputs (warm: the kernels from the disk cache)."""
    data = copy.deepcopy(case)
    data["run"] = {**data["run"], "t_end_days": days, "samples": int(days) + 1}
    best = math.inf
    with tempfile.TemporaryDirectory() as out:
        for _ in range(repeat + 1):  # the first fills the cache if it was not
            start = time.perf_counter()
            subprocess.run([sys.executable, "-c", _RUN_IN_A_PROCESS, json.dumps(data), out],
                           check=True, capture_output=True)  # fmt: skip
            best = min(best, time.perf_counter() - start)
    return best


def shell_study(log: Callable[[str], None]) -> dict[str, Any]:
    """The 20 kg shell's year through its floor: full against averaged, once each (the full
    year takes ~10 s), the largest relative difference of the spin rate over the year's
    samples and the speed-up. JSON-ready."""
    year = _request(SHELL_CASE, 365.0, 366)
    log("shell: a full year and an averaged one")
    full = _timed(year, "full", year.rtol, 1)[1]
    averaged = _timed(year, "averaged", year.rtol, 1)[1]
    rate = full.columns["rate"]
    return {
        "case": "examples/ob_aluminium_sphere.toml over 365 days: a 20 kg aluminium shell, "
        "700 km sun-synchronous, 10 rpm",
        "full_s": full.wall_time,
        "averaged_s": averaged.wall_time,
        "speedup": full.wall_time / averaged.wall_time,
        "rate_difference": float(np.max(np.abs(averaged.columns["rate"] / rate - 1.0))),
        "final_over_orbital_rate": float(
            rate[-1] / (year.params.orbit.mean_motion * year.params.T0)
        ),
    }


def capture_study(log: Callable[[str], None]) -> dict[str, Any]:
    """The small box's year, full and hybrid, once each: their rates over the last 30 days
    against the orbital rate, and the full run's angle between the axis of least inertia and
    the local vertical over those days (its libration). JSON-ready."""
    from tumble.rotations import quat_to_matrix

    data = copy.deepcopy(BOX_CASE)
    year = parse_scenario(data, "orbiting_body.toml").request
    p = year.params
    n = p.orbit.mean_motion * p.T0
    last = year.tau > year.tau[-1] - 30.0 * DAY / p.T0
    log("small box: a full year and a hybrid one")
    full = _timed(year, "full", year.rtol, 1)[1]
    hybrid = simulate(year.model, p, year.initial, year.tau, "averaged", rtol=year.rtol,
                      atol=year.atol, averaging=year.averaging)  # fmt: skip
    axis = int(np.argmin(BOX_CASE["body"]["inertia"]))
    t_s = year.tau[last] * p.T0
    up = p.orbit.states(t_s)[:, :3]
    up /= np.linalg.norm(up, axis=1, keepdims=True)
    q = np.stack([full.columns[f"q{i}"][last] for i in range(4)], axis=1)
    tilt = [math.degrees(math.acos(min(1.0, abs(float(quat_to_matrix(qi)[:, axis] @ u)))))
            for qi, u in zip(q, up, strict=True)]  # fmt: skip
    return {
        "case": "examples/ob_small_box.toml: a 4 kg aluminium box, moments 0.09 / 0.12 / "
        "0.15 kg m², 700 km sun-synchronous, 10 rpm, 365 days",
        "full_s": full.wall_time,
        "hybrid_s": hybrid.wall_time,
        "full_rate_over_n": float(np.median(full.columns["rate"][last]) / n),
        "hybrid_rate_over_n": float(np.median(hybrid.columns["rate"][last]) / n),
        "full_vertical_tilt_max_deg": max(tilt),
        "hybrid_legs": [list(leg) for leg in hybrid.legs],
    }


def rocket_study(repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    """A rocket body's averaged year: the integration's wall time (the run table's, best of
    ``repeat``), the run end to end in a fresh process (load, run, checks, outputs) against
    the same for one day (the start-up of any warm run), and the final spin period against
    its slightly triaxial twin's. JSON-ready."""
    twin_case = copy.deepcopy(ROCKET_CASE)
    twin_case["body"]["inertia"] = ROCKET_TWIN
    year = dataclasses.replace(_request(ROCKET_CASE, 365.0, 366), methods=("averaged",))
    log("rocket body: an averaged year, its twin's, and end to end")
    _timed(year, "averaged", year.rtol, 1)  # warm
    runs = [_timed(year, "averaged", year.rtol, 1)[1] for _ in range(repeat)]
    twin = _timed(_request(twin_case, 365.0, 366), "averaged", year.rtol, 1)[1]
    ends = {name: _process_seconds(ROCKET_CASE, days, repeat)
            for name, days in (("year", 365.0), ("one_day", 1.0))}  # fmt: skip
    final, twin_final = float(runs[0].columns["period"][-1]), float(twin.columns["period"][-1])
    return {
        "case": "examples/ob_rocket_body.toml: I = 2160 / 5580 / 5580 kg m², a 6.5 m × 2.4 m "
        "aluminium cylinder (3 mm wall), 800 km sun-synchronous, 10 °/s, 365 days",
        "integrator": runs[0].integrator,
        "integration_s": min(r.wall_time for r in runs),
        "end_to_end_s": ends,
        "year_over_one_day": ends["year"] / ends["one_day"],
        "twin_inertia": ROCKET_TWIN,
        "twin_final_period_difference": abs(final / twin_final - 1.0),
    }


def markdown(orbit: dict[str, Any]) -> str:
    """The study's figures as Markdown (the performance page's table)."""
    lines = [f"Orbiting body, one year ({orbit['case']}):", "",
             "| run | rtol | time [s] | evaluations | spin period vs full |",
             "|---|---:|---:|---:|---:|"]  # fmt: skip
    for method in ("full", "averaged"):
        for rtol, v in orbit[method].items():
            lines.append(f"| {method} | {rtol} | {v['time_s']:.4g} | {v['nfev']} | "
                         f"{v['period_error']:.2e} |")  # fmt: skip
    if "speedup" in orbit:
        lines += ["", f"Speed-up of the averaged year (rtol {orbit['rtol']:g}) over the full "
                  f"one at rtol 1e-10 (≥ 1000×): {orbit['speedup']:.0f}× "
                  f"({orbit['speedup_vs_full_1e-8']:.0f}× over the full one at 1e-8)."]  # fmt: skip
    mc = orbit.get("monte_carlo")
    if mc:
        bands = mc["final_period_percentiles_s"]
        lines.append(f"{mc['samples']} averaged years on one thread of the ensemble runner: "
                     f"{mc['time_s']:.3g} s, "
                     f"{mc['in_full_30_day_runs']:.3g} full 30-day runs of "
                     f"{mc['full_30_days_s']:.3g} s "
                     f"(≤ 5); final spin period {bands['50']:.0f} s at the median, "
                     f"{bands['5']:.0f}–{bands['95']:.0f} s for 90 % of the draws.")  # fmt: skip
    rocket = orbit.get("rocket_body")
    if rocket:
        ends = rocket["end_to_end_s"]
        lines += ["", f"A rocket body's averaged year ({rocket['case']}), on "
                  f"{rocket['integrator']}: {rocket['integration_s']:.3g} s of integration "
                  f"(≤ 0.1 s); end to end "
                  f"{ends['year']:.3g} s against {ends['one_day']:.3g} s for one day "
                  f"(× {rocket['year_over_one_day']:.2f}, ≤ 1.1); final spin period within "
                  f"{100 * rocket['twin_final_period_difference']:.3f} % of its slightly "
                  "triaxial twin's (≤ 0.1 %)."]  # fmt: skip
    shell = orbit.get("shell")
    if shell:
        lines += ["", f"A year through the floor ({shell['case']}): the averaged run's spin rate "
                  f"within {100 * shell['rate_difference']:.3f} % of the full run's throughout "
                  f"(≤ 1 %), {shell['speedup']:.0f}× faster (≥ 100×; {shell['full_s']:.3g} s "
                  f"against {shell['averaged_s']:.3g} s); it ends at "
                  f"{shell['final_over_orbital_rate']:.2f} times the orbital rate."]  # fmt: skip
    box = orbit.get("capture")
    if box:
        lines += ["", f"Through the floor to capture ({box['case']}): over the last 30 days the "
                  f"full run turns at {box['full_rate_over_n']:.4f} n, its axis of least "
                  f"inertia within {box['full_vertical_tilt_max_deg']:.1f}° of the local "
                  f"vertical (captured), the hybrid run at {box['hybrid_rate_over_n']:.4f} n "
                  f"(the same end state); {box['full_s']:.3g} s against "
                  f"{box['hybrid_s']:.3g} s."]  # fmt: skip
    return "\n".join(lines)
