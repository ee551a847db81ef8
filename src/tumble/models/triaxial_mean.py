"""The averaged equations of order 2 of a triaxial body in mean variables, as a model's
averaged form: shared by the torqued body and the rotating field, which differ only in their
torque, its time dependence, the columns they derive from (L_ξ, T) and their full state.

A hybrid run (``AveragingOptions.hybrid``) hands the resonance bands of the phases to the full
equations: the bands about k·ν = 0 for every harmonic k of the slow rates
(:func:`tumble.averaging.second_order.resonance_table`), among them those whose polhode
harmonics (k1, 0) meet the separatrix, where ν1 → 0; and, nearer the separatrix still, the
states whose polhode the torus grid cannot resolve. The full legs therefore carry the body
across the separatrix, and each return reads the torus it is on
(:meth:`~tumble.averaging.triaxial_second.TriaxialSystem.reorient`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.quadrature import AveragingError
from tumble.averaging.second_order import RESONANCE_WIDTHS, MeanSystem, nearest_resonance
from tumble.averaging.triaxial_second import TriaxialSystem
from tumble.models.base import AveragedForm, AveragingOptions, Columns, Crossing

__all__ = ["MEAN_SLOW", "BodyState", "triaxial_mean_form"]

BodyState = tuple[
    Callable[[float, FloatArray, FloatArray], FloatArray],
    Callable[[float, FloatArray], tuple[FloatArray, FloatArray]],
]
"""A model's full state from the body rate and the attitude and back:
``(to_full(t, ω, A) -> y, from_full(t, y) -> (ω, A))``, ω [rad/time] in body axes, A body →
inertial, at time t of the model's default full form."""

_CHUNK_TURNS = 20.0
"""A hybrid run's full leg checks the band after this many turns of the fastest phase."""

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
    body_state: BodyState,
) -> AveragedForm[Any, Any]:
    """The averaged equations of order ``options.order`` in mean variables (L̄_ξ, T̄) and the
    mean angle variables of the Euler–Poinsot motion (and the forcing phase)
    (:class:`tumble.averaging.triaxial_second.TriaxialSystem`), started from the mean state of
    the body rate ``omega`` and ``attitude`` at t = 0 (``options.initial = "osculating"``) or
    from them taken as mean; its columns are ``columns(L_ξ, T)`` of the osculating variables
    rebuilt at each time asked for, with ``L1_mean`` … ``T_mean`` beside them; with
    ``options.hybrid`` its resonance bands are crossed on the full equations (module notes),
    whose state ``body_state`` builds and reads."""
    system, x0, w0 = TriaxialSystem.through(inertia, torque, eps, omega, attitude, forcing_period)
    mean = MeanSystem(system.terms, w0.size, options.order, refuse=not options.hybrid)
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
        crossing=_bands(system, mean, x0, body_state) if options.hybrid else None,
    )


def _bands(
    system: TriaxialSystem, mean: MeanSystem, x0: FloatArray, body_state: BodyState
) -> Crossing:
    """The bands of a hybrid run (module notes): within ``RESONANCE_WIDTHS`` widths of a
    resonance, or where the torus grid cannot resolve the polhode (near the separatrix)."""
    mapping = mean.map()
    to_body, from_body = body_state
    inertia = system.inertia
    last: list[Any] = [None, {}]  # the last state's table: band and signed ask for it in turn

    def table(
        x: FloatArray, omega: FloatArray | None = None
    ) -> dict[tuple[int, ...], float] | None:
        # On the torus of the body rate ω (a full state's: past the separatrix it may be
        # either), or on the one the run is on now (a mean state's: asked along the run).
        key = (np.asarray(x[:4], dtype=float).tobytes(), None if omega is None else omega.tobytes())
        if last[0] != key:
            try:
                found: dict[tuple[int, ...], float] | None = system.resonances(math.inf, x[:4],
                                                                                omega)  # fmt: skip
            except AveragingError:  # no average on the grid: the separatrix is near
                found = None
            last[:] = [key, found]
        return last[1]  # type: ignore[no-any-return]

    def signed(z: FloatArray) -> dict[tuple[int, ...], float]:
        return dict(table(z) or {})

    def measure(x: FloatArray, omega: FloatArray | None = None) -> float:
        found = table(x, omega)
        if found is None:
            return -1.0
        return nearest_resonance(found)[0] / RESONANCE_WIDTHS - 1.0

    def slow_of(omega: FloatArray, A: FloatArray) -> FloatArray:
        return np.array([*(A @ (inertia * omega)), 0.5 * float(omega @ (inertia * omega))])

    def band_full(y: FloatArray) -> float:
        # Read at t = 0: the distances do not change when the body and its torque turn
        # together about the inertial axis a forcing turns about (a field's), which is all
        # that the time changes in a full state's attitude (the rotating field's frame).
        omega, A = from_body(0.0, y)
        return measure(slow_of(omega, A), omega)

    def to_full(t: float, z: FloatArray) -> FloatArray:
        x, w = mapping.to_osculating(t, z[:4], z[4:])
        return to_body(t, *system.state_at(x, w))

    def to_mean(t: float, y: FloatArray, z_entry: FloatArray) -> FloatArray:
        omega, A = from_body(t, y)
        x = slow_of(omega, A)
        system.reorient(t, x, omega)
        w = system.phases_of(x, omega, A)
        if system.period:  # the forcing phase, 0 at t = 0
            w[2] = 2.0 * math.pi * t / system.period
        y_mean, psi = mapping.to_mean(t, x, w)
        return np.concatenate([y_mean, psi])

    chunk = _CHUNK_TURNS * 2.0 * math.pi / float(np.max(np.abs(system.frequencies(x0))))
    return Crossing(measure, band_full, to_full, to_mean, "a resonance of the Euler–Poinsot "
                    "phases (and the forcing)", chunk, signed)  # fmt: skip
