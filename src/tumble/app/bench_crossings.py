"""The benchmark of runs whose slow motion crosses a separatrix or a resonance: the examples
that do, at ε = 1e-3 and 1e-4, the default averaged method (what ``tumble run`` does with the
example's ``[run]``) against the full equations over the whole run.

* ``a3_negative`` (resisting medium): the nutation angle ϑ passes π/2, where the proper
  rotation stops (theory of the resisting medium, §10.2);
* ``rf_transient_x1`` and ``rf_counter_rotating`` (rotating field): the polhode crosses its
  separatrix, and in the second the spin passes through L = 0;
* ``tb_damper_crossing`` (torqued body): a damper and a linear drag take a spin about the
  least axis through the separatrix to the largest;
* ``ob_upper_stage_flat_spin`` (orbiting body): a spent stage's liquid takes its spin about the
  long axis through the separatrix to a flat spin.

Each example runs with ε scaled and its end time with 1/ε, so that its slow horizon ε·t_end is
the example's; :data:`SAMPLES` samples. The orbiting body has no ε key: its ε is the spin
period over the time constant of its internal dissipation (the one slow process that matters
to it; its gravity gradient is 4e-7 of the spin's scale Iω²), and the time constant is what
is scaled. For each: the full run at rtol 1e-10 (the benchmark's best of ``repeat``), a
reference full run at rtol 1e-12, and the averaged run at rtol 1e-10. The error is the
largest difference of each slow variable from the reference over the whole run
(:func:`tumble.analysis.verify.slow_errors`), relative to the variable's largest value (at
least 1), the largest over the variables, and is judged in units of ε: the target is
:data:`ERROR_IN_EPS` ε, and :data:`SPEEDUP` times the full run's speed at ε = 1e-4.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble.analysis.verify import slow_errors
from tumble.io.scenario import parse_scenario

__all__ = [
    "CAPTURE",
    "CAPTURE_AGREEMENT",
    "CASES",
    "EPS",
    "ERROR_IN_EPS",
    "SAMPLES",
    "SPEEDUP",
    "capture_markdown",
    "capture_study",
    "crossing_study",
    "markdown",
]

CASES: dict[str, dict[str, Any]] = {
    "a3_negative": {
        "model": "resisting_medium",
        "parameters": {"eps": 0.01, "kappa": 0.5, "a": [0.2, 0.0, -0.6],
                       "b": [[0.6, 0.0, 0.0], [0.0, 0.6, 0.0], [0.0, 0.0, 0.2]],
                       "s": [[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]]},
        "initial": {"k": 1.0, "rho": 0.8, "sigma": 0.0, "psi": 0.0, "theta": 0.8, "phi": 0.0},
        "run": {"tau_end": 300.0},
    },
    "rf_transient_x1": {
        "model": "rotating_field",
        "parameters": {"inertia": [1.0, 2.0, 2.5], "beta": 1.5707963267948966, "eps": 0.01},
        "initial": {"L": 1.5, "rho": 0.6, "sigma": 0.0, "k2": 0.5, "regime": "x1", "u0": 0.0,
                    "psi0": 0.0},
        "run": {"tau_end": 300.0},
    },
    "rf_counter_rotating": {
        "model": "rotating_field",
        "parameters": {"inertia": [1.0, 1.6, 2.2], "beta_deg": 17.0, "eps": 0.02},
        "initial": {"L": 0.6, "rho_deg": 149.0, "sigma": 0.0, "k2": 0.3, "regime": "x3"},
        "run": {"tau_end": 600.0},
    },
    "tb_damper_crossing": {
        "model": "torqued_body",
        "parameters": {"inertia": [1.0, 2.0, 3.0], "eps": 0.01},
        "torque": [{"kind": "internal_dissipation", "tau": 1.0},
                   {"kind": "linear_drag",
                    "B": [[0.3, 0.0, 0.0], [0.0, 0.2, 0.0], [0.0, 0.0, 0.1]]}],
        "initial": {"omega": [1.0, 0.25, 0.0], "psi_deg": 0.0, "theta_deg": 50.0,
                    "phi_deg": 0.0},
        "run": {"t_end": 400.0},
    },
    "ob_upper_stage_flat_spin": {
        "model": "orbiting_body",
        "body": {"mass": 1000.0, "inertia": [300.0, 1400.0, 1500.0]},
        "orbit": {"altitude": 500.0, "inclination_deg": 28.5, "epoch": "2025-03-01T00:00:00Z"},
        "torques": {"eddy_current": False, "gravity_gradient": True, "dissipation_days": 0.05},
        "initial": {"spin_period": 1.0, "spin_axis": [1.0, 0.15, 0.0], "psi_deg": 0.0,
                    "theta_deg": 40.0, "phi_deg": 0.0},
        "run": {"t_end_days": 0.3},
    },
}  # fmt: skip
"""The examples (``examples/<name>.toml``, a test holds them equal) whose slow motion crosses
a band: the model, its parameters, the initial state and the end time."""
EPS = (1e-3, 1e-4)
ERROR_IN_EPS = 10.0
"""The largest slow error over the run, in units of ε, that meets the target."""
SPEEDUP = 300.0
"""The averaged run's speed-up over the full one that meets the target at ε = 1e-4."""
SAMPLES = 401


def request_at(name: str, eps: float) -> Any:
    """The example ``name`` at ``eps``, its end time scaled to keep its slow horizon."""
    from tumble.app.bench import at_eps
    from tumble.models.orbiting_body.inputs import DAY

    data = copy.deepcopy(CASES[name])
    if data["model"] == "orbiting_body":  # ε = spin period / dissipation time (module notes)
        days = data["torques"]["dissipation_days"]
        horizon = data["run"]["t_end_days"] / days
        days = data["initial"]["spin_period"] / (eps * DAY)
        data["torques"]["dissipation_days"] = days
        data["run"] = {"t_end_days": horizon * days, "samples": SAMPLES}
    else:
        data = at_eps(data, eps, None, SAMPLES)
    return parse_scenario(data, f"examples/{name}.toml at eps = {eps:g}").request


def _case(name: str, eps: float, repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    from tumble.app.bench import _best  # short calls repeated until they add up
    from tumble.integrate import simulate

    req = request_at(name, eps)
    model, p, ini, tau = req.model, req.params, req.initial, req.tau

    def run(method: str, rtol: float, atol: float) -> Any:
        return simulate(model, p, ini, tau, method, rtol=rtol, atol=atol, averaging=req.averaging)

    log(f"crossings: {name} at ε = {eps:g}, the reference full run")
    ref = run("full", 1e-12, 1e-14)
    log(f"crossings: {name} at ε = {eps:g}, full and averaged")
    full_s, _ = _best(lambda: run("full", 1e-10, 1e-12), repeat)
    avg_s, avg = _best(lambda: run("averaged", 1e-10, 1e-12), repeat)
    errors = {}
    for v, (_, e) in slow_errors(model, p, ref, avg).items():
        column = ref.columns.get(v)
        scale = max(1.0, float(abs(column).max())) if column is not None else 1.0
        errors[v] = float(e.max()) / scale if e.size else 0.0
    error = max(errors.values())
    return {
        "eps": eps,
        "t_end": float(tau[-1]),
        "method": avg.form + _how(avg.legs),
        "full_s": full_s,
        "full_nfev": int(ref.nfev),
        "averaged_s": avg_s,
        "averaged_nfev": int(avg.nfev),
        "speedup": full_s / avg_s,
        "error": error,
        "error_in_eps": error / eps,
        "errors": errors,
    }


def _how(legs: tuple[tuple[str, float, float], ...]) -> str:
    """How an averaged run crossed its bands, for the table: by full legs (a hybrid run), by
    an asymptotic step, or not at all ("")."""
    kinds = {kind for kind, _, _ in legs}
    if "full" in kinds:
        return " (hybrid)"
    return " (asymptotic step)" if "asymptotic" in kinds else ""


def crossing_study(repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Every case at every ε (module notes); JSON-ready."""
    return {name: {f"{eps:g}": _case(name, eps, repeat, log) for eps in EPS} for name in CASES}


def study_table(
    head: tuple[str, str], result: dict[str, Any], row: Callable[[str, str, dict[str, Any]], str]
) -> str:
    """A study's Markdown table: its header and rule lines ``head``, then ``row(name, ε key,
    figures)`` for every case of ``result`` (keyed by name, then by ε)."""
    lines = [*head]
    for name, by_eps in result.items():
        lines += [row(name, key, r) for key, r in by_eps.items()]
    return "\n".join(lines)


def markdown(result: dict[str, Any]) -> str:
    """The study as a Markdown table."""
    head = ("| example | ε | full [s] | averaged [s] | speed-up | largest slow error | in ε |",
            "|---|---|---|---|---|---|---|")  # fmt: skip
    return study_table(head, result, lambda name, key, r: (
        f"| {name} ({r['method']}) | {key} | {r['full_s']:.3f} | {r['averaged_s']:.4f} "
        f"| {r['speedup']:.0f}× | {r['error']:.2e} | {r['error_in_eps']:.0f} |"))  # fmt: skip


CAPTURE: dict[str, tuple[float, float, float]] = {
    "damper, body torque 4.5e-4": (300.0, 4.5e-4, 0.0),
    "damper, body torque 1.2e-3": (300.0, 1.2e-3, 0.0),
    "damper, dipole 6e-4 in a field along L": (300.0, 0.0, 6e-4),
}
"""The capture ensembles: a triaxial body (moments 1, 2, 3) turning about its axis of least
inertia, a damper of time constant τ (:class:`~tumble.torques.InternalDissipation`), and a
constant body moment along the axis of largest inertia, or a body-fixed magnetic dipole along
the intermediate axis in a constant unit field along inertial ξ3, the body's least axis turned
onto it (so that L̂·B > 0 at every crossing): a torque of the attitude, whose odds need its
average over the precession; (τ, moment, dipole) in model units."""
CAPTURE_SIZE = 1000
CAPTURE_AGREEMENT = 0.03
"""The largest |frequency − predicted probability| that meets the target (absolute)."""


def _dipole_moment(t: float, q: Any, omega: Any, params: Any) -> Any:
    """M = m × Aᵀ B for m = (0, m2, 0) in the body (``params[0]`` = m2) and B = ξ3: B in the
    body, Aᵀ ξ3, is the third row of A (body → inertial), of which components 1 and 3 count."""
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    b1, b3 = 2.0 * (q1 * q3 - q0 * q2), 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return np.array([params[0] * b3, 0.0, -params[0] * b1])


def _dipole(m2: float) -> Any:
    """:func:`_dipole_moment` as a user's numba torque, compiled when the study runs (as a
    scenario's ``torque = "file:function"`` is) and never cached, so that the compiled full
    runs call it."""
    import numba

    from tumble.torques import UserTorque

    return UserTorque(numba.njit(_dipole_moment), {"m2": m2}, "bench:dipole")


def _capture(
    tau: float, moment: float, dipole: float, log: Callable[[str], None]
) -> dict[str, Any]:
    """One ensemble: CAPTURE_SIZE full runs from random phases about x1 until past the
    separatrix; the frequency of entering x3+ against the mean predicted probability, each
    at its run's ‖L‖ and direction of L at the crossing; and the averaged runs of the same
    ensemble, each predicting it at its own crossing (what an averaged study of crossings
    gives)."""
    from tumble.averaging.crossing import averaged_crossing, first_crossing, separatrix_crossing
    from tumble.errors import TumbleError
    from tumble.integrate import dop853, simulate_batch
    from tumble.models import torqued_body as tb
    from tumble.rotations import matrix_to_quat
    from tumble.torques import ConstantBodyTorque, InternalDissipation, Torque

    inertia = np.array([1.0, 2.0, 3.0])
    torque: Torque = InternalDissipation(inertia, tau)
    if moment:
        torque = torque + ConstantBodyTorque(np.array([0.0, 0.0, moment]))
    if dipole:
        torque = torque + _dipole(dipole)
    p = tb.Params(inertia, 1.0, torque)
    rng = np.random.default_rng(1)
    phase = rng.uniform(0.0, 2.0 * np.pi, CAPTURE_SIZE)
    # |ω| ≈ 1 about x1, the transverse rate 0.25 at a random phase: h = T − L²/(2 I2) > 0;
    # with the dipole, the body's x1 on ξ3 (A's columns: x1 → ξ3, x3 → −ξ1).
    turned = np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    q0 = matrix_to_quat(turned if dipole else np.eye(3))
    initials = [tb.State(np.array([1.0, 0.25 * np.cos(f), 0.25 * np.sin(f)]), q0) for f in phase]
    tau_samples = np.linspace(0.0, 5.0 * tau, 5001)  # ~40 samples a polhode period
    start = time.perf_counter()
    runs = simulate_batch(tb.MODEL, [p] * CAPTURE_SIZE, initials, tau_samples,
                          threads=dop853.available_threads(), method="full")  # fmt: skip
    full_s = time.perf_counter() - start
    entered, predicted = [], []
    # A region is entered once h is past the separatrix by the larger flux of a passage at
    # the start's ‖L‖ (h oscillates by about that much within a lap).
    L0 = float(np.linalg.norm(inertia * initials[0].omega))
    L_start = turned @ (inertia * initials[0].omega) if dipole else inertia * initials[0].omega
    depth = max(separatrix_crossing(torque, inertia, L0, "x1+", direction=L_start).fluxes.values())
    failed = 0
    for run in runs:
        if isinstance(run, TumbleError):  # counted, not hidden: the table shows the crossings
            failed += 1
            continue
        c = run.columns
        omega = np.stack([c["omega1"], c["omega2"], c["omega3"]], axis=1)
        found = first_crossing(inertia, run.tau, omega, depth)
        if found is None:
            continue
        at, L, left, region = found
        k = int(np.searchsorted(run.tau, at))
        L_xi = np.array([c["L1"][k], c["L2"][k], c["L3"][k]])
        entered.append(region == "x3+")
        odds = separatrix_crossing(torque, inertia, L, left, direction=L_xi).probabilities
        predicted.append(odds["x3+"])
    frequency, probability = float(np.mean(entered)), float(np.mean(predicted))
    start = time.perf_counter()
    averaged = simulate_batch(tb.MODEL, [p] * CAPTURE_SIZE, initials, tau_samples[::10],
                              threads=dop853.available_threads(), method="averaged")  # fmt: skip
    odds_avg, failed_avg = [], 0
    for run in averaged:
        if isinstance(run, TumbleError):
            failed_avg += 1
            continue
        c = run.columns
        crossing = averaged_crossing(inertia, run.tau, np.stack([c["L1"], c["L2"], c["L3"]], 1),
                                     c["T"])  # fmt: skip
        if crossing is not None:  # it leaves x1+: every body starts with ω1 > 0, and an
            L_xi = crossing[1]  # averaged run keeps its sense of rotation
            odds = separatrix_crossing(torque, inertia, float(np.linalg.norm(L_xi)), "x1+",
                                       direction=L_xi).probabilities  # fmt: skip
            odds_avg.append(odds["x3+"])
    averaged_s = time.perf_counter() - start
    from_averaged = float(np.mean(odds_avg)) if odds_avg else math.nan  # none crossed: NaN
    log(f"capture: τ = {tau:g}, moment {moment:g}, dipole {dipole:g}: {frequency:.3f} against "
        f"{probability:.3f}, and {from_averaged:.3f} from the averaged runs")  # fmt: skip
    return {
        "size": CAPTURE_SIZE,
        "crossed": len(entered),
        "failed": failed,
        "frequency": frequency,
        "predicted": probability,
        "difference": abs(frequency - probability),
        "full_s": full_s,
        "averaged_crossed": len(odds_avg),
        "averaged_failed": failed_avg,
        "averaged": from_averaged,
        "averaged_difference": abs(frequency - from_averaged),
        "averaged_s": averaged_s,
    }


def capture_study(log: Callable[[str], None]) -> dict[str, Any]:
    """Every capture ensemble (:data:`CAPTURE`); JSON-ready."""
    return {name: _capture(*case, log) for name, case in CAPTURE.items()}


def capture_markdown(result: dict[str, Any]) -> str:
    """The capture ensembles as a Markdown table."""
    lines = [
        "| ensemble | runs crossing | frequency of x3+ | predicted | difference | full runs [s] "
        "| averaged runs crossing | predicted by them | difference | averaged runs [s] |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, r in result.items():
        lines.append(
            f"| {name} | {r['crossed']} of {r['size']} | {r['frequency']:.3f} "
            f"| {r['predicted']:.3f} | {r['difference']:.3f} | {r['full_s']:.1f} "
            f"| {r['averaged_crossed']} of {r['size']} | {r['averaged']:.3f} "
            f"| {r['averaged_difference']:.3f} | {r['averaged_s']:.1f} |"
        )
    return "\n".join(lines)
