"""The nutation envelope of the nonlinear-moment model against the full motion: the
extrema of θ(t), the discrepancy of the averaged θmax, θmin at them, where averaging
loses accuracy (§10, §11), and the results a run reports.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.models.base import Json, Report, Sampled, SlowPath, ValidityIssue, first_time
from tumble.models.inputs.nonlinear_moment import Params, State
from tumble.models.nonlinear_moment.exact import limits

NEAR_SEPARATRIX = 1e-3
"""1 − k² below which an averaged run is warned that it nears a separatrix (§11)."""

EPS_PERIOD_LIMIT = 0.5
"""ε·T (slow time per nutation period) above which ε is not small enough for averaging."""


def extrema(traj: Sampled, p: Params) -> list[tuple[str, int, float, float, float, float]]:
    """Every local maximum and minimum of θ(t) of a full trajectory for 0 < t < t_end.

    A start at a turning point is not counted (§14). A compiled run located the zeros of
    θ' as it integrated (:data:`tumble.kernels.EVENT_THETA_DOT`); otherwise they are
    bracketed on the integrator's steps (subdivided four times, so no swing is missed) and
    refined on the dense output.

    Parameters
    ----------
    traj : Trajectory
        A ``full`` trajectory (``slow`` gives ``theta_dot``, ``theta``, ``R``, ``G``).
    p : Params

    Returns
    -------
    list of (kind, k, t, theta, R, G)
        ``kind`` "max" or "min", ``k`` counting from 1 within its kind.
    """
    t_end = float(traj.tau[-1])
    cols = traj.event_columns
    counts = {"max": 0, "min": 0}
    out = []
    for j in np.flatnonzero((traj.events > 0.0) & (traj.events < t_end)):
        kind = "max" if traj.event_signs[j] > 0.0 else "min"
        counts[kind] += 1
        out.append((kind, counts[kind], float(traj.events[j]), float(cols["theta"][j]),
                    float(cols["R"][j]), float(cols["G"][j])))  # fmt: skip
    return out


def envelope_discrepancy(
    rows: Sequence[tuple[str, int, float, float, float, float]], averaged: Any
) -> dict[str, Any]:
    """Discrepancy of the averaged envelope θmax(t), θmin(t) at the full solution's extrema.

    Parameters
    ----------
    rows : sequence
        Output of :func:`extrema`.
    averaged : Trajectory
        An ``averaged`` trajectory (``slow`` gives ``theta_max``, ``theta_min``).

    Returns
    -------
    dict
        ``max_relative`` max over maxima of |θ̄max(t_k) − θ_k|/θ_k [1], ``max_abs_theta_max``
        and ``max_abs_theta_min`` [rad], and the counts.
    """
    out: dict[str, Any] = {"n_max": 0, "n_min": 0}
    for kind in ("max", "min"):
        sel = [(r[2], r[3]) for r in rows if r[0] == kind]
        out[f"n_{kind}"] = len(sel)
        if not sel:
            out[f"max_abs_theta_{kind}"] = None
            continue
        t_k, th = (np.array(v) for v in zip(*sel, strict=True))
        env = averaged.slow(t_k)[f"theta_{kind}"]
        out[f"max_abs_theta_{kind}"] = float(np.max(np.abs(env - th)))
        if kind == "max":
            out["max_relative"] = float(np.max(np.abs(env - th) / th))
    out.setdefault("max_relative", None)
    return out


def validity(p: Params, st: State, slow: SlowPath, t_end: float) -> list[ValidityIssue]:
    """Where an averaged trajectory loses accuracy (§10, §11), with the first time.

    ``near_separatrix``: 1 − k² < ``NEAR_SEPARATRIX`` (the period grows like ln(1/(1 − k²))
    and averaging degrades before it fails at ``SEPARATRIX_TOL``). ``eps_not_small``: the slow
    time per nutation period ε·T exceeds ``EPS_PERIOD_LIMIT``. Both are the tool's judgement of
    the "≪" of §6–§7.

    Parameters
    ----------
    p : Params
    st : State
    slow : callable
        ``slow(t) -> columns`` of the averaged run (``k2``, ``period``).
    t_end : float
        End of the run [t].

    Returns
    -------
    list of ValidityIssue
    """
    if not p.perturbed:
        return []
    grid = np.linspace(0.0, t_end, 801)
    on_grid = slow(grid)  # one orbit per grid point, shared by both checks

    def cols(t: FloatArray) -> dict[str, FloatArray]:
        return on_grid if t is grid else slow(t)

    issues = []
    checks = (
        (
            "near_separatrix",
            lambda t: NEAR_SEPARATRIX - (1.0 - cols(t)["k2"]),
            f"the nutation nears a separatrix (1 − k² < {NEAR_SEPARATRIX:g}): the period "
            "grows without bound and averaging loses accuracy (§11)",
        ),
        (
            "eps_not_small",
            lambda t: p.eps * cols(t)["period"] - EPS_PERIOD_LIMIT,
            f"ε·T > {EPS_PERIOD_LIMIT:g}: the slow variables change noticeably within one "
            "nutation period, so averaging is not accurate (envelope error O(ε·T), §10)",
        ),
    )
    for name, cond, message in checks:
        t0 = first_time(cond, grid)
        if t0 is not None:
            issues.append(ValidityIssue(name, t0, f"{message}; first at t = {t0:.6g}"))
    return issues


def report(p: Params, st: State, trajectories: Mapping[str, Sampled]) -> Report:
    """Extrema table, envelope discrepancy and wall times (the scenario contract).

    Parameters
    ----------
    p : Params
    st : State
    trajectories : mapping
        Method → Trajectory.

    Returns
    -------
    Report
        Unperturbed: the orbit constants of :func:`limits` at the top of summary.json.
        Perturbed: ``full_extrema`` table, ``max_envelope_discrepancy`` (relative, θmax) with
        its details, and ``wall_time_s`` of each method.
    """
    summary: dict[str, Json] = {
        "wall_time_s": {m: float(t.wall_time) for m, t in trajectories.items()}
    }
    tables: dict[str, tuple[tuple[str, ...], list[tuple[Json, ...]]]] = {}
    if not p.perturbed:
        summary.update(limits(p, st))
        return Report(tables, summary)
    if "full" in trajectories:
        rows = extrema(trajectories["full"], p)
        tables["full_extrema"] = (("kind", "k", "t", "theta", "R", "G"), list(rows))
        if "averaged" in trajectories:
            env = envelope_discrepancy(rows, trajectories["averaged"])
            summary["max_envelope_discrepancy"] = env["max_relative"]
            summary["envelope"] = env
    summary["initial_orbit"] = limits(p, st)
    return Report(tables, summary)


def slow_errors(
    p: Params, full: Sampled, averaged: Sampled
) -> dict[str, tuple[FloatArray, FloatArray]]:
    """Averaging error of each slow variable, for ``tumble verify``.

    θmax and θmin: |θ̄ext(t_k) − θ_k| at the full solution's maxima and minima (the envelope
    (2.2) is what the averaged method predicts, §10); R and G: |full − averaged| at the
    sample times.

    Parameters
    ----------
    p : Params
    full, averaged : Trajectory
        Runs of the two methods on the same sample times.

    Returns
    -------
    dict
        Variable → (times [t], absolute errors [rad or 1/t]).
    """
    rows = extrema(full, p)
    out: dict[str, tuple[FloatArray, FloatArray]] = {}
    for kind in ("max", "min"):
        sel = [(r[2], r[3]) for r in rows if r[0] == kind]
        if sel:
            t_k, th = (np.array(v, dtype=float) for v in zip(*sel, strict=True))
            out[f"theta_{kind}"] = (t_k, np.abs(averaged.slow(t_k)[f"theta_{kind}"] - th))
    for name in ("R", "G"):
        out[name] = (full.tau, np.abs(full.columns[name] - averaged.columns[name]))
    return out


def _diagnostics(p: Params, st: State, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    return {k: cols[k] for k in ("k2", "period", "root_case", "E")}
