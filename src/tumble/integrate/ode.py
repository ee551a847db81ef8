"""Adaptive integration with dense output (scipy's DOP853), and honest failure reports."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError

__all__ = ["DEFAULT_ATOL", "DEFAULT_RTOL", "DenseSolution", "check_times", "integrate"]

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


def integrate(
    rhs: Callable[[float, FloatArray], FloatArray],
    y0: ArrayLike,
    t_end: float,
    *,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    what: str = "the equations of motion",
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
    with np.errstate(divide="raise", over="raise", invalid="raise"):
        try:
            res = solve_ivp(
                rhs, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True
            )
        except FloatingPointError as exc:
            raise IntegrationError(
                f"{what}: arithmetic failure during integration ({exc})"
            ) from None
    if res.status < 0 or not np.all(np.isfinite(res.y)):
        t_fail = float(res.t[-1]) if res.t.size else 0.0
        raise IntegrationError(f"{what}: integration failed at t = {t_fail:.6g}: {res.message}")
    return DenseSolution(np.asarray(res.t), int(res.nfev), res.sol)
