"""Comparisons between methods: differences of trajectories and the averaging error study."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from tumble._typing import ArrayLike, FloatArray
from tumble.integrate import DEFAULT_ATOL, DEFAULT_RTOL, simulate
from tumble.models import AnyModel

__all__ = [
    "ErrorStudy",
    "angle_difference",
    "averaging_error_study",
    "fitted_order",
    "max_differences",
]


def angle_difference(x: FloatArray, y: FloatArray) -> FloatArray:
    """x − y wrapped to (−π, π] [rad]: angles compared modulo 2π
    (docs/theory/resisting-medium.md §14)."""
    return np.angle(np.exp(1j * (np.asarray(x) - np.asarray(y))))


def max_differences(a: xr.Dataset, b: xr.Dataset) -> dict[str, float]:
    """Maximum |a − b| over the sample times, for every variable the two datasets share.

    Variables whose ``attrs["angle"]`` is true are compared modulo 2π.
    """
    out: dict[str, float] = {}
    for name in a.data_vars:
        if name not in b.data_vars:
            continue
        x, y = a[name].values, b[name].values
        d = angle_difference(x, y) if a[name].attrs.get("angle") else x - y
        out[str(name)] = float(np.max(np.abs(d))) if d.size else 0.0
    return out


def fitted_order(eps: ArrayLike, err: ArrayLike) -> float:
    """Slope of log(err) against log(ε), least squares: the measured order of accuracy."""
    return float(np.polyfit(np.log(np.asarray(eps)), np.log(np.asarray(err)), 1)[0])


@dataclass(frozen=True)
class ErrorStudy:
    """Max |full − averaged| per variable at each ε, and the fitted orders."""

    eps: FloatArray
    errors: dict[str, FloatArray]
    slopes: dict[str, float]


def averaging_error_study(
    model: AnyModel,
    p: Any,
    initial: Any,
    eps_values: Sequence[float],
    *,
    slow_time: float = 2.0,
    variables: Sequence[str] = ("k", "theta"),
    samples: int = 2001,
    reference: str = "closed_form",
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
) -> ErrorStudy:
    """Averaged-vs-full error over τ ∈ [0, slow_time/ε] for each ε, and its fitted order.

    The error is the maximum over ``samples`` equally spaced times of the instantaneous
    difference (the full solution keeps its O(ε) oscillation; nothing is smoothed).

    Parameters
    ----------
    model : Model
        The model; ``p.with_eps(eps)`` must give its parameters at another ε.
    p, initial : model Params and State
        Parameters (their ε is replaced) and the common initial state.
    eps_values : sequence of float
        Values of ε.
    slow_time : float
        Horizon in slow time ε τ [1].
    variables : sequence of str
        Columns to compare.
    samples : int
        Sample times per run.
    reference : {"closed_form", "averaged"}
        Which description of the averaged motion to compare with the full one.
    rtol, atol : float
        Tolerances of the full integration.
    """
    eps_arr = np.asarray(eps_values, dtype=float)
    errors: dict[str, list[float]] = {v: [] for v in variables}
    for eps in eps_arr:
        pe = p.with_eps(float(eps))
        tau = np.linspace(0.0, slow_time / eps, samples)
        full = simulate(model, pe, initial, tau, "full", rtol=rtol, atol=atol)
        avg = simulate(model, pe, initial, tau, reference, rtol=rtol, atol=atol)
        for v in variables:
            errors[v].append(float(np.max(np.abs(full.columns[v] - avg.columns[v]))))
    err = {v: np.array(e) for v, e in errors.items()}
    return ErrorStudy(eps_arr, err, {v: fitted_order(eps_arr, e) for v, e in err.items()})
