"""Performance benchmark: every figure measured in one run on one machine, as ratios.

Four studies, each with its error figures and its target beside it:

``full_speedup_vs_scipy``
    The full equations over ``horizon`` time units (default 1e5) at rtol 1e-10, for the free
    triaxial body and for the default scenario of each model (``tumble init``) with ε scaled so
    that the slow horizon ε·t_end stays the template's: compiled DOP853
    (:func:`tumble.integrate.dop853.solve`) against scipy's DOP853 calling the model's
    right-hand side. Both take the same steps; each final state's error is measured against
    a tighter reference.
``full_time_ratio_vs_heyoka``
    The same runs against heyoka.py (Taylor method, LLVM; ``pip install tumble[bench]``) at
    equal error: heyoka runs a ladder of tolerances and its time at tumble's error is
    interpolated (log time against log error) between the two rungs that bracket it.
``averaged_speedup``
    Each paper model's default scenario at ε = 1e-2, 1e-3 and 1e-4 over the template's slow
    horizon:
    the averaged equations (and the closed form, where the model has one) against the full
    ones, both through :func:`tumble.integrate.simulate` (what a user runs), with the slow
    variables' error against a full run at rtol 1e-12. "Equal accuracy" also times the
    loosest full run whose slow error does not exceed the averaged one.
``batch_throughput``
    Trajectories per second of :func:`tumble.integrate.dop853.solve_batch` on 1, 2 and all cores.
``averaged_batch_throughput``
    Averaged runs per second of an ensemble of 1000 initial states of each paper model
    (:func:`tumble.integrate.simulate_batch` with ``method = "averaged"``) on 1 and all cores,
    and of one :func:`tumble.integrate.simulate` per point.
``orbiting_body``
    A year of a large defunct satellite in LEO, averaged against full, and 1000 averaged years
    of it with uncertain conductor, inertia and spin against one full 30-day run
    (:mod:`tumble.app.bench_orbit`).
``crossings``
    The examples whose slow motion crosses a separatrix or a resonance at ε = 1e-3 and 1e-4:
    the default averaged method's largest slow error over the run, in units of ε, and its
    speed-up over the full run (:mod:`tumble.app.bench_crossings`).
``capture``
    Ensembles of 1000 full runs of a triaxial body driven across the separatrix of the free
    motion: the frequency of each rotation it passes into against the predicted probability
    (:func:`tumble.averaging.separatrix_crossing`).

``compile`` times the first call of each kernel kind from an empty disk cache, in a fresh
process (numba's compile, once per installation), and the load from the cache.

Times are the best of ``repeat`` calls (time.perf_counter): the best is the cost of the code,
the rest is the machine's load. The errors are the largest component of the final state's
difference, relative to the largest component of the reference (at least 1).
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
import time
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from tumble._typing import FloatArray
from tumble.analysis.verify import slow_errors
from tumble.app import heyoka_peer
from tumble.app.bench_machine import compile_times, machine, startup_times
from tumble.app.bench_verdicts import TARGETS, verdicts
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs
from tumble.errors import IntegrationError, ParameterError, TumbleError
from tumble.integrate import dop853, simulate, simulate_batch
from tumble.io.scenario import parse_scenario, template
from tumble.kernels import Kernel
from tumble.kernels.rhs import evaluate_repeatedly
from tumble.models.base import AveragingOptions

__all__ = [
    "TARGETS",
    "BenchSettings",
    "FullCase",
    "at_eps",
    "full_cases",
    "run_benchmark",
]

PAPER_MODELS = ("resisting_medium", "rotating_field", "nonlinear_moment")
FULL_MODELS = (*PAPER_MODELS, "torqued_body")

REFERENCE_RTOL = 1e-13  # DOP853 reference: 3 decades below the benchmark's rtol 1e-10
REFERENCE_ATOL = 1e-15
HEYOKA_REFERENCE_TOL = 1e-15  # heyoka's Taylor method near double precision
HEYOKA_LADDER = tuple(10.0**-k for k in range(6, 16))
FULL_LADDER = tuple(10.0**-k for k in range(3, 11))  # full runs for "equal accuracy"
AVERAGED_EPS = (1e-2, 1e-3, 1e-4)
ENGINE_EPS = (1e-3, 1e-4)
ENGINE_CASES: dict[str, tuple[str, str | None]] = {
    "spinner: resisting_medium moment": ("resisting_medium", "numeric"),
    "triaxial: torqued_body gravity gradient": ("torqued_body", None),  # its own averaging
    "nutation: nonlinear_moment damping and pressure": ("nonlinear_moment", "numeric"),
}
"""The general averaging engine in each of its settings, on a built-in torque: the model's
default scenario with ``[run] averaging = "numeric"``, by the engine's setting and torque."""
EVAL_SECONDS = 0.05  # time spent measuring the cost of one evaluation
AVERAGED_SAMPLES = 201
ENSEMBLE_SIZE = 1000
ENSEMBLE_INITIAL: dict[str, dict[str, tuple[float, float]]] = {
    "resisting_medium": {"rho": (0.2, 2.9), "theta": (0.3, 2.8), "k": (0.5, 2.0)},
    "rotating_field": {"rho": (0.2, 2.9), "k2": (0.2, 0.8)},
    "nonlinear_moment": {"theta": (0.8, 1.2), "theta_dot": (-0.3, 0.3)},
}
"""The initial keys an averaged ensemble of each paper model spreads (uniformly, seeded)."""


@dataclass(frozen=True)
class BenchSettings:
    """What the benchmark measures and how long it may take.

    Attributes
    ----------
    horizon : float
        Length of the full runs [each model's time unit] (issue: 1e5).
    rtol, atol : float
        Tolerances of the timed runs.
    repeat : int
        Timed calls per figure; the best counts.
    scipy : bool
        Time scipy's DOP853 calling the right-hand side from Python (about a minute per case
        at 1e5).
    heyoka : bool
        Compare with heyoka.py when it is installed.
    batch_size : int
        Trajectories per batch.
    compile : bool
        Measure the cold compile in a fresh process with an empty cache.
    startup : bool
        Time ``tumble`` answering from a fresh process (help, models, input errors).
    engine : bool
        Time the general averaging engine against the full runs (:data:`ENGINE_CASES`).
    orbit : bool
        Time a year of an orbiting body and a Monte Carlo of them, a rocket body's year, a
        shell's through its floor, a box's to its capture and two years of a box-wing
        satellite in sunlight (:mod:`tumble.app.bench_orbit`, :mod:`tumble.app.bench_sunlight`;
        about 3 minutes).
    crossings : bool
        Time the examples whose slow motion crosses a separatrix or a resonance, averaged
        against full at ε = 1e-3 and 1e-4 (:mod:`tumble.app.bench_crossings`; about 3 minutes).
    ensemble_size : int
        Initial states in each averaged ensemble (:data:`ENSEMBLE_SIZE`; a quick check takes
        fewer).
    """

    horizon: float = 1e5
    rtol: float = 1e-10
    atol: float = 1e-12
    repeat: int = 5
    scipy: bool = True
    heyoka: bool = True
    batch_size: int = 128
    compile: bool = True
    startup: bool = True
    engine: bool = True
    orbit: bool = True
    crossings: bool = True
    ensemble_size: int = ENSEMBLE_SIZE

    def __post_init__(self) -> None:
        if not (self.horizon > 0.0 and math.isfinite(self.horizon)):
            raise ParameterError(f"--horizon = {self.horizon:g} must be a positive number")
        if not 1e-14 <= self.rtol <= 1e-3:
            raise ParameterError(f"--rtol = {self.rtol:g} must be in [1e-14, 1e-3]")
        if self.repeat < 1:
            raise ParameterError(f"--repeat = {self.repeat} must be at least 1")
        if self.batch_size < 2:
            raise ParameterError(f"--batch-size = {self.batch_size} must be at least 2")
        if self.ensemble_size < 20:
            raise ParameterError(f"ensemble_size = {self.ensemble_size} must be at least 20")


@dataclass(frozen=True)
class FullCase:
    """One full-simulation benchmark: a compiled kernel and the same equations in Python.

    Attributes
    ----------
    name : str
        ``free_body`` or a model name.
    description : str
        What runs, for the table.
    kernel : Kernel
        The compiled right-hand side (no event: every integrator does the same work).
    y0 : ndarray
        Initial state.
    rhs : callable
        ``rhs(t, y)``, the model's right-hand side as Python calls it.
    """

    name: str
    description: str
    kernel: Kernel
    y0: FloatArray
    rhs: Callable[[float, FloatArray], FloatArray]


def _template(name: str) -> dict[str, Any]:
    """The default scenario of ``name`` (``tumble init``) as a dict."""
    return tomllib.loads(template(name))


def _eps_section(data: dict[str, Any]) -> dict[str, Any]:
    return data["perturbation"] if data["model"] == "nonlinear_moment" else data["parameters"]


def _end_key(data: dict[str, Any]) -> str:
    return "t_end" if "t_end" in data["run"] else "tau_end"


def _scenario_at(
    name: str, eps: float | None, t_end: float | None, samples: int, initial: dict | None = None
) -> Any:
    """The default scenario of model ``name`` at ``eps`` over its slow horizon (``t_end`` =
    template's ε·t_end / eps), or over ``t_end`` with ε scaled to keep that slow horizon;
    ``initial`` overrides keys of its ``[initial]``."""
    data = _template(name)
    data["initial"].update(initial or {})
    return parse_scenario(at_eps(data, eps, t_end, samples), f"<{name} template>").request


def at_eps(
    data: dict[str, Any], eps: float | None, t_end: float | None, samples: int
) -> dict[str, Any]:
    """The scenario ``data`` (changed in place and returned) at ``eps`` over its slow horizon
    (``t_end`` = its ε·t_end / eps), or over ``t_end`` with ε scaled to keep that horizon, with
    ``samples`` samples."""
    sec, key = _eps_section(data), _end_key(data)
    slow = sec["eps"] * data["run"][key]
    if eps is None:
        assert t_end is not None
        eps = slow / t_end
    sec["eps"] = eps
    data["run"][key] = slow / eps if t_end is None else t_end
    data["run"]["samples"] = samples
    return data


# The rotating-field template's transient (regime x1, k² = 0.5) nears the separatrix within
# its slow horizon, where neighbouring solutions part exponentially: at 1e5 time units rtol
# 1e-10 keeps no digit of the final state (measured error 1.6), and no "equal error" exists.
# The x3 regime of the same body and field stays regular (error 2e-4 at rtol 1e-10).
_FULL_INITIAL = {"rotating_field": {"regime": "x3"}}


def _python_rhs(rhs: Callable[..., Any], p: Any) -> Callable[[float, FloatArray], FloatArray]:
    """A model's ``rhs(t, y, p)`` as the ``fun(t, y)`` scipy integrates."""

    def fun(t: float, y: FloatArray) -> FloatArray:
        return np.asarray(rhs(t, y, p))

    return fun


def _overrides(name: str) -> str:
    changed = _FULL_INITIAL.get(name, {})
    return "".join(f" ({k} = {v})" for k, v in changed.items())


def full_cases(horizon: float) -> list[FullCase]:
    """The full-simulation cases over ``horizon`` time units.

    The free triaxial body I = (1, 2, 3), ω0 = (0.3, 1, 0.2) (a tumbling motion about the
    smallest axis, k² ≈ 0.12); then each model's default scenario with ε = (template's
    ε·t_end)/horizon, so that the run covers the template's slow horizon (the rotating field
    from its x3 regime, see ``_FULL_INITIAL``).
    """
    inertia = np.array([1.0, 2.0, 3.0])
    free = rigid_body_kernel(inertia, None)
    assert free is not None
    cases = [
        FullCase(
            "free_body",
            "free triaxial body I = (1, 2, 3), ω0 = (0.3, 1, 0.2)",
            free,
            np.array([0.3, 1.0, 0.2, 1.0, 0.0, 0.0, 0.0]),
            lambda t, y: rigid_body_rhs(t, y, inertia, None),
        )
    ]
    for name in FULL_MODELS:
        req = _scenario_at(name, None, horizon, 2, _FULL_INITIAL.get(name))
        full, p = req.model.full.form(), req.params
        assert full.kernel is not None
        kernel = full.kernel(p)
        assert kernel is not None  # the templates hold no Python functions
        cases.append(
            FullCase(
                name,
                f"{name} template{_overrides(name)}, {full.name} form {full.equation}, "
                f"ε = {p.eps:.3g}",
                Kernel(kernel.kind, kernel.params),
                np.asarray(full.initial_state(p, req.initial), dtype=float),
                _python_rhs(full.rhs, p),
            )
        )
    return cases


SHORT_RUN_S = 0.2
"""A call shorter than this is repeated until the calls add up to it (at most
:data:`SHORT_RUN_CALLS` times): the best of three sub-millisecond calls on a shared machine
is mostly its noise."""
SHORT_RUN_CALLS = 1000


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """Best wall time of ``repeat`` calls of ``fn`` [s], or of as many more as fit in
    :data:`SHORT_RUN_S` for a short call; and the last result."""
    best, result, spent, calls = math.inf, None, 0.0, 0
    while calls < repeat or (spent < SHORT_RUN_S and calls < SHORT_RUN_CALLS):
        start = time.perf_counter()
        result = fn()
        elapsed = time.perf_counter() - start
        best, spent, calls = min(best, elapsed), spent + elapsed, calls + 1
    return best, result


def _error(y: Any, ref: FloatArray) -> float:
    """Largest component of y − ref relative to the largest of ref (at least 1)."""
    return float(np.max(np.abs(np.asarray(y) - ref)) / max(1.0, float(np.max(np.abs(ref)))))


def _compiled_final(case: FullCase, t_end: float, rtol: float, atol: float) -> Any:
    sol = dop853.solve(case.kernel, case.y0, t_end, rtol=rtol, atol=atol, record=False, dense=False)
    if sol.status != 0:
        raise IntegrationError(f"bench {case.name}: {sol.message} at t = {sol.t:g}")
    return sol


def _scipy_part(case: FullCase, s: BenchSettings, log: Callable[[str], None]) -> dict[str, Any]:
    """Compiled DOP853 against scipy's DOP853 calling the right-hand side from Python, both measured
    against the compiled DOP853 at rtol REFERENCE_RTOL."""
    T = s.horizon
    log(f"full {case.name}: compiled DOP853")
    tumble_s, sol = _best(lambda: _compiled_final(case, T, s.rtol, s.atol), s.repeat)
    ref = _compiled_final(case, T, REFERENCE_RTOL, REFERENCE_ATOL).y
    log(f"full {case.name}: scipy DOP853 calling the right-hand side from Python")
    start = time.perf_counter()
    sp = solve_ivp(case.rhs, (0.0, T), case.y0, method="DOP853", rtol=s.rtol, atol=s.atol)
    scipy_s = time.perf_counter() - start
    if sp.status != 0:
        raise IntegrationError(f"bench {case.name}: scipy: {sp.message}")
    return {
        "description": case.description,
        "speedup": scipy_s / tumble_s,
        "tumble_s": tumble_s,
        "tumble_error": _error(sol.y, ref),
        "nfev": sol.nfev,
        "scipy_s": scipy_s,
        "scipy_error": _error(sp.y[:, -1], ref),
        "scipy_nfev": int(sp.nfev),
        "reference": f"compiled DOP853 at rtol {REFERENCE_RTOL:g}",
    }


def _heyoka_run(system: Any, y0: FloatArray, t_end: float, tol: float, repeat: int) -> dict:
    """heyoka at ``tol``: its build time apart, the best of ``repeat`` propagations."""
    build, once = heyoka_peer.propagate(system, y0, t_end, tol)
    best, y = _best(once, repeat)
    return {"tol": tol, "time_s": best, "build_s": build, "y": y}


def _heyoka_part(
    case: FullCase, s: BenchSettings, log: Callable[[str], None]
) -> dict[str, Any] | None:
    """Compiled DOP853 against heyoka.py at equal error, both measured against heyoka at
    HEYOKA_REFERENCE_TOL; None when heyoka is missing or cannot express the case.

    The quadratic drag's w|w| is not analytic at w = 0, and a Taylor step across the kink is
    wrong by an amount its error control does not see (measured: heyoka's error stalls at
    5e-3 for tolerances 1e-6 … 1e-12 on the resisting-medium template). That case is compared
    without its quadratic drag.
    """
    note = ""
    kernel = case.kernel
    smooth = heyoka_peer.without_quadratic_drag(kernel)
    if smooth is not None:
        kernel, note = smooth, "without the quadratic drag (not analytic at ω_i = 0)"
        case = FullCase(case.name, f"{case.description}, {note}", kernel, case.y0, case.rhs)
    system = heyoka_peer.heyoka_system(kernel)
    if system is None:
        return None
    T = s.horizon
    log(f"full {case.name}: compiled DOP853 (heyoka comparison)")
    tumble_s, sol = _best(lambda: _compiled_final(case, T, s.rtol, s.atol), s.repeat)
    log(f"full {case.name}: heyoka reference at tol {HEYOKA_REFERENCE_TOL:g}")
    ref = _heyoka_run(system, case.y0, T, HEYOKA_REFERENCE_TOL, 1)["y"]
    # Two independent methods and transcriptions: their distance bounds the references' own
    # error and checks the heyoka system against the compiled kernel.
    agreement = _error(_compiled_final(case, T, REFERENCE_RTOL, REFERENCE_ATOL).y, ref)
    tumble_error = _error(sol.y, ref)
    ladder = []
    for tol in HEYOKA_LADDER:
        log(f"full {case.name}: heyoka at tol {tol:g}")
        rung = _heyoka_run(system, case.y0, T, tol, s.repeat)
        rung["error"] = _error(rung.pop("y"), ref)
        ladder.append(rung)
        if rung["error"] < 0.1 * tumble_error:
            break  # tumble's error is bracketed
    t_eq, bracketed = heyoka_peer.at_equal_error(ladder, tumble_error)
    return {
        "description": case.description,
        "ratio": tumble_s / t_eq,
        "tumble_s": tumble_s,
        "tumble_error": tumble_error,
        "heyoka_s_at_equal_error": t_eq,
        "bracketed": bracketed,
        "ladder": ladder,
        "reference": f"heyoka.py Taylor at tol {HEYOKA_REFERENCE_TOL:g}",
        "reference_agreement": agreement,
        "note": note,
    }


# ---------------------------------------------------------------------------------------------
# Averaged against full.

# Slow columns of a full run compared with the reference full run (the nonlinear-moment model
# measures its averaging error at the extrema of θ, which a full run does not predict).
_FULL_SLOW = {"nonlinear_moment": ("R", "G", "theta")}


def _relative(errors: dict[str, tuple[FloatArray, FloatArray]], ref: Any) -> dict[str, float]:
    """Largest error of each slow variable over the run, relative to the variable's largest
    value in the reference run (at least 1: angles in radians, momenta of order one)."""
    out = {}
    for v, (_, e) in errors.items():
        col = ref.columns.get(v, ref.columns.get("theta") if v.startswith("theta_") else None)
        scale = max(1.0, float(np.max(np.abs(col)))) if col is not None else 1.0
        out[v] = float(np.max(e)) / scale if e.size else 0.0
    return out


def _full_vs_full(model: Any, ref: Any, run: Any) -> dict[str, float]:
    names = _FULL_SLOW.get(model.name, model.averaged.compare if model.averaged else ())
    errors = {v: (ref.tau, np.abs(run.columns[v] - ref.columns[v])) for v in names}
    return _relative(errors, ref)


def _averaged_case(
    name: str,
    eps: float,
    s: BenchSettings,
    log: Callable[[str], None],
    averaging: str | None = None,
) -> dict[str, Any]:
    """Averaged (and closed form) against full for model ``name`` at ``eps``; ``averaging``
    overrides the scenario's ``[run] averaging`` ("numeric": the general engine)."""
    req = _scenario_at(name, eps, None, AVERAGED_SAMPLES)
    if averaging is not None:
        req = replace(req, averaging=replace(req.averaging, averaging=averaging))
    model, p, ini, tau = req.model, req.params, req.initial, req.tau

    def run(method: str, rtol: float, atol: float) -> Any:
        return simulate(model, p, ini, tau, method, rtol=rtol, atol=atol, averaging=req.averaging)

    def run_with(options: AveragingOptions) -> Any:
        return simulate(model, p, ini, tau, "averaged", rtol=s.rtol, atol=s.atol,
                        averaging=options)  # fmt: skip

    log(f"averaged {name} ε = {eps:g}: reference full run")
    ref = run("full", 1e-12, 1e-14)
    full_s, _ = _best(lambda: run("full", s.rtol, s.atol), s.repeat)
    out: dict[str, Any] = {
        "eps": eps,
        "t_end": float(tau[-1]),
        "slow_horizon": float(eps * tau[-1]),
        "full_s": full_s,
        "full_nfev": ref.nfev,
        "reference": "full, compiled DOP853 at rtol 1e-12",
    }
    for method in ("averaged", "closed_form"):
        if method not in model.methods:
            continue
        try:
            model.check(p, method)
        except ParameterError:
            continue  # e.g. the unperturbed closed form of a perturbed run
        log(f"averaged {name} ε = {eps:g}: {method}")
        m_s, traj = _best(functools.partial(run, method, s.rtol, s.atol), s.repeat)
        errors = _relative(slow_errors(model, p, ref, traj), ref)
        out[method] = {
            "time_s": m_s,
            "nfev": traj.nfev,
            "speedup": full_s / m_s,
            "error": max(errors.values()),
            "errors": errors,
        }
    out["eval_us"] = _eval_costs(req)
    out["full_equal_accuracy"] = _equal_accuracy(
        out["averaged"], run, model, ref, s, lambda r: log(f"{name} ε = {eps:g}: {r}")
    )
    out["averaged"]["nfev_ratio"] = ref.nfev / max(out["averaged"]["nfev"], 1)
    if 2 in model.averaged.orders and eps <= 1e-3:  # where the verdicts read it
        # The same at order 2: the mean state of the osculating start, F₁ + F₂, the osculating
        # variables rebuilt at the samples; the bands of resonances crossed on the full
        # equations where the model has them (a run of order 2 stops there otherwise).
        second = replace(req.averaging, order=2, hybrid=model.averaged.hybrid)
        log(f"averaged {name} ε = {eps:g}: order 2")
        order2 = functools.partial(run_with, second)
        try:
            m_s, traj = _best(order2, s.repeat)
        except IntegrationError as exc:
            out["averaged_order2"] = {"failed": str(exc), "hybrid": second.hybrid}
            return out
        errors = _relative(slow_errors(model, p, ref, traj), ref)
        entry = {"time_s": m_s, "nfev": traj.nfev, "speedup": full_s / m_s,
                 "error": max(errors.values()), "errors": errors,
                 "hybrid": second.hybrid}  # fmt: skip
        entry["full_equal_accuracy"] = _equal_accuracy(
            entry, run, model, ref, s, lambda r: log(f"{name}: order 2, {r}")
        )
        out["averaged_order2"] = entry
        out["eval_us"]["averaged_order2"] = _eval_order2(req)
    return out


def _equal_accuracy(
    entry: dict[str, Any],
    run: Callable[[str, float, float], Any],
    model: Any,
    ref: Any,
    s: BenchSettings,
    log: Callable[[str], None],
) -> dict[str, Any]:
    """The loosest full run whose slow error is at most ``entry``'s (an averaged run's); its
    speed-up written into ``entry``. Where not even the tightest full run of the ladder is as
    accurate, a full run of equal accuracy would be tighter still, and slower: its time is a
    bound (``speedup_equal_accuracy_at_least``)."""
    target = entry["error"]
    for rtol in FULL_LADDER:
        log(f"full at rtol {rtol:g}")
        t_s, traj = _best(functools.partial(run, "full", rtol, rtol * 1e-2), s.repeat)
        err = max(_full_vs_full(model, ref, traj).values())
        if err <= target:
            entry["speedup_equal_accuracy"] = t_s / entry["time_s"]
            return {"rtol": rtol, "time_s": t_s, "error": err}
    entry["speedup_equal_accuracy_at_least"] = t_s / entry["time_s"]
    return {"rtol": None, "tightest_rtol": rtol, "time_s": t_s, "error": err}


def _eval_us(
    kernel: Kernel | None, rhs: Callable[[float, FloatArray], Any], y: FloatArray
) -> float:
    """The cost of one evaluation of a right-hand side at ``y`` [µs]: in compiled code when
    ``kernel`` is given (as the compiled integrator calls it), else from Python."""
    if kernel is not None:
        evaluate_repeatedly(kernel.kind, 0.0, y, kernel.params, 1, 0.0)  # compiled, warm
        n, seconds = 1000, 0.0
        while seconds < EVAL_SECONDS:
            n *= 4
            start = time.perf_counter()
            evaluate_repeatedly(kernel.kind, 0.0, y, kernel.params, n, 0.0)
            seconds = time.perf_counter() - start
        return seconds / n * 1e6
    n, start = 0, time.perf_counter()
    while time.perf_counter() - start < EVAL_SECONDS:
        rhs(0.0, y)
        n += 1
    return (time.perf_counter() - start) / n * 1e6


def _eval_costs(req: Any) -> dict[str, float]:
    """One evaluation of the full and of the averaged right-hand side at the initial state,
    each as its run evaluates it (compiled or Python) [µs]."""
    model, p, ini = req.model, req.params, req.initial
    full = model.full.form()
    avg = model.averaged.form(p, ini, model.averaged.check(req.averaging))
    y_full, y_avg = full.initial_state(p, ini), avg.initial_state(p, ini)
    compiled = avg.kernel(p) if avg.kernel is not None else None
    return {
        "full": _eval_us(full.kernel(p) if full.kernel else None, _python_rhs(full.rhs, p), y_full),
        "averaged": _eval_us(compiled, _python_rhs(avg.rhs, p), y_avg),
    }


def _eval_order2(req: Any) -> float:
    """One evaluation of the order-2 averaged right-hand side at the initial mean state [µs]
    (Python: the torus grid, its FFTs and differences)."""
    model, p, ini = req.model, req.params, req.initial
    form = model.averaged.form(p, ini, replace(req.averaging, order=2))
    return _eval_us(None, _python_rhs(form.rhs, p), form.initial_state(p, ini))


# ---------------------------------------------------------------------------------------------
# Batches.


def _batch(s: BenchSettings, log: Callable[[str], None]) -> dict[str, Any]:
    """Throughput of solve_batch on the resisting-medium template (its own ε = 0.01 and
    τ_end = 400) from ``batch_size`` initial states spread over ρ and ϑ."""
    data = _template("resisting_medium")
    rng = np.random.default_rng(6)
    Y0, req = [], None
    for _ in range(s.batch_size):
        data["initial"]["rho"] = float(rng.uniform(0.2, 2.9))
        data["initial"]["theta"] = float(rng.uniform(0.3, 1.3))
        req = parse_scenario(data, "<resisting_medium template>").request
        Y0.append(req.model.full.form().initial_state(req.params, req.initial))
    assert req is not None
    compiled = req.model.full.form().kernel
    kernel = compiled(req.params) if compiled is not None else None
    assert kernel is not None  # the template's form is compiled
    t_end = float(req.tau[-1])
    P = np.tile(kernel.params, (s.batch_size, 1))
    Y0a = np.array(Y0)
    te = np.array([t_end])
    threads = sorted({1, 2, dop853.available_threads()})
    log("batch: compiling")
    dop853.solve_batch(kernel.kind, P[:2], Y0a[:2], 1.0, [1.0], rtol=s.rtol, atol=s.atol)
    rows: dict[str, Any] = {}
    last = None
    for n in threads:
        log(f"batch: {s.batch_size} trajectories on {n} thread(s)")
        best, res = _best(
            functools.partial(
                dop853.solve_batch,
                kernel.kind,
                P,
                Y0a,
                t_end,
                te,
                rtol=s.rtol,
                atol=s.atol,
                threads=n,
            ),
            s.repeat,
        )
        if np.any(res.status != 0):
            raise IntegrationError("bench batch: a trajectory failed")
        rows[str(n)] = {"time_s": best, "trajectories_per_s": s.batch_size / best}
        if last is not None:
            rows[str(n)]["identical_to_1_thread"] = bool(np.array_equal(res.y, last))
        else:
            last = res.y
    one = rows["1"]["trajectories_per_s"]
    for key, row in rows.items():
        row["efficiency"] = row["trajectories_per_s"] / (int(key) * one)
    # Error figure: the batch's final states against a tighter reference (every 16th).
    picks = range(0, s.batch_size, 16)
    ref = dop853.solve_batch(
        kernel.kind, P[picks], Y0a[picks], t_end, te, rtol=REFERENCE_RTOL, atol=REFERENCE_ATOL
    )
    err = max(_error(last[i, -1], ref.y[j, -1]) for j, i in enumerate(picks))  # type: ignore[index]
    return {
        "case": f"resisting_medium template, t_end = {t_end:g}, ε = {req.params.eps:g}",
        "size": s.batch_size,
        "rtol": s.rtol,
        "threads": rows,
        "error": err,
        "cores": os.cpu_count(),
    }


def _averaged_ensemble(name: str, s: BenchSettings, log: Callable[[str], None]) -> dict[str, Any]:
    """Averaged runs per second of an ensemble of ``s.ensemble_size`` initial states of the
    model's template at ε = 1e-3 (:func:`tumble.integrate.simulate_batch`, ``method =
    "averaged"``) on 1 and on all cores, against one :func:`simulate` per point."""
    rng = np.random.default_rng(8)
    reqs = []
    size = s.ensemble_size
    for _ in range(size):
        ranges = ENSEMBLE_INITIAL[name]
        initial = {key: float(rng.uniform(lo, hi)) for key, (lo, hi) in ranges.items()}
        reqs.append(_scenario_at(name, 1e-3, None, AVERAGED_SAMPLES, initial))
    first = reqs[0]
    params, initials = [r.params for r in reqs], [r.initial for r in reqs]

    def ensemble(threads: int) -> list[Any]:
        return simulate_batch(first.model, params, initials, first.tau, rtol=s.rtol,
                              atol=s.atol, method="averaged", averaging=first.averaging,
                              threads=threads)  # fmt: skip

    log(f"averaged ensemble {name}: compiling")
    simulate_batch(first.model, params[:2], initials[:2], first.tau, rtol=s.rtol, atol=s.atol,
                   method="averaged", averaging=first.averaging)  # fmt: skip
    rows: dict[str, Any] = {}
    for n in sorted({1, dop853.available_threads()}):
        log(f"averaged ensemble {name}: {size} runs on {n} thread(s)")
        best, out = _best(functools.partial(ensemble, n), s.repeat)
        failed = sum(not hasattr(o, "columns") for o in out)
        rows[str(n)] = {"time_s": best, "runs_per_s": size / best, "failed": failed}
    one = rows["1"]["runs_per_s"]
    for key, row in rows.items():
        row["efficiency"] = row["runs_per_s"] / (int(key) * one)
    log(f"averaged ensemble {name}: one simulate() per point")
    subset = range(0, size, 10)

    def singles() -> None:
        for i in subset:
            with contextlib.suppress(TumbleError):
                simulate(first.model, params[i], initials[i], first.tau, "averaged",
                         rtol=s.rtol, atol=s.atol, averaging=first.averaging)  # fmt: skip

    single_s, _ = _best(singles, s.repeat)
    return {
        "case": f"{name} template at ε = 0.001, initial "
        + ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in ENSEMBLE_INITIAL[name].items()),
        "size": size,
        "threads": rows,
        "single_runs_per_s": len(subset) / single_s,
        "cores": os.cpu_count(),
    }


def run_benchmark(
    settings: BenchSettings | None = None,
    log: Callable[[str], None] | None = None,
) -> dict[str, Any]:
    """Measure every figure of the benchmark on this machine.

    Parameters
    ----------
    settings : BenchSettings, optional
        Horizon, tolerances, repeats and which studies run (default: the standard ones).
    log : callable, optional
        Called with a short description of each step as it starts (a progress display).

    Returns
    -------
    dict
        JSON-ready: ``machine``, ``settings``, ``targets``, ``full_speedup_vs_scipy``,
        ``full_time_ratio_vs_heyoka``, ``averaged_speedup``, ``engine_speedup``,
        ``batch_throughput``, ``averaged_batch_throughput``, ``compile`` and ``verdicts``
        (each target: the figure, the target and whether it is met). Times in seconds; errors
        relative (see the module docstring).
    """
    s = settings or BenchSettings()
    say = log or (lambda _msg: None)
    result: dict[str, Any] = {
        "machine": machine(),
        "settings": {k: getattr(s, k) for k in BenchSettings.__dataclass_fields__},
        "targets": dict(TARGETS),
    }
    if s.startup:
        result["startup_s"] = startup_times(say)
    if s.compile:
        result["compile"] = compile_times(say)
    cases = full_cases(s.horizon)
    say("warming the compiled kernels")
    for case in cases:
        _compiled_final(case, 1.0, s.rtol, s.atol)
    result["full_speedup_vs_scipy"] = (
        {case.name: _scipy_part(case, s, say) for case in cases} if s.scipy else None
    )
    heyoka = {}
    if s.heyoka and heyoka_peer.available() is not None:
        for case in cases:
            part = _heyoka_part(case, s, say)
            if part is not None:
                heyoka[case.name] = part
    result["full_time_ratio_vs_heyoka"] = heyoka or None
    result["averaged_speedup"] = {
        name: {f"{eps:g}": _averaged_case(name, eps, s, say) for eps in AVERAGED_EPS}
        for name in PAPER_MODELS
    }
    result["engine_speedup"] = (
        {
            label: {f"{eps:g}": _averaged_case(name, eps, s, say, averaging) for eps in ENGINE_EPS}
            for label, (name, averaging) in ENGINE_CASES.items()
        }
        if s.engine
        else None
    )
    result["batch_throughput"] = _batch(s, say)
    result["averaged_batch_throughput"] = {name: _averaged_ensemble(name, s, say)
                                           for name in PAPER_MODELS}  # fmt: skip
    if s.orbit:
        from tumble.app.bench_orbit import orbiting_study

        result["orbiting_body"] = orbiting_study(s.repeat, say)
        from tumble.app.bench_sunlight import sunlight_study

        result["orbiting_body"]["sunlight"] = sunlight_study(s.repeat, say)
    if s.crossings:
        from tumble.app.bench_crossings import capture_study, crossing_study

        result["crossings"] = crossing_study(s.repeat, say)
        result["capture"] = capture_study(say)
    result["verdicts"] = verdicts(result)
    return result
