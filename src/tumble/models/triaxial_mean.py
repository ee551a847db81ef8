"""The averaged equations of order 2 of a triaxial body in mean variables, as a model's
averaged form: shared by the torqued body and the rotating field, which differ only in their
torque, its time dependence and the columns they derive from (L_ξ, T)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.second_order import MeanSystem
from tumble.averaging.triaxial_second import TriaxialSystem
from tumble.models.base import AveragedForm, AveragingOptions, Columns

__all__ = ["MEAN_SLOW", "triaxial_mean_form"]

MEAN_SLOW = ("L1", "L2", "L3", "T")
"""The mean slow variables, written as the columns ``L1_mean`` … ``T_mean``."""


def triaxial_mean_form(
    torque: Callable[..., Any],
    inertia: FloatArray,
    eps: float,
    omega: FloatArray,
    attitude: FloatArray,
    forcing_period: float | None,
    options: AveragingOptions,
    columns: Callable[[FloatArray, FloatArray], Columns],
    equation: str,
) -> AveragedForm[Any, Any]:
    """The averaged equations of order ``options.order`` in mean variables (L̄_ξ, T̄) and the
    mean angle variables of the Euler–Poinsot motion (and the forcing phase)
    (:class:`tumble.averaging.triaxial_second.TriaxialSystem`), started from the mean state of
    the body rate ``omega`` and ``attitude`` at t = 0 (``options.initial = "osculating"``) or
    from them taken as mean; its columns are ``columns(L_ξ, T)`` of the osculating variables
    rebuilt at each time asked for, with ``L1_mean`` … ``T_mean`` beside them."""
    system, x0, w0 = TriaxialSystem.through(inertia, torque, eps, omega, attitude, forcing_period)
    mean = MeanSystem(system.terms, w0.size, options.order)
    guarded = mean.guarded()

    def initial_state(p: Any, st: Any) -> FloatArray:
        if options.initial == "mean":
            return np.concatenate([x0, w0])
        return mean.start(0.0, x0, w0)

    def to_columns(p: Any, st: Any, t: FloatArray, Y: FloatArray) -> Columns:
        Y = np.atleast_2d(Y)
        X, _ = mean.osculating(t, Y)
        cols = columns(X[:, :3], X[:, 3])
        cols |= {f"{name}_mean": Y[:, i] for i, name in enumerate(MEAN_SLOW)}
        return cols

    return AveragedForm(
        name=f"mean_order{options.order}",
        equation=f"{equation} averaged to order {options.order} in mean variables",
        slow=(*(f"{v}_mean" for v in MEAN_SLOW), *(f"w{i + 1}_mean" for i in range(w0.size))),
        rhs=lambda t, y, p: guarded(t, y),
        initial_state=initial_state,
        to_columns=to_columns,
    )
