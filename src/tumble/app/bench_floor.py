"""What bounds an averaged run's speed-up on the benchmark's short cases: its compiled work
against the time the target allows.

A target of N× asks an averaged run to take at most 1/N of the full run's time: the budget.
Each case here times, in one process, with the full run's tolerances (rtol 1e-10, atol 1e-12):

* the full run and the default averaged run, as the benchmark times them
  (:func:`tumble.integrate.simulate`, the best of calls adding up to 0.2 s);
* the averaged run's evaluations: their count times the cost of one, in compiled code, at the
  initial state. No integration of these equations at this tolerance with this method costs
  less;
* the averaged equations' integration with the least Python: the same pieces, stops and
  restarts as the run, each piece one call of the compiled DOP853 with its samples
  interpolated in the loop, and no columns, no form, no Trajectory (its calls' own Python,
  tens of µs each, included);
* the columns of the samples (the form's ``to_columns``, compiled where the model has it).

The floor is the evaluations plus the columns. Where it alone exceeds the budget, the target
is out of reach of the method at that tolerance, whatever the Python around it; where it fills
most of the budget, the target asks for a run with almost no Python. ``benchmarks/
averaged_floor.py`` runs the study and writes the table of the performance page.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from tumble._typing import FloatArray

__all__ = ["ATOL", "CASES", "RTOL", "floor_study", "markdown", "over_budget"]

RTOL, ATOL = 1e-10, 1e-12
"""The tolerances of the benchmark's speed-ups, for the full and the averaged runs alike."""

CASES: tuple[tuple[str, str, float, float], ...] = (
    ("template", "rotating_field", 1e-3, 100.0),
    ("template", "rotating_field", 1e-4, 1000.0),
    ("template", "nonlinear_moment", 1e-3, 100.0),
    ("template", "nonlinear_moment", 1e-4, 1000.0),
    ("crossing", "a3_negative", 1e-4, 300.0),
    ("crossing", "rf_transient_x1", 1e-4, 300.0),
    ("crossing", "tb_damper_crossing", 1e-4, 300.0),
)
"""(source, name, ε, target speed-up): a paper model's template at the benchmark's ε
(:func:`tumble.app.bench._averaged_case`), or a crossing example
(:func:`tumble.app.bench_crossings.request_at`)."""


def _request(source: str, name: str, eps: float) -> Any:
    if source == "template":
        from tumble.app.bench import AVERAGED_SAMPLES, _scenario_at

        return _scenario_at(name, eps, None, AVERAGED_SAMPLES)
    from tumble.app.bench_crossings import request_at

    return request_at(name, eps)


def _pieces(avg: Any, kernel: Any, y0: FloatArray, tau: FloatArray) -> Callable[[], Any]:
    """The averaged run's compiled integration alone, as a function returning (samples,
    evaluations): the stops and the surface of :func:`tumble.integrate.ode.compiled_plan`, each
    piece one :func:`tumble.integrate.dop853.solve` with its samples (from its own starting
    step, where the streamed run carries the last one over), and the restarts of
    :func:`tumble.integrate.replay.stream`."""
    from tumble.integrate import dop853
    from tumble.integrate.ode import compiled_plan, restart_at

    t_end = float(tau[-1])

    def run() -> tuple[FloatArray, int]:
        stops, surface = compiled_plan(kernel, avg.breakpoints, y0, t_end, "floor")
        Y = np.full((tau.size, y0.size), np.nan)
        t0, y, nfev = 0.0, y0, 0
        for stop in stops:
            while True:
                watched = replace(kernel, event=surface.event, terminal=True) if surface else kernel
                rows = np.flatnonzero((tau >= t0) & (tau <= stop))
                sol = dop853.solve(watched, y, stop, t0=t0, rtol=RTOL, atol=ATOL,
                                   t_eval=tau[rows], record=False, dense=False)  # fmt: skip
                nfev += sol.nfev
                if sol.status not in (0, dop853.STOPPED):
                    raise RuntimeError(f"floor: {sol.message} at t = {sol.t:g}")
                done = rows[: sol.y_eval.shape[0]]
                kept = np.isfinite(sol.y_eval[:, 0])
                Y[done[kept]] = sol.y_eval[kept]
                t0, y = float(sol.t), sol.y
                if sol.status != dop853.STOPPED:
                    break
                assert surface is not None
                if surface.restart is not None:
                    y = np.asarray(surface.restart(t0, y), dtype=float)
                surface = None  # crossed at most once
            if t0 >= t_end:
                break
            y = restart_at(avg.breakpoints, t0, y)
        return Y, nfev

    return run


def _case(source: str, name: str, eps: float, target: float, repeat: int) -> dict[str, Any]:
    from tumble.app.bench import _best, _eval_us
    from tumble.integrate import simulate
    from tumble.integrate.simulate import integrator_named

    req = _request(source, name, eps)
    model, p, st, tau = req.model, req.params, req.initial, req.tau

    def run(method: str) -> Any:
        return simulate(model, p, st, tau, method, rtol=RTOL, atol=ATOL, averaging=req.averaging)

    full_s, _ = _best(lambda: run("full"), repeat)
    averaged_s, traj = _best(lambda: run("averaged"), repeat)
    avg = model.averaged.form(p, st, model.averaged.check(req.averaging))
    kernel = integrator_named("auto").averaged_kernel(avg, p)
    if kernel is None:
        raise RuntimeError(f"floor: the averaged form of {name} has no compiled kernel")
    y0 = np.asarray(avg.initial_state(p, st), dtype=float)
    integration_s, (Y, nfev) = _best(_pieces(avg, kernel, y0, tau), repeat)
    columns_s, _ = _best(lambda: avg.to_columns(p, st, tau, Y), repeat)
    budget_s = full_s / target
    eval_us = _eval_us(kernel, lambda t, y: None, y0)
    evaluations_s = traj.nfev * eval_us * 1e-6
    floor_s = evaluations_s + columns_s
    return {
        "source": source,
        "eps": eps,
        "target": target,
        "samples": int(tau.size),
        "full_s": full_s,
        "averaged_s": averaged_s,
        "speedup": full_s / averaged_s,
        "budget_s": budget_s,
        "integration_s": integration_s,
        "integration_nfev": nfev,
        "run_nfev": int(traj.nfev),
        "eval_us": eval_us,
        "evaluations_s": evaluations_s,
        "columns_s": columns_s,
        "floor_s": floor_s,
        "floor_over_budget": floor_s / budget_s,
        "rest_s": averaged_s - floor_s,
    }


def floor_study(repeat: int, log: Callable[[str], None]) -> dict[str, Any]:
    """Every case of :data:`CASES`, keyed by name and ε; JSON-ready."""
    out: dict[str, Any] = {}
    for source, name, eps, target in CASES:
        log(f"floor: {name} at ε = {eps:g}")
        out.setdefault(name, {})[f"{eps:g}"] = _case(source, name, eps, target, repeat)
    return out


def markdown(result: dict[str, Any]) -> str:
    """The study as the performance page's table."""
    from tumble.app.bench_crossings import study_table

    def ms(seconds: float) -> str:
        return f"{1e3 * seconds:.3g}"

    head = ("| case | ε | target | full [ms] | budget [ms] | averaged [ms] | evaluations [ms] "
            "(count × µs) | integration [ms] | columns [ms] | floor / budget |",
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")  # fmt: skip
    return study_table(head, result, lambda name, key, r: (
        f"| {name} ({r['source']}) | {key} | {r['target']:.0f}× | {ms(r['full_s'])} | "
        f"{ms(r['budget_s'])} | {ms(r['averaged_s'])} | {ms(r['evaluations_s'])} "
        f"({r['run_nfev']} × {r['eval_us']:.2g}) | {ms(r['integration_s'])} | "
        f"{ms(r['columns_s'])} | {r['floor_over_budget']:.2f} |"))  # fmt: skip


def over_budget(result: dict[str, Any]) -> list[str]:
    """The cases whose floor (evaluations and columns) alone exceeds their budget."""
    return [f"{name} at ε = {key}" for name, by_eps in result.items()
            for key, r in by_eps.items() if r["floor_over_budget"] > 1.0]  # fmt: skip
