"""What an integration accepts, without the integrators: the checks a scenario's ``[run]``
table is validated with before any numerics load."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = [
    "BUDGET_MARGIN",
    "FIRST_CHUNK",
    "MAX_STEPS",
    "SPEEDING_UP",
    "USER_CODE_TIMEOUT_S",
    "check_times",
    "pace_message",
    "user_code_timeout",
    "user_code_wait",
]

MAX_STEPS = 100_000_000
"""Default step budget of a full run (``[run] max_steps``): about a minute or two of the
compiled integrator, beyond which a run is stopped with an error naming the key rather than
left to run for hours (a stiff or mistyped input)."""

USER_CODE_TIMEOUT_S = 60.0
"""Default of ``[run] user_code_timeout`` [s]: how long a user's torque function may run
without returning before the run is stopped (:mod:`tumble.app.guard`); the integrators call it
thousands of times a second."""

_USER_CODE_WAIT = [USER_CODE_TIMEOUT_S]


def user_code_wait() -> float:
    """How long a user's compiled torque may go without returning before the compiled run
    that calls it is stopped [s] (:meth:`tumble.integrate.dop853.Integration.advance`):
    ``run.user_code_timeout`` inside :func:`user_code_timeout`, its default elsewhere (a
    notebook's :func:`~tumble.integrate.simulate`)."""
    return _USER_CODE_WAIT[0]


@contextlib.contextmanager
def user_code_timeout(seconds: float) -> Iterator[None]:
    """Set :func:`user_code_wait` to ``seconds`` for the block."""
    previous = _USER_CODE_WAIT[0]
    _USER_CODE_WAIT[0] = float(seconds)
    try:
        yield
    finally:
        _USER_CODE_WAIT[0] = previous


BUDGET_MARGIN = 100.0
"""A run is refused early when, at its current step size, the rest would take more than this
many times its remaining step budget: steps grow, but not by a hundredfold on average."""

SPEEDING_UP = 1.5
"""A run whose steps per unit time (1/h) are this many times their mean so far is speeding up
(its rate has at least tripled, were it growing linearly): the steps it has left are then
estimated with that growth carried on, not at today's pace alone. Well above the scatter of a
chunk's mean step against the run's (a nutation, an orbit: a few per cent over 20 000 steps)."""

FIRST_CHUNK = 1000
"""Steps a compiled run of averaged equations takes before its pace is first checked (then
twice as many each time): their right-hand sides may cost microseconds (the engine's
quadratures), so a hopeless run is refused within a fraction of a second, not after its
whole budget."""


def pace_message(
    t: float,
    t_end: float,
    h_abs: float,
    steps_left: int,
    max_steps: int,
    *,
    h_mean: float | None = None,
) -> str:
    """Why a run at time t with step ``h_abs`` is refused, or "" if its pace can still reach
    ``t_end`` within a margin of the ``steps_left`` of its budget.

    The margin is :data:`BUDGET_MARGIN` unless ``h_mean``, the mean step so far, is given:
    then the run is credited only with the growth its steps have shown, a margin of
    ``h_abs / h_mean`` clipped to 1 … :data:`BUDGET_MARGIN`. A motion that keeps its pace
    (a fast spin) or speeds up (a body spun up by a torque) has no growth to come, and would
    otherwise run its whole budget, minutes of an expensive right-hand side, before failing.
    A run speeding up (:data:`SPEEDING_UP`) is judged with its rate 1/h taken as linear in
    time, a + b t: its mean over [0, t] is a + b t/2 = 1/h_mean and its value now 1/h_abs,
    so that the steps left are (t_end − t)/h_abs + b (t_end − t)²/2.
    """
    ahead = (t_end - t) / max(h_abs, 1e-300)
    margin = BUDGET_MARGIN
    if h_mean is not None and h_mean > 0.0:
        margin = min(max(h_abs / h_mean, 1.0), BUDGET_MARGIN)
        if t > 0.0 and h_mean >= SPEEDING_UP * h_abs:
            b = 2.0 * (1.0 / max(h_abs, 1e-300) - 1.0 / h_mean) / t
            ahead += 0.5 * b * (t_end - t) ** 2
    if ahead <= margin * steps_left:
        return ""
    return (
        f"at t = {t:.6g} the step is {h_abs:.3g}, so the run to {t_end:.6g} needs about "
        f"{ahead:.2g} more steps, far beyond run.max_steps = {max_steps} (shorten the run, or "
        "check the input: a very fast or stiff motion)"
    )


def check_times(tau: ArrayLike, *, field: str = "run.tau") -> FloatArray:
    """Validate sample times: finite, ≥ 0, strictly ascending; return them as an array."""
    t = np.asarray(tau, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ParameterError(f"{field} must be a non-empty list of times")
    # The usual case in one pass: ascending from t[0] ≥ 0 to a finite end means every time is
    # finite (a NaN fails every comparison); anything else goes through the checks below.
    if t[0] >= 0.0 and math.isfinite(t[-1]) and (t.size == 1 or bool((t[1:] > t[:-1]).all())):
        return t
    if not np.all(np.isfinite(t)) or t[0] < 0.0:
        raise ParameterError(f"{field} must contain finite times ≥ 0")
    if np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
        raise ParameterError(
            f"{field} must be strictly ascending, but {field}[{i + 1}] = {t[i + 1]:g} "
            f"follows {t[i]:g}"
        )
    return t
