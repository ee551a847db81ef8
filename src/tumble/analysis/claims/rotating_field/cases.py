"""The rotating field's cases shared by its claims: the body of theory §15 and the transient
of §12 (Yu. G. Martynenko 1979; docs/theory/rotating-field.md)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from tumble.analysis.claims.common import cache_per_scale, quiet
from tumble.integrate import simulate
from tumble.models import rotating_field as rf

RF = "rotating_field"
RF_BODY = (1.0, 1.6, 2.2)
"""A triaxial body, I1 < I2 < I3, away from the thin plate (I1 + I2 − I3 = 0.4)."""

XI3 = np.array([0.0, 0.0, 1.0])


def params(inertia: Sequence[float], beta: float, eps: float) -> rf.Params:
    """``rf.Params`` of the moments (I1, I2, I3) [inertia unit], field angle β [rad] and ε."""
    return rf.Params(np.asarray(inertia, dtype=float), beta, eps)


def transient() -> tuple[rf.Params, rf.State]:
    """The example of §12 / examples/rf_transient_x1.toml: from regime x1 through the
    separatrix into x3 (ε = 0.01, β = π/2, body (1, 2, 2.5))."""
    p = params((1.0, 2.0, 2.5), math.pi / 2, 0.01)
    return p, rf.state_from_elements(p, 1.5, 0.6, 0.0, 0.5, "x1")


@cache_per_scale
def transient_runs() -> tuple[np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The :func:`transient` over τ ≤ 300: its times and the full and averaged columns (shared
    by rf-13 and rf-18)."""
    p, st = transient()
    tau = np.linspace(0.0, 300.0, 601)
    full = quiet(simulate, rf.MODEL, p, st, tau, "full").columns
    avg = quiet(simulate, rf.MODEL, p, st, tau, "averaged").columns
    return tau, full, avg
