"""Hybrid runs: the averaged equations, with the bands where they fail handed to the full ones.

Averaging fails where a fast phase stops or two phases resonate: a resisting-medium body whose
proper rotation φ stops at ϑ = π/2, a polhode at its separatrix. There the averaged solution
is off by O(√ε) or worse, whatever its order. A hybrid run integrates the averaged equations
(in mean variables) until the state enters such a band (:class:`tumble.models.base.Crossing`),
rebuilds the osculating state and from it the full state, integrates the full equations
across the band, and re-enters the averaged equations through the osculating → mean map. Its
error is then that of the averaged legs and of the maps at the two hand-overs, the crossing
itself being exact (to the integration tolerance).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
from scipy.integrate import solve_ivp

from tumble._typing import FloatArray
from tumble.errors import IntegrationError
from tumble.integrate.limits import MAX_STEPS
from tumble.integrate.ode import DenseSolution, integrate
from tumble.kernels import Kernel
from tumble.models.base import AveragedForm, Columns, Crossing, FullForm

__all__ = ["HybridRun", "hybrid"]

P = TypeVar("P")
S = TypeVar("S")


@dataclass(frozen=True)
class _Leg:
    """One leg of a hybrid run: [t0, t1] on the averaged or the full equations."""

    kind: str  # "averaged" or "full"
    t0: float
    t1: float
    states: Callable[[FloatArray], FloatArray]  # t (absolute) → states, shape (n, dim)
    steps: FloatArray


@dataclass(frozen=True)
class HybridRun(Generic[P, S]):
    """A hybrid run's legs, with its columns anywhere in its span.

    Attributes
    ----------
    legs : list
        The legs in time order.
    nfev : int
        Right-hand-side evaluations of both kinds.
    handovers : list of tuple
        (time of entry into the band, time of return to the averaged equations).
    """

    avg: AveragedForm[P, S]
    full: FullForm[P, S]
    p: P
    initial: S
    legs: list[_Leg]
    nfev: int
    handovers: list[tuple[float, float]]

    @property
    def steps(self) -> FloatArray:
        """Step times of every leg."""
        return np.concatenate([leg.steps for leg in self.legs])

    def columns(self, t: FloatArray, osculating: bool = True) -> Columns:
        """Output columns at times ``t``: on averaged legs the mean columns and (with
        ``osculating``) the osculating ones rebuilt; on full legs the full form's columns, the
        mean ones NaN (no mean state exists inside the band)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        which = np.searchsorted([leg.t1 for leg in self.legs[:-1]], t, side="left")
        out: dict[str, FloatArray] = {}
        names: set[str] = set()  # the averaged legs' columns: the run's
        for i, leg in enumerate(self.legs):
            at = np.flatnonzero(which == i)
            if not at.size:
                continue
            Y = leg.states(t[at])
            if leg.kind == "averaged":
                cols = self.avg.to_columns(self.p, self.initial, t[at], Y)
                if osculating and self.avg.osculating is not None:
                    cols |= self.avg.osculating(self.p, self.initial, t[at], Y)
                names |= set(cols)
            else:
                cols = self.full.to_columns(self.p, t[at], Y)
            for name, values in cols.items():
                column = out.setdefault(name, np.full(t.size, math.nan))
                column[at] = values
        if not names:  # every time asked for is inside a band
            z = self.avg.initial_state(self.p, self.initial)
            names = set(self.avg.to_columns(self.p, self.initial, np.zeros(1), z[None, :]))
        return {name: out.get(name, np.full(t.size, math.nan)) for name in names}


def _averaged_leg(
    avg: AveragedForm[P, S],
    p: P,
    crossing: Crossing,
    t0: float,
    z: FloatArray,
    t_end: float,
    rtol: float,
    atol: float,
) -> tuple[_Leg, int, float | None, FloatArray]:
    """The averaged equations from (t0, z) until the band is entered or ``t_end``; the leg,
    its evaluations, the time of entry (None: not entered) and the state there."""

    def entered(t: float, y: FloatArray) -> float:
        return crossing.band(y)

    entered.terminal = True  # type: ignore[attr-defined]
    entered.direction = -1.0  # type: ignore[attr-defined]
    res = solve_ivp(lambda t, y: avg.rhs(t, y, p), (t0, t_end), z, method="DOP853",
                    rtol=rtol, atol=atol, dense_output=True, events=[entered])  # fmt: skip
    if res.status < 0 or not np.all(np.isfinite(res.y)):
        raise IntegrationError(
            f"hybrid run: the averaged equations failed at t = {float(res.t[-1]):.6g}: "
            f"{res.message}"
        )
    sol = res.sol

    def states(t: FloatArray) -> FloatArray:
        return np.asarray(sol(t), dtype=float).T

    t1 = float(res.t[-1])
    leg = _Leg("averaged", t0, t1, states, np.asarray(res.t[1:]))
    if res.status == 1:
        return leg, int(res.nfev), t1, np.asarray(res.y_events[0][0])
    return leg, int(res.nfev), None, np.asarray(res.y[:, -1])


def _full_leg(
    full: FullForm[P, S],
    p: P,
    kernel: Kernel | None,
    crossing: Crossing,
    t0: float,
    y: FloatArray,
    t_end: float,
    rtol: float,
    atol: float,
    max_steps: int,
) -> tuple[list[_Leg], int, float, FloatArray]:
    """The full equations from (t0, y) in chunks until the state has left the band (by
    ``Crossing.LEAVE``) or ``t_end``; the legs, evaluations, end time and state."""
    legs: list[_Leg] = []
    nfev, t = 0, t0
    while t < t_end:
        span = min(crossing.chunk, t_end - t)
        start = t

        def rhs(s: float, x: FloatArray, start: float = start) -> FloatArray:
            return full.rhs(start + s, x, p)

        sol: DenseSolution = integrate(rhs, y, span, rtol=rtol, atol=atol, kernel=kernel,
                                       what=f"hybrid run: the full equations {full.equation}",
                                       max_steps=max_steps)  # fmt: skip

        def states(s: FloatArray, sol: DenseSolution = sol, start: float = start) -> FloatArray:
            return sol(np.asarray(s) - start)

        legs.append(_Leg("full", start, start + span, states, start + sol.ts[1:]))
        nfev += sol.nfev
        y = sol(np.array([span]))[0]
        t = start + span
        if crossing.band_full(y) >= crossing.LEAVE:
            break
    return legs, nfev, t, y


def hybrid(
    avg: AveragedForm[P, S],
    full: FullForm[P, S],
    p: P,
    initial: S,
    t_end: float,
    rtol: float,
    atol: float,
    kernel: Kernel | None = None,
    max_steps: int = MAX_STEPS,
) -> HybridRun[P, S]:
    """Run the averaged form ``avg`` from ``initial`` to ``t_end``, crossing its band
    (``avg.crossing``) on the full form ``full`` (compiled when ``kernel`` is given).

    Raises
    ------
    IntegrationError
        A leg failed.
    """
    crossing = avg.crossing
    if crossing is None:
        raise IntegrationError(f"hybrid run: the averaged form {avg.name} has no band to cross")
    legs: list[_Leg] = []
    handovers: list[tuple[float, float]] = []
    nfev, t = 0, 0.0
    z = np.asarray(avg.initial_state(p, initial), dtype=float)
    inside = crossing.band(z) < 0.0
    y = crossing.to_full(0.0, z) if inside else z
    while t < t_end:
        if not inside:
            leg, n, entry, z = _averaged_leg(avg, p, crossing, t, z, t_end, rtol, atol)
            legs.append(leg)
            nfev += n
            if entry is None:
                break
            t = entry
            y = crossing.to_full(t, z)
        entry, z_entry = t, z
        if entry == 0.0 and inside:  # started inside the band: no mean state to continue
            z_entry = np.asarray(avg.initial_state(p, initial), dtype=float)
        chunks, n, t, y = _full_leg(full, p, kernel, crossing, t, y, t_end, rtol, atol, max_steps)
        legs += chunks
        nfev += n
        handovers.append((entry, t))
        if t >= t_end:
            break
        z = crossing.to_mean(t, y, z_entry)
        inside = False
    return HybridRun(avg, full, p, initial, legs, nfev, handovers)
