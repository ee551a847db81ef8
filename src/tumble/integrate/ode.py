"""Adaptive integration with dense output (scipy's DOP853), and honest failure reports."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from tumble._progress import advanced
from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError, TumbleError
from tumble.integrate import dop853
from tumble.integrate.limits import FIRST_CHUNK, MAX_STEPS, check_times, pace_message
from tumble.kernels import EVENT_NONE, Kernel
from tumble.models.base import Breakpoint

__all__ = [
    "DEFAULT_ATOL",
    "DEFAULT_RTOL",
    "DenseSolution",
    "check_times",
    "compiled_breakpoints",
    "integrate",
]

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-12


@dataclass(frozen=True)
class DenseSolution:
    """A solution that can be evaluated at any time in ``[t0, t_end]``.

    Attributes
    ----------
    ts : ndarray
        Times of the integrator's steps (for resolving phases between samples).
    nfev : int
        Right-hand-side evaluations.
    integrator : str
        ``"numba"`` (the compiled DOP853) or ``"scipy"``.
    events, event_signs : ndarray
        Zeros of the form's event function located during the run (the kernel's on the
        compiled path, the ``event`` argument of :func:`integrate` on scipy's), and the sign
        of the event function just before each.
    """

    ts: FloatArray
    nfev: int
    _sol: Any
    integrator: str = "scipy"
    events: FloatArray = field(default_factory=lambda: np.empty(0))
    event_signs: FloatArray = field(default_factory=lambda: np.empty(0))

    def __call__(self, t: ArrayLike) -> FloatArray:
        """States at times ``t``, shape (n, dim)."""
        return np.asarray(self._sol(np.asarray(t, dtype=float)), dtype=float).T


class _Piecewise:
    """Dense output of consecutive segments [t_i, t_(i+1)] (restarts at breakpoints)."""

    def __init__(self, starts: list[float], sols: list[Any]) -> None:
        self.starts = np.asarray(starts[1:], dtype=float)
        self.sols = sols

    def __call__(self, t: FloatArray) -> FloatArray:
        t = np.atleast_1d(t)
        which = np.searchsorted(self.starts, t, side="right")
        out = np.empty((self.sols[0](t[:1]).shape[0], t.size))
        for i, sol in enumerate(self.sols):
            mask = which == i
            if np.any(mask):
                out[:, mask] = sol(t[mask])
        return out


def _event(
    g: Callable[[float, FloatArray], float], terminal: bool = True, direction: float = 0.0
) -> Callable[[float, FloatArray], float]:
    def event(t: float, y: FloatArray) -> float:
        return g(t, y)

    event.terminal = terminal  # type: ignore[attr-defined]
    event.direction = direction  # type: ignore[attr-defined]
    return event


def _recorders(
    g: Callable[[float, FloatArray], float] | None,
) -> list[Callable[[float, FloatArray], float]]:
    """The recorded event as scipy events: rising zeros (negative before), falling ones."""
    if g is None:
        return []
    return [_event(g, terminal=False, direction=1.0), _event(g, terminal=False, direction=-1.0)]


def _inside(
    rhs: Callable[[float, FloatArray], FloatArray], t0: float, t1: float
) -> Callable[[float, FloatArray], FloatArray]:
    """``rhs`` evaluated strictly inside [t0, t1]: a stage that lands on a segment end (a time
    breakpoint, where a forcing has a kink) must see the forcing of its own segment, not the
    other side's. The shift, 1e-12 relative, is far below any tolerance of the solver."""
    delta = 1e-12 * max(1.0, abs(t0), abs(t1))
    lo, hi = t0 + delta, t1 - delta

    def f(t: float, y: FloatArray) -> FloatArray:
        return rhs(min(max(t, lo), hi), y)

    return f


def integrate(
    rhs: Callable[[float, FloatArray], FloatArray],
    y0: ArrayLike,
    t_end: float,
    *,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    what: str = "the equations of motion",
    breakpoints: Sequence[Breakpoint] = (),
    kernel: Kernel | None = None,
    event: Callable[[float, FloatArray], float] | None = None,
    max_steps: int | None = None,
) -> DenseSolution:
    """Integrate ``dy/dt = rhs(t, y)`` from t = 0 to ``t_end`` with DOP853 and dense output.

    Parameters
    ----------
    rhs : callable
        Right-hand side ``rhs(t, y) -> dy/dt``.
    y0 : array_like
        Initial state at t = 0.
    t_end : float
        Final time [the problem's time unit], ≥ 0.
    rtol, atol : float
        Relative and absolute local error tolerances.
    what : str
        Name of the system, for error messages.
    breakpoints : sequence of Breakpoint
        Surfaces the solution crosses at most once and where ``rhs`` is not smooth (e.g. a
        separatrix). The step is stopped exactly at the crossing and the integration restarts
        there (through the breakpoint's restart map). Breakpoints at known times (a kink in a
        prescribed forcing) split the interval, so no step straddles them.
    kernel : Kernel, optional
        The same right-hand side compiled: integrate it with the compiled DOP853
        (:mod:`tumble.integrate.dop853`, the same method and step control as scipy's) instead of
        calling ``rhs``. On this path breakpoints are at known times (the run is split there)
        or one surface with its compiled event function (``Breakpoint.event``, a terminal
        event of the kernel; the kernel has no event of its own).
    event : callable, optional
        ``event(t, y)``, whose zeros are recorded (``DenseSolution.events`` and the sign
        before each) on the scipy path; the compiled path records the kernel's own event,
        which must be the same function.
    max_steps : int, optional
        Step budget on the scipy path (``[run] max_steps``; at most :data:`PYTHON_MAX_STEPS`):
        a run that spends it, or whose pace would need a hundred times what is left, stops
        with an IntegrationError naming the key. The compiled path is budgeted by
        :func:`tumble.integrate.simulate`.

    Raises
    ------
    IntegrationError
        If the solver fails, the solution stops being finite or the step budget is spent.
    """
    y0 = np.asarray(y0, dtype=float)
    if not np.all(np.isfinite(y0)):
        raise IntegrationError(f"{what}: the initial state is not finite: {y0}")
    if t_end == 0.0:
        return DenseSolution(np.array([0.0]), 0, lambda t: np.repeat(y0[:, None], np.size(t), 1))
    if kernel is not None:
        if not breakpoints:
            return _integrate_compiled(kernel, y0, t_end, rtol=rtol, atol=atol, what=what)
        return _integrate_compiled_split(
            kernel, y0, t_end, breakpoints, rtol, atol, what, max_steps
        )
    budget = min(PYTHON_MAX_STEPS, PYTHON_MAX_STEPS if max_steps is None else int(max_steps))
    try:
        return _integrate_scipy(
            _Budgeted(rhs, t_end, budget), y0, t_end, rtol, atol, what, breakpoints, event
        )
    except _BudgetSpent as spent:
        raise IntegrationError(f"{what}: {spent}") from None


PYTHON_MAX_STEPS = 1_000_000
"""The most steps an integration whose right-hand side is Python (scipy's DOP853) may take:
~4 minutes at 20 µs per evaluation. The compiled integrator takes ``[run] max_steps``."""

_EVALUATIONS_PER_STEP = 12  # scipy's DOP853: 12 stages per accepted step (rejections add more)


class _BudgetSpent(Exception):
    """Raised out of solve_ivp by :class:`_Budgeted` (turned into an IntegrationError)."""


class _Budgeted:
    """``rhs`` counting its evaluations: past the step budget, or when the pace so far would
    need a hundred times the budget left to reach ``t_end``, it stops the integration."""

    def __init__(self, rhs: Callable[[float, FloatArray], FloatArray], t_end: float, steps: int):
        self.rhs, self.t_end, self.steps = rhs, t_end, steps
        self.limit = _EVALUATIONS_PER_STEP * steps
        self.n = 0

    def __call__(self, t: float, y: FloatArray) -> FloatArray:
        self.n += 1
        if self.n % 1200 == 0 or self.n >= self.limit:  # the pace every ~100 steps
            self._check(t)
        return self.rhs(t, y)

    def _check(self, t: float) -> None:
        key = f"run.max_steps = {self.steps}"
        if self.n >= self.limit:
            raise _BudgetSpent(
                f"{key} steps spent at t = {t:.6g} of {self.t_end:.6g} (shorten the run, "
                "or check the input: a very stiff or fast motion)"
            )
        left = self.t_end - t
        if self.n >= 12_000 and t > 0.0 and left * self.n / t > 100.0 * (self.limit - self.n):
            raise _BudgetSpent(
                f"at t = {t:.6g} the steps so far need ~{left * self.n / t / 12:.3g} more to "
                f"reach t = {self.t_end:.6g}, far beyond {key} (shorten the run, or check the "
                "input: a very stiff or fast motion)"
            )


def _segment(
    f: Callable[[float, FloatArray], FloatArray],
    t0: float,
    t1: float,
    y: FloatArray,
    rtol: float,
    atol: float,
    what: str,
    pending: Sequence[Breakpoint],
    first_step: float | None,
    recorders: Sequence[Callable[[float, FloatArray], float]] = (),
) -> Any:
    """scipy's DOP853 from (t0, y) to t1, stopping at the first surface of ``pending`` (the
    first events) and recording the zeros of ``recorders`` (the last ones); IntegrationError
    on failure, on a non-finite state or on an arithmetic exception."""
    from scipy.integrate import solve_ivp  # only here: a compiled run never loads scipy's ODEs

    with np.errstate(divide="raise", over="raise", invalid="raise"):
        try:
            res = solve_ivp(
                f,
                (t0, t1),
                y,
                method="DOP853",
                rtol=rtol,
                atol=atol,
                dense_output=True,
                events=[*(_event(b.condition) for b in pending if b.condition), *recorders] or None,
                first_step=first_step,
            )
        except TumbleError as exc:  # a user's torque failed: keep the steps before it
            exc.dense = _steps_before(f, t0, t1, y, rtol, atol, first_step)
            raise
        except FloatingPointError as exc:
            raise IntegrationError(
                f"{what}: arithmetic failure during integration ({exc})"
            ) from None
    if res.status < 0 or not np.all(np.isfinite(res.y)):
        t_fail = float(res.t[-1]) if res.t.size else t0
        raise IntegrationError(f"{what}: integration failed at t = {t_fail:.6g}: {res.message}")
    return res


def _steps_before(
    f: Callable[[float, FloatArray], FloatArray], t0: float, t1: float, y: FloatArray,
    rtol: float, atol: float, first_step: float | None,
) -> Any:  # fmt: skip
    """The dense output (an ``OdeSolution``) of the steps scipy's DOP853 takes from (t0, y)
    towards t1 before ``f`` fails, retaken one by one (solve_ivp's steps: the same solver,
    the same calls; events only read them); None if it fails before its first step."""
    from scipy.integrate import DOP853, OdeSolution

    ts, pieces = [t0], []
    try:
        solver = DOP853(f, t0, y, t1, rtol=rtol, atol=atol,
                        first_step=first_step if first_step else None)  # fmt: skip
        while solver.status == "running" and solver.step() is None:
            ts.append(solver.t)
            pieces.append(solver.dense_output())
    except Exception:  # the failure again (or the budget): the steps before it are kept
        pass
    return OdeSolution(ts, pieces) if pieces else None


def _integrate_scipy(
    rhs: Callable[[float, FloatArray], FloatArray],
    y0: FloatArray,
    t_end: float,
    rtol: float,
    atol: float,
    what: str,
    breakpoints: Sequence[Breakpoint],
    event: Callable[[float, FloatArray], float] | None = None,
) -> DenseSolution:
    """:func:`integrate` by scipy, segment by segment between breakpoints."""
    # Known times split the interval; a surface the start sits on is already passed.
    times = {float(b.time) for b in breakpoints if b.time is not None}
    stops = [*sorted(t for t in times if 0.0 < t < t_end), t_end]
    pending = [
        b
        for b in breakpoints
        if b.time is None and b.condition is not None and b.condition(0.0, y0) != 0.0
    ]
    starts, steps, nfev = [0.0], [np.array([0.0])], 0
    sols: list[Any] = []  # the dense output of each segment
    t0, y = 0.0, y0
    first_step: float | None = None
    recorders = _recorders(event)
    found: list[tuple[float, float]] = []  # (t, sign before) of the recorded event
    while True:
        seg_end = next(s for s in stops if s > t0)
        if first_step is not None:
            first_step = min(first_step, seg_end - t0)
        f = _inside(rhs, t0, seg_end) if stops[0] < t_end else rhs
        try:
            res = _segment(f, t0, seg_end, y, rtol, atol, what, pending, first_step, recorders)
        except TumbleError as exc:  # the segments before, and the steps of this one kept
            if exc.dense is not None:
                done = _Piecewise(starts, [*sols, exc.dense]) if sols else exc.dense
                ts = np.concatenate([*steps, np.asarray(exc.dense.ts[1:])])
                exc.dense = DenseSolution(ts, nfev, done, "scipy")
            raise
        if recorders:
            rising, falling = res.t_events[-2], res.t_events[-1]
            found += [(float(t), -1.0) for t in rising] + [(float(t), 1.0) for t in falling]
        sols.append(res.sol)
        steps.append(np.asarray(res.t[1:]))
        nfev += int(res.nfev)
        # Restart with the step size the solver had reached (the last step is cut short by
        # the stop, so take the one before): its own initial guess can be orders of magnitude
        # too small, and regrowing the step costs hundreds of evaluations.
        h = float(res.t[-2] - res.t[-3]) if res.t.size > 2 else 0.0
        if res.status == 1:
            fired = next(i for i, ev in enumerate(res.t_events[: len(pending)]) if ev.size)
            t0, y = float(res.t_events[fired][0]), np.asarray(res.y_events[fired][0])
            restart = pending.pop(fired).restart
            if restart is not None:
                y = np.asarray(restart(t0, y), dtype=float)
        elif seg_end < t_end:
            t0, y = seg_end, restart_at(breakpoints, seg_end, np.asarray(res.y[:, -1]))
        else:
            break
        if t0 >= t_end:
            break
        first_step = h if h > 0.0 else None
        starts.append(t0)
    found.sort()
    events = np.array([t for t, _ in found])
    signs = np.array([sign for _, sign in found])
    if len(sols) == 1:
        return DenseSolution(np.concatenate(steps), nfev, sols[0], "scipy", events, signs)
    sol = _Piecewise(starts, sols)
    return DenseSolution(np.unique(np.concatenate(steps)), nfev, sol, "scipy", events, signs)


def _integrate_compiled(
    kernel: Kernel, y0: FloatArray, t_end: float, *, rtol: float, atol: float, what: str
) -> DenseSolution:
    """:func:`integrate` through the compiled DOP853, with the same failure reports."""
    kernel.check_end(t_end)
    return compiled_dense(dop853.solve(kernel, y0, t_end, rtol=rtol, atol=atol), what)


def compiled_breakpoints(breakpoints: Sequence[Breakpoint]) -> bool:
    """Whether the compiled integrator can honour ``breakpoints``: any at known times, and at
    most one surface, with its compiled event function (:attr:`Breakpoint.event`)."""
    surfaces = [b for b in breakpoints if b.time is None]
    return len(surfaces) <= 1 and all(b.event != EVENT_NONE for b in surfaces)


def _integrate_compiled_split(
    kernel: Kernel,
    y0: FloatArray,
    t_end: float,
    breakpoints: Sequence[Breakpoint],
    rtol: float,
    atol: float,
    what: str,
    max_steps: int | None,
) -> DenseSolution:
    """:func:`integrate` through the compiled DOP853 with breakpoints: split at the known
    times (a kink of the right-hand side there), so that no step straddles one, and stopped
    at a surface by the kernel's event made terminal, then restarted past it through its map.
    Each piece starts with the step size the controller proposed at the end of the last one (as
    the ensembles of :mod:`tumble.integrate.ensemble` do); all share the budget."""
    stops, surface = compiled_plan(kernel, breakpoints, y0, t_end, what)
    budget = MAX_STEPS if max_steps is None else int(max_steps)
    results: list[dop853.Solution] = []
    t0, y, first, steps = 0.0, y0, 0.0, 0
    while t0 < t_end:
        stop = next(s for s in stops if s > t0)
        watched = replace(kernel, event=surface.event, terminal=True) if surface else kernel
        options = dop853.Options(rtol, atol, min(first, stop - t0))
        run = dop853.Integration(watched, y, stop, options, t0=t0)
        # Chunks growing from FIRST_CHUNK steps and no longer than the budget left, so that a
        # small budget is kept exactly and a hopeless pace is seen early.
        chunk = FIRST_CHUNK
        while not run.advance(min(chunk, max(1, budget - steps - run.progress.n_steps))):
            advanced(run.progress.t, t_end)
            spent = run.progress.n_steps + steps
            if spent >= budget:
                raise IntegrationError(f"{what}: run.max_steps = {budget} steps spent at t = "
                                       f"{run.progress.t:.6g} of {t_end:.6g}")  # fmt: skip
            refused = pace_message(
                run.progress.t, t_end, run.progress.h_abs, budget - spent, budget
            )
            if refused:
                raise IntegrationError(f"{what}: {refused}")
            chunk = min(2 * chunk, dop853.CHUNK_STEPS)
        advanced(run.progress.t, t_end)
        res = run.solution()
        if res.status not in (0, dop853.STOPPED):
            compiled_dense(res, what)  # raises: the piece failed
        results.append(res)
        steps += res.ts.size - 1
        first = float(run.progress.h_abs)  # the step the controller would try next
        t0, y = float(res.t), res.y
        if res.status == dop853.STOPPED:
            assert surface is not None  # only a watched surface stops a run
            if surface.restart is not None:
                y = np.asarray(surface.restart(t0, y), dtype=float)
            surface = None  # crossed at most once
        elif t0 < t_end:
            y = restart_at(breakpoints, t0, y)
    return joined_pieces(results, what)


def compiled_plan(
    kernel: Kernel, breakpoints: Sequence[Breakpoint], y0: FloatArray, t_end: float, what: str
) -> tuple[list[float], Breakpoint | None]:
    """:func:`split_plan` of a run of ``kernel`` on the compiled integrator, once the kernel
    takes ``t_end`` and the compiled integrator the breakpoints (ParameterError if not: at
    most one surface, with its compiled event function, and no event of the kernel's own
    beside it)."""
    kernel.check_end(t_end)
    surfaces = [b for b in breakpoints if b.time is None]
    if not compiled_breakpoints(breakpoints) or (surfaces and kernel.event != EVENT_NONE):
        raise ParameterError(
            f"{what}: the compiled integrator takes breakpoints at known times and at most "
            "one surface with a compiled event function"
        )
    return split_plan(breakpoints, y0, t_end)


def split_plan(
    breakpoints: Sequence[Breakpoint], y0: FloatArray, t_end: float
) -> tuple[list[float], Breakpoint | None]:
    """Where a compiled run stops (the breakpoints' known times inside (0, t_end), then
    t_end) and the one surface it watches (None if the start sits on it: already passed).
    The single runs and the ensembles split alike."""
    surfaces = [b for b in breakpoints if b.time is None]
    surface = surfaces[0] if surfaces else None
    if surface is not None and surface.condition is not None and surface.condition(0.0, y0) == 0.0:
        surface = None
    # A kink within round-off of either end is the start or the end itself.
    slack = 1e-12 * max(1.0, t_end)
    times = sorted({float(b.time) for b in breakpoints if b.time is not None})
    return [t for t in times if slack < t < t_end - slack] + [t_end], surface


def restart_at(breakpoints: Sequence[Breakpoint], t: float, y: FloatArray) -> FloatArray:
    """The state a run split at the known time ``t`` goes on from: the restart map of the
    breakpoint at that time (a jump the theory gives there), or ``y``. Every path that splits
    a run (scipy's, the compiled one, the streamed one, the ensembles) restarts alike."""
    slack = 1e-12 * max(1.0, abs(t))  # the stop is the breakpoint's time, to round-off
    for b in breakpoints:
        if b.time is not None and b.restart is not None and abs(float(b.time) - t) <= slack:
            return np.asarray(b.restart(t, y), dtype=float)
    return y


def joined_pieces(results: Sequence[dop853.Solution], what: str) -> DenseSolution:
    """The dense output of consecutive compiled pieces of one run (each restarted at the end
    of the last: a breakpoint's time, or a surface's terminal event); IntegrationError if a
    piece failed. The ensembles join their pieces the same way."""
    sols: list[Callable[[FloatArray], FloatArray]] = []
    starts: list[float] = [0.0]
    steps: list[FloatArray] = []
    nfev = 0
    for k, res in enumerate(results):
        stopped = res.status == dop853.STOPPED
        piece = compiled_dense(replace(res, status=0) if stopped else res, what)
        sols.append(_states_by_rows(piece))
        steps.append(res.ts[1:])
        nfev += res.nfev
        if k + 1 < len(results):
            starts.append(float(res.t))
    ts = np.concatenate([[0.0], *steps])
    sol = sols[0] if len(sols) == 1 else _Piecewise(starts, sols)
    return DenseSolution(ts, nfev, sol, "numba")


def _states_by_rows(sol: DenseSolution) -> Callable[[FloatArray], FloatArray]:
    """``sol`` as the piecewise output takes its pieces: states of shape (dim, n)."""

    def states(t: FloatArray) -> FloatArray:
        return sol(t).T

    return states


def compiled_dense(res: dop853.Solution, what: str) -> DenseSolution:
    """A compiled solution as a :class:`DenseSolution`; IntegrationError if it failed.

    Parameters
    ----------
    res : Solution
        Result of :func:`tumble.integrate.dop853.solve` or
        :func:`tumble.integrate.dop853.solve_many`.
    what : str
        What was integrated, for the error message.
    """
    if res.status != 0:
        raise IntegrationError(f"{what}: integration failed at t = {res.t:.6g}: {res.message}")
    return DenseSolution(
        res.ts,
        res.nfev,
        lambda t: res(t).T,
        integrator="numba",
        events=res.event_t,
        event_signs=res.event_signs,
    )
