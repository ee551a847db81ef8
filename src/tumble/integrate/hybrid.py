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
from scipy.integrate import DOP853, OdeSolution
from scipy.optimize import brentq

from tumble._typing import FloatArray
from tumble.errors import IntegrationError
from tumble.integrate import dop853
from tumble.integrate.limits import MAX_STEPS
from tumble.integrate.ode import DenseSolution, compiled_dense, integrate
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
    def spans(self) -> tuple[tuple[str, float, float], ...]:
        """The legs as (kind, start, end), consecutive legs of one kind (a full crossing
        taken in chunks) merged."""
        out: list[tuple[str, float, float]] = []
        for leg in self.legs:
            if out and out[-1][0] == leg.kind:
                out[-1] = (leg.kind, out[-1][1], leg.t1)
            else:
                out.append((leg.kind, leg.t0, leg.t1))
        return tuple(out)

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
    its evaluations, the time of entry (None: not entered) and the state there.

    Stepped one step at a time (DOP853) with the band checked after each: at small ε a step
    of the averaged equations (∝ 1/ε) outlasts the crossing of a resonance band (∝ 1/√ε), so
    the band can be jumped between two checks; ``crossing.signed`` then changes sign over the
    step, and the edge is found inside it."""
    solver = DOP853(lambda t, y: avg.rhs(t, y, p), t0, z, t_end, rtol=rtol, atol=atol)
    times, pieces = [t0], []
    signs = crossing.signed(z) if crossing.signed is not None else {}
    outside = crossing.band(z) >= 0.0  # a leg re-entered by the map may start inside
    entry: float | None = None
    while solver.status == "running":
        message = solver.step()
        if solver.status == "failed" or not np.all(np.isfinite(solver.y)):
            raise IntegrationError(
                f"hybrid run: the averaged equations failed at t = {solver.t:.6g}: {message}"
            )
        piece = solver.dense_output()
        times.append(solver.t)
        pieces.append(piece)
        band_end = crossing.band(solver.y)
        if outside:
            entry = _entry(crossing, piece, solver.t_old, solver.t, band_end, signs)
            if entry is not None:
                break
        outside = outside or band_end >= 0.0
        if crossing.signed is not None:
            signs = crossing.signed(solver.y)
    sol = OdeSolution(times, pieces)

    def states(t: FloatArray) -> FloatArray:
        return np.asarray(sol(t), dtype=float).T

    t1 = times[-1] if entry is None else entry
    leg = _Leg("averaged", t0, t1, states, np.asarray(times[1:]))
    return leg, int(solver.nfev), entry, np.asarray(sol(t1), dtype=float)


def _entry(
    crossing: Crossing,
    piece: Callable[[float], FloatArray],
    t0: float,
    t1: float,
    band_end: float,
    before: dict[tuple[int, ...], float],
) -> float | None:
    """The time at which the step [t0, t1] (dense output ``piece``), started outside the band,
    enters it: where the band ends inside, or where a resonance whose signed distance changed
    sign over the step was crossed; None if neither."""
    xtol = 1e-9 * abs(t1 - t0) + 1e-300

    def band(t: float) -> float:
        return crossing.band(piece(t))

    if band_end < 0.0:
        return float(brentq(band, t0, t1, xtol=xtol))
    if crossing.signed is None:
        return None
    after = crossing.signed(piece(t1))
    jumped = [k for k, d in before.items() if k in after and d * after[k] < 0.0]
    if not jumped:
        return None

    def distance(t: float, k: tuple[int, ...]) -> float:
        table = crossing.signed(piece(t))  # type: ignore[misc]
        if k not in table:
            raise IntegrationError(
                f"hybrid run: the harmonic {k} of {crossing.label} vanished inside a step of "
                f"the averaged equations at t = {t:.6g}"
            )
        return table[k]

    # the first resonance crossed, then the band's edge before it
    centre = min(float(brentq(distance, t0, t1, args=(k,), xtol=xtol)) for k in jumped)
    return float(brentq(band, t0, centre, xtol=xtol))


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

        what = f"hybrid run: the full equations {full.equation}"
        if kernel is not None:  # at the leg's own times: a torque may depend on the time
            sol = compiled_dense(dop853.solve(kernel, y, start + span, t0=start, rtol=rtol,
                                              atol=atol), what)  # fmt: skip
            shift = 0.0
        else:

            def rhs(s: float, x: FloatArray, start: float = start) -> FloatArray:
                return full.rhs(start + s, x, p)

            sol = integrate(rhs, y, span, rtol=rtol, atol=atol, what=what, max_steps=max_steps)
            shift = start

        def states(s: FloatArray, sol: DenseSolution = sol, shift: float = shift) -> FloatArray:
            return sol(np.asarray(s) - shift)

        legs.append(_Leg("full", start, start + span, states, shift + sol.ts[1:]))
        nfev += sol.nfev
        y = states(np.array([start + span]))[0]
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
