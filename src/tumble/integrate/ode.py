"""Adaptive integration with dense output (scipy's DOP853), and honest failure reports."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError
from tumble.models.base import Breakpoint

__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_RTOL",
    "DenseSolution",
    "check_times",
    "integrate",
]

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12


@dataclass(frozen=True)
class DenseSolution:
    """A solution that can be evaluated at any time in ``[t0, t_end]``.

    Attributes
    ----------
    ts : ndarray
        Times of the integrator's steps (for resolving phases between samples).
    nfev : int
        Right-hand-side evaluations.
    """

    ts: FloatArray
    nfev: int
    _sol: Any

    def __call__(self, t: ArrayLike) -> FloatArray:
        """States at times ``t``, shape (n, dim)."""
        return np.asarray(self._sol(np.asarray(t, dtype=float)), dtype=float).T


def check_times(tau: ArrayLike, *, field: str = "run.tau") -> FloatArray:
    """Validate sample times: finite, ≥ 0, strictly ascending; return them as an array."""
    t = np.asarray(tau, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ParameterError(f"{field} must be a non-empty list of times")
    if not np.all(np.isfinite(t)) or t[0] < 0.0:
        raise ParameterError(f"{field} must contain finite times ≥ 0")
    if np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
        raise ParameterError(
            f"{field} must be strictly ascending, but {field}[{i + 1}] = {t[i + 1]:g} "
            f"follows {t[i]:g}"
        )
    return t


class _Piecewise:
    """Dense output of consecutive segments [t_i, t_(i+1)] (restarts at breakpoints)."""

    def __init__(self, starts: list[float], sols: list[Any]) -> None:
        self.starts = np.asarray(starts[1:], dtype=float)
        self.sols = sols

    def __call__(self, t: FloatArray) -> FloatArray:
        t = np.atleast_1d(t)
        which = np.searchsorted(self.starts, t, side="right")
        out = np.empty((self.sols[0](t[:1]).shape[0], t.size))
        for i, sol in enumerate(self.sols):
            mask = which == i
            if np.any(mask):
                out[:, mask] = sol(t[mask])
        return out


def _event(g: Callable[[float, FloatArray], float]) -> Callable[[float, FloatArray], float]:
    def event(t: float, y: FloatArray) -> float:
        return g(t, y)

    event.terminal = True  # type: ignore[attr-defined]
    return event


def integrate(
    rhs: Callable[[float, FloatArray], FloatArray],
    y0: ArrayLike,
    t_end: float,
    *,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    what: str = "the equations of motion",
    breakpoints: Sequence[Breakpoint] = (),
) -> DenseSolution:
    """Integrate ``dy/dt = rhs(t, y)`` from t = 0 to ``t_end`` with DOP853 and dense output.

    Parameters
    ----------
    rhs : callable
        Right-hand side ``rhs(t, y) -> dy/dt``.
    y0 : array_like
        Initial state at t = 0.
    t_end : float
        Final time [the problem's time unit], ≥ 0.
    rtol, atol : float
        Relative and absolute local error tolerances.
    what : str
        Name of the system, for error messages.
    breakpoints : sequence of Breakpoint
        Surfaces the solution crosses at most once and where ``rhs`` is not smooth (e.g. a
        separatrix). The step is stopped exactly at the crossing and the integration restarts
        there (through the breakpoint's restart map), so no step straddles the non-smooth
        point.

    Raises
    ------
    IntegrationError
        If the solver fails or the solution stops being finite.
    """
    y0 = np.asarray(y0, dtype=float)
    if not np.all(np.isfinite(y0)):
        raise IntegrationError(f"{what}: the initial state is not finite: {y0}")
    if t_end == 0.0:
        return DenseSolution(np.array([0.0]), 0, lambda t: np.repeat(y0[:, None], np.size(t), 1))
    # A breakpoint the start sits on is already passed.
    pending = [b for b in breakpoints if b.condition(0.0, y0) != 0.0]
    starts, sols, steps, nfev = [0.0], [], [np.array([0.0])], 0
    t0, y = 0.0, y0
    while True:
        with np.errstate(divide="raise", over="raise", invalid="raise"):
            try:
                res = solve_ivp(
                    rhs,
                    (t0, t_end),
                    y,
                    method="DOP853",
                    rtol=rtol,
                    atol=atol,
                    dense_output=True,
                    events=[_event(b.condition) for b in pending] or None,
                )
            except FloatingPointError as exc:
                raise IntegrationError(
                    f"{what}: arithmetic failure during integration ({exc})"
                ) from None
        if res.status < 0 or not np.all(np.isfinite(res.y)):
            t_fail = float(res.t[-1]) if res.t.size else t0
            raise IntegrationError(f"{what}: integration failed at t = {t_fail:.6g}: {res.message}")
        sols.append(res.sol)
        steps.append(np.asarray(res.t[1:]))
        nfev += int(res.nfev)
        if res.status != 1:
            break
        fired = next(i for i, ev in enumerate(res.t_events) if ev.size)
        t0, y = float(res.t_events[fired][0]), np.asarray(res.y_events[fired][0])
        restart = pending.pop(fired).restart
        if restart is not None:
            y = np.asarray(restart(t0, y), dtype=float)
        if t0 >= t_end:
            break
        starts.append(t0)
    if len(sols) == 1:
        return DenseSolution(np.concatenate(steps), nfev, sols[0])
    return DenseSolution(np.unique(np.concatenate(steps)), nfev, _Piecewise(starts, sols))
