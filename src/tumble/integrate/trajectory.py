"""What a run of a model returns (:class:`Trajectory`), what an integrated run is asked for
(:class:`RunSpec`), and the Trajectory of an integrated run built from its dense solution."""

from __future__ import annotations

import time
from collections.abc import Callable, Collection
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import ParameterError
from tumble.integrate.limits import MAX_STEPS
from tumble.integrate.ode import DenseSolution
from tumble.models.base import AveragedForm, Columns, FullForm, Model

__all__ = [
    "RunSpec",
    "Trajectory",
    "UnwrapStream",
    "integrated",
    "turning_angles",
    "unwrap_columns",
]

P = TypeVar("P")
S = TypeVar("S")


@dataclass(frozen=True)
class Trajectory:
    """Output of one method: columns at the sample times, and how it was obtained.

    Attributes
    ----------
    tau : ndarray
        Sample times [model time unit].
    columns : dict
        Output columns (names as in the model record), each of the shape of ``tau``.
    method, form : str
        Method and the form of the equations used.
    wall_time : float
        Seconds spent [s].
    nfev : int
        Right-hand-side evaluations (0 for closed forms).
    slow : callable
        ``slow(tau) -> columns`` anywhere in ``[0, tau[-1]]``, for validity checks (a compiled
        averaged run replays itself from its checkpoints: :mod:`tumble.integrate.replay`).
    steps : ndarray
        The integrator's step times: a grid that resolves every fast oscillation, for
        locating extrema. Empty for closed forms and for the runs that keep their samples,
        not their steps (compiled full runs without ``dense``, compiled averaged runs).
    integrator : str
        ``"numba"``, ``"scipy"`` or ``""`` (closed forms).
    events, event_signs : ndarray
        Zeros of the full form's event function found during the integration (e.g. the
        extrema of θ), and the sign of the event function before each.
    event_columns : dict
        The columns at ``events``.
    legs : tuple
        A hybrid run's legs, ``(kind, start, end)`` with kind "averaged" or "full" [model
        time unit], or an averaged run's around its asymptotic crossing steps (kind
        "asymptotic": the inner region the step's theory describes); empty for any other run.
    """

    tau: FloatArray
    columns: dict[str, FloatArray]
    method: str
    form: str
    wall_time: float
    nfev: int
    slow: Callable[[FloatArray], dict[str, FloatArray]] = field(repr=False)
    steps: FloatArray = field(default_factory=lambda: np.empty(0), repr=False)
    integrator: str = ""
    events: FloatArray = field(default_factory=lambda: np.empty(0), repr=False)
    event_signs: FloatArray = field(default_factory=lambda: np.empty(0), repr=False)
    event_columns: Columns = field(default_factory=dict, repr=False)
    legs: tuple[tuple[str, float, float], ...] = ()

    def attitude(self) -> Any:
        """The attitude at the samples, body → inertial, from the columns q0 … q3 of a full
        run (scalar first; :func:`tumble.models.base.attitude_columns`).

        Returns
        -------
        scipy.spatial.transform.Rotation
            One rotation per sample: ``.as_matrix()`` gives R with v_inertial = R v_body.

        Raises
        ------
        ParameterError
            The run has no attitude (an averaged or closed-form run).
        """
        if "q0" not in self.columns:
            raise ParameterError(
                f"the {self.method} run has no attitude: only full runs write q0 … q3"
            )
        from scipy.spatial.transform import Rotation  # loaded where asked for: import time

        q = np.stack([self.columns[f"q{i}"] for i in (1, 2, 3, 0)], axis=-1)  # scalar last
        return Rotation.from_quat(q)


def unwrap_columns(
    model: Model[P, S],
    p: P,
    method: str,
    cols: Columns,
    initial: S,
    turning: Collection[str] | None = None,
) -> None:
    """Make angle columns continuous, starting from the initial value, not mod 2π; with
    ``turning`` (names), those alone: the others are constant along the run, at their
    initial values (:func:`turning_angles`)."""
    for c in model.columns(p, method):
        if c.unwrap and c.name in cols and (turning is None or c.name in turning):
            angle = cols[c.name]
            if angle.size > 1 and np.any(np.abs(np.diff(angle)) >= np.pi):  # else the same
                angle = np.unwrap(angle)
            start = getattr(initial, c.name, angle[0])
            cols[c.name] = angle + 2.0 * np.pi * np.round((start - angle[0]) / (2.0 * np.pi))


def turning_angles(
    model: Model[P, S], p: P, avg: AveragedForm[P, S], initial: S, dim: int
) -> list[str]:
    """The angle columns an averaged run of ``avg`` unwraps: the model's, less those the form
    says do not turn (``AveragedForm.angles``)."""
    names = [c.name for c in model.columns(p, "averaged") if c.unwrap]
    if avg.angles is None:
        return names
    turning = avg.angles(p, initial, np.empty(0), np.empty((0, dim)))
    return [name for name in names if name in turning]


class UnwrapStream:
    """:func:`unwrap_columns` on a grid that comes in consecutive parts: each part's angles
    unwrapped as numpy's ``unwrap`` does the whole grid (the same corrections, summed in the
    same order), anchored at the initial value as :func:`unwrap_columns` anchors them, so that
    a run consumed chunk by chunk gets the bits of one unwrapped at once."""

    def __init__(self, names: list[str], initial: object) -> None:
        self.names, self.initial = names, initial
        self.last: dict[str, float] = {}  # the grid's value before this part
        self.total: dict[str, float] = {}  # the corrections so far
        self.shift: dict[str, float] = {}  # the anchor's whole turns

    def __call__(self, cols: Columns) -> None:
        """Unwrap the angle columns of the next part of the grid in place."""
        for name in self.names:
            p = cols[name]
            if not p.size:
                continue
            if name not in self.last:  # the grid's first value: the anchor
                first = float(p[0])
                start = getattr(self.initial, name, first)
                self.shift[name] = 2.0 * np.pi * np.round((start - first) / (2.0 * np.pi))
                self.total[name], self.last[name] = 0.0, first
            dd = np.diff(np.concatenate([[self.last[name]], p]))
            ddmod = np.mod(dd + np.pi, 2.0 * np.pi) - np.pi
            np.copyto(ddmod, np.pi, where=(ddmod == -np.pi) & (dd > 0))
            correct = ddmod - dd
            np.copyto(correct, 0, where=abs(dd) < np.pi)
            sums = np.cumsum(np.concatenate([[self.total[name]], correct]))[1:]
            self.total[name], self.last[name] = float(sums[-1]), float(p[-1])
            cols[name] = (p + sums) + self.shift[name]


def _sampled(
    model: Model[P, S],
    p: P,
    method: str,
    sol: DenseSolution,
    to_columns: Callable[[FloatArray, FloatArray], Columns],
    tau: FloatArray,
    initial: S,
) -> Columns:
    """Columns at ``tau``; angles unwrapped on the union of solver steps and samples.

    The solver's steps resolve every turn of the fast phases, so unwrapping on them gives the
    continuous angle even when the samples are sparser than a turn.
    """
    # Both are ascending: a stable sort merges them (a time in both is kept twice, harmless).
    times = np.concatenate([sol.ts, tau])
    order = np.argsort(times, kind="stable")
    grid = times[order]
    cols = to_columns(grid, sol(grid))
    unwrap_columns(model, p, method, cols, initial)
    where = np.empty(times.size, dtype=np.intp)
    where[order] = np.arange(times.size)
    at = where[sol.ts.size :]
    return {name: values[at] for name, values in cols.items()}


@dataclass(frozen=True)
class RunSpec(Generic[P, S]):
    """What one run of a model integrates: its parameters, initial state, sample times
    [model time unit], tolerances and step budget."""

    model: Model[P, S]
    p: P
    initial: S
    tau: FloatArray
    rtol: float
    atol: float
    max_steps: int = MAX_STEPS

    @property
    def t_end(self) -> float:
        """The last sample time, where the integration ends [model time unit]."""
        return float(self.tau[-1])

    def what(self, eq: FullForm[P, S] | AveragedForm[P, S]) -> str:
        """The equations ``eq`` as an error message names them."""
        kind = "averaged" if isinstance(eq, AveragedForm) else "full"
        return f"{self.model.name} {kind} equations {eq.equation}"


def integrated(
    run: RunSpec[P, S],
    method: str,
    eq: FullForm[P, S] | AveragedForm[P, S],
    sol: DenseSolution,
    start: float,
) -> Trajectory:
    """The Trajectory of an integrated method, its wall time counted from ``start``."""
    model, p, initial, tau = run.model, run.p, run.initial, run.tau
    if isinstance(eq, AveragedForm):
        avg = eq

        def to_columns(t: FloatArray, Y: FloatArray) -> Columns:
            return avg.to_columns(p, initial, t, Y)

    else:
        full = eq

        def to_columns(t: FloatArray, Y: FloatArray) -> Columns:
            return full.to_columns(p, t, Y)

    cols = _sampled(model, p, method, sol, to_columns, tau, initial)
    if isinstance(eq, AveragedForm) and eq.osculating is not None:
        cols.update(eq.osculating(p, initial, tau, sol(tau)))

    def slow(t: FloatArray) -> Columns:
        return to_columns(t, sol(t))

    events = sol.events
    event_columns = to_columns(events, sol(events)) if events.size else {}
    wall = time.perf_counter() - start
    return Trajectory(
        tau,
        cols,
        method,
        eq.name,
        wall,
        sol.nfev,
        slow,
        sol.ts,
        sol.integrator,
        events,
        sol.event_signs,
        event_columns,
        legs=step_legs(eq, float(tau[-1])) if isinstance(eq, AveragedForm) else (),
    )


def step_legs(form: AveragedForm[Any, Any], t_end: float) -> tuple[tuple[str, float, float], ...]:
    """The legs of an averaged run of ``form`` to ``t_end`` around the asymptotic crossing
    steps it takes (``AveragedForm.steps``): ("averaged", start, end) and ("asymptotic", start,
    end) in time order, the inner regions cut to [0, t_end]; empty without a step."""
    legs: list[tuple[str, float, float]] = []
    t = 0.0
    for a, b in sorted(form.steps):
        a, b = max(a, t), min(b, t_end)
        if b <= a:
            continue
        if a > t:
            legs.append(("averaged", t, a))
        legs.append(("asymptotic", a, b))
        t = b
    if legs and t < t_end:
        legs.append(("averaged", t, t_end))
    return tuple(legs)
