"""A run the compiled integrator's tests share: the same simulation on the compiled integrator
and on scipy's, each checked to have run where it was asked to (no silent fallback)."""

from __future__ import annotations

from typing import Any

import numpy as np

from tumble.integrate import simulate


def numba_and_scipy(
    model: Any, params: Any, state: Any, t: np.ndarray, method: str, **options: Any
) -> dict[str, Any]:
    """``{"numba": run, "scipy": run}``: :func:`tumble.integrate.simulate` of the same
    arguments (``options`` its keywords, without ``integrator``) on each integrator."""
    runs = {
        integrator: simulate(model, params, state, t, method, integrator=integrator, **options)
        for integrator in ("numba", "scipy")
    }
    assert runs["numba"].integrator == "numba" and runs["scipy"].integrator == "scipy"
    return runs
