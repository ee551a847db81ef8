"""What an integration accepts, without the integrators: the checks a scenario's ``[run]``
table is validated with before any numerics load."""

from __future__ import annotations

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
    if not np.all(np.isfinite(t)) or t[0] < 0.0:
        raise ParameterError(f"{field} must contain finite times ≥ 0")
    if np.any(np.diff(t) <= 0.0):
        i = int(np.flatnonzero(np.diff(t) <= 0.0)[0])
        raise ParameterError(
            f"{field} must be strictly ascending, but {field}[{i + 1}] = {t[i + 1]:g} "
            f"follows {t[i]:g}"
        )
    return t
