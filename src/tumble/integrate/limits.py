"""What an integration accepts, without the integrators: the checks a scenario's ``[run]``
table is validated with before any numerics load."""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError

__all__ = ["MAX_STEPS", "check_times"]

MAX_STEPS = 100_000_000
"""Default step budget of a full run (``[run] max_steps``): about a minute or two of the
compiled integrator, beyond which a run is stopped with an error naming the key rather than
left to run for hours (a stiff or mistyped input)."""


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
