"""A compiled run that keeps its samples and a bounded set of checkpoints, not its steps, and
is evaluated anywhere by replaying it from the checkpoint before.

A run of averaged equations may take millions of steps (the orbiting body's over centuries):
its dense output, 7 interpolant rows of the state per step, grew with the span until the
memory ran out. Here the run is consumed chunk by chunk (:class:`~.dop853.Integration`): each
chunk keeps its steps and interpolants while its samples are taken from them and the caller
looks at them (to unwrap the angles on them), and is then dropped; the time, state and next
step size are kept at the end of every chunk. From a checkpoint the compiled DOP853 takes
exactly the steps the run took (the same state, step size, kernel and end point give the same
arithmetic, and its step-size controller keeps no memory of earlier steps), so
:class:`Replay` gives the states the dense output would have given, at the cost of re-running
one stretch of :data:`CHECKPOINT_STEPS` steps (or a multiple of it, once the checkpoints are
thinned). A time is evaluated on the step the whole dense output would have chosen (a step's
start on the step it begins, the run's end on its last step): the samples and the replayed
states are the dense output's, bit for bit.

Memory: the samples, one chunk and at most :data:`MAX_CHECKPOINTS` states, whatever the span.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace

import numpy as np

from tumble._progress import advanced
from tumble._typing import FloatArray
from tumble.errors import IntegrationError, TumbleError
from tumble.integrate import dop853
from tumble.integrate.limits import FIRST_CHUNK, pace_message
from tumble.integrate.ode import compiled_plan, restart_at
from tumble.kernels import Kernel
from tumble.models.base import Breakpoint

__all__ = ["CHECKPOINT_STEPS", "MAX_CHECKPOINTS", "Filled", "Replay", "Streamed", "stream"]

CHECKPOINT_STEPS = 2000
"""Steps between two checkpoints of a streamed run (the chunks it advances by, after the
first ones): replaying a stretch costs about as much as a chunk of the run, a few milliseconds
for the averaged engines."""

MAX_CHECKPOINTS = 4096
"""The most checkpoints a streamed run keeps: past it, every other one is dropped (the stretch
between two doubles), so that their memory is bounded too (4096 states: under a megabyte)."""

_REPLAY_STEPS = 250  # steps a replay advances by between two looks at where it stands

OnChunk = Callable[[dop853.Solution, FloatArray, slice], None]
"""``on_chunk(piece, steps, samples)``: one chunk of the run (its steps and interpolants,
:class:`~.dop853.Solution`), the step times and the slice of the samples it covers (each
time of the run covered once, by the chunk whose interpolant the dense output would use)."""


def _covered(times: FloatArray, lo: float, hi: float, closed: bool) -> slice:
    """The ascending ``times`` in [lo, hi) (or [lo, hi] when ``closed``), as a slice."""
    i0 = int(np.searchsorted(times, lo, side="left"))
    i1 = int(np.searchsorted(times, hi, side="right" if closed else "left"))
    return slice(i0, i1)


@dataclass(frozen=True)
class _Checkpoint:
    """Where a stretch of the run can be replayed from: time, state, the step size the run
    tried next, the kernel its piece ran (its surface watched; None: the end of a piece, not
    replayed from) and the end its piece ran to."""

    t: float
    y: FloatArray
    h: float
    kernel: Kernel | None
    stop: float


class Replay:
    """The states of a streamed run anywhere in its span, replayed between checkpoints.

    Parameters
    ----------
    checkpoints : sequence of _Checkpoint
        In time order; a piece's end and the next piece's start share a time (the start, after
        a breakpoint's restart map, is the one taken there).
    rtol, atol : float
        The run's tolerances.
    what : str
        The equations, for the error message of a replay that fails (it cannot, unless the
        kernel is not deterministic).
    """

    def __init__(
        self, checkpoints: Sequence[_Checkpoint], rtol: float, atol: float, what: str
    ) -> None:
        self._points = list(checkpoints)
        self._times = np.array([c.t for c in self._points])
        self.rtol, self.atol, self.what = rtol, atol, what
        # The last times asked for and their states: a validity check scans its grid more
        # than once (the separatrix, then its crossing), each scan a pass over the whole span.
        self._last: tuple[FloatArray, FloatArray] = (np.empty(0), np.empty((0, 0)))

    def __call__(self, t: FloatArray) -> FloatArray:
        """States at times ``t`` (any order, within the run's span), shape (m, n)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if t.size and np.array_equal(t, self._last[0]):
            return self._last[1].copy()
        states = self._states(t)
        if t.size > 1:
            self._last = (t.copy(), states.copy())
        return states

    def _states(self, t: FloatArray) -> FloatArray:
        order = np.argsort(t, kind="stable")
        ordered = t[order]
        out = np.empty((t.size, self._points[0].y.size))
        # The last checkpoint at or before each time (the run's end is on its last step: the
        # stretch before it).
        last = len(self._points) - 2
        which = np.clip(np.searchsorted(self._times, ordered, side="right") - 1, 0, last)
        bounds = np.flatnonzero(np.diff(which)) + 1
        for rows in np.split(np.arange(t.size), bounds):
            if rows.size:
                i = int(which[rows[0]])
                out[order[rows]] = self._stretch(i, ordered[rows], closed=i == last)
        return out

    def _stretch(self, i: int, t: FloatArray, closed: bool) -> FloatArray:
        """States at the ascending times ``t`` from checkpoint ``i`` to the next one (that one
        included when ``closed``)."""
        point = self._points[i]
        states = np.repeat(point.y[None, :], t.size, axis=0)
        if point.kernel is None:
            return states  # a run that ends where it starts
        # The run's own state, step size, kernel and end point (a step the run tried past
        # the next checkpoint, and refused, shapes the step it took), so that the replay takes
        # the run's steps; it stops once it has passed the last time asked for.
        options = dop853.Options(self.rtol, self.atol, point.h, True, True)
        run = dop853.Integration(point.kernel, point.y, point.stop, options, t0=point.t)
        filled = 0
        while filled < t.size:
            done = run.advance(_REPLAY_STEPS)
            piece = run.take()
            if done and piece.status not in (0, dop853.STOPPED):
                raise IntegrationError(
                    f"{self.what}: replay failed at t = {piece.t:.6g}: {piece.message}"
                )
            rows = _covered(t, float(piece.ts[0]), float(piece.ts[-1]), closed and done)
            if rows.stop > rows.start:
                states[rows] = piece(t[rows])
                filled = rows.stop
            if done:
                break
        return states


@contextlib.contextmanager
def _keeping(filled: Filled) -> Iterator[None]:
    """Hand the samples ``filled`` on with an error that stops the run (module notes)."""
    try:
        yield
    except TumbleError as exc:  # what ran before: its samples (the caller makes them a run)
        if exc.partial is None and filled.rows > 0:
            exc.partial = filled
        raise


class Filled:
    """The samples a streamed run filled (the first ``rows`` of ``y_eval``) before an error
    stopped it: ``TumbleError.partial`` of :func:`stream`, which the caller turns into the
    run's trajectory up to there."""

    def __init__(self) -> None:
        self.rows = 0
        self.y_eval: FloatArray = np.empty((0, 0))


@dataclass(frozen=True)
class Streamed:
    """What a streamed run kept: the states at the samples, the zeros of the kernel's own
    event (a run without breakpoints), the evaluations, and its replay."""

    y_eval: FloatArray
    nfev: int
    replay: Replay
    events: FloatArray
    event_signs: FloatArray
    event_y: FloatArray


class _Checkpoints:
    """The checkpoints of a run as it goes: one per chunk, thinned to every other one when
    there are :data:`MAX_CHECKPOINTS` (a piece's start and end are always kept)."""

    def __init__(self) -> None:
        self.points: list[_Checkpoint] = []
        self.fixed: list[bool] = []
        self.stride = 1  # chunks between two kept checkpoints
        self.chunks = 0

    def add(self, point: _Checkpoint, fixed: bool) -> None:
        self.chunks += 1
        if not fixed and self.chunks % self.stride:
            return
        self.points.append(point)
        self.fixed.append(fixed)
        if len(self.points) >= MAX_CHECKPOINTS:
            self.stride *= 2
            kept = [
                k
                for k in range(len(self.points))
                if self.fixed[k] or k % 2 == 0 or k == len(self.points) - 1
            ]
            self.points = [self.points[k] for k in kept]
            self.fixed = [self.fixed[k] for k in kept]


def stream(
    kernel: Kernel,
    y0: FloatArray,
    tau: FloatArray,
    breakpoints: Sequence[Breakpoint],
    rtol: float,
    atol: float,
    what: str,
    max_steps: int,
    on_chunk: OnChunk | None = None,
) -> Streamed:
    """Integrate ``kernel`` from (0, ``y0``) to ``tau[-1]``, keeping the states at ``tau``.

    The run is split at the breakpoints' known times and stopped at their one surface (its
    compiled event made terminal, then restarted through its map) as
    :func:`tumble.integrate.ode.integrate` splits it; each piece starts with the step size the
    last one ended with. Its steps are handed to ``on_chunk`` chunk by chunk and dropped.

    Parameters
    ----------
    kernel : Kernel
        The compiled right-hand side.
    y0 : ndarray
        Initial state at t = 0 (finite).
    tau : ndarray
        Sample times, ascending, from ≥ 0 to the end of the run > 0 [the kernel's time unit].
    breakpoints : sequence of Breakpoint
        As :func:`tumble.integrate.ode.integrate` takes them on the compiled path.
    rtol, atol : float
        Tolerances.
    what : str
        The equations, for error messages.
    max_steps : int
        Step budget (``[run] max_steps``); the pace is checked after every chunk.
    on_chunk : callable, optional
        See :data:`OnChunk`; None when the steps are not needed (they are not recorded then).

    Raises
    ------
    IntegrationError
        The run failed, spent its budget, or goes at a pace that would need a hundred times
        what is left of it.
    """
    filled = Filled()
    t_end = float(tau[-1])
    y_eval = np.full((tau.size, y0.size), np.nan)

    def fill(piece: dop853.Solution, finished: bool) -> None:
        """The samples ``piece`` passed, and its steps handed to ``on_chunk``. A time at a
        chunk's end is the next chunk's start (the next piece's, after the restart map); the
        run's end is on its last step."""
        if piece.ts.size < 2:  # no step taken
            return
        closed = finished and piece.t >= t_end
        steps_t = piece.ts if closed else piece.ts[:-1]
        rows = _covered(tau, float(piece.ts[0]), float(piece.ts[-1]), closed)
        if rows.stop > rows.start:
            y_eval[rows] = piece(tau[rows])
        if on_chunk is not None:
            on_chunk(piece, steps_t, rows)
        filled.y_eval, filled.rows = y_eval, max(filled.rows, rows.stop)

    with _keeping(filled):
        stops, surface = compiled_plan(kernel, breakpoints, y0, t_end, what)
        n = y0.size
        events: list[tuple[FloatArray, FloatArray, FloatArray]] = []
        checkpoints = _Checkpoints()
        t0, y, first, steps, nfev = 0.0, y0, 0.0, 0, 0
        chunk = FIRST_CHUNK
        while True:
            stop = next(s for s in stops if s > t0)
            watched = replace(kernel, event=surface.event, terminal=True) if surface else kernel
            options = dop853.Options(rtol, atol, min(first, stop - t0), True, True)
            run = dop853.Integration(watched, y, stop, options, t0=t0)
            checkpoints.add(_Checkpoint(t0, y.copy(), options.first_step, watched, stop), True)
            while True:
                try:
                    finished = run.advance(
                        min(chunk, max(1, max_steps - steps - run.progress.n_steps))
                    )
                except TumbleError:  # a user's torque: the steps before its fault are kept
                    fill(run.take(), False)
                    raise
                chunk = min(2 * chunk, CHECKPOINT_STEPS)
                piece = run.take()
                progress = run.progress
                advanced(progress.t, t_end)
                spent = steps + progress.n_steps
                if finished and progress.status not in (0, dop853.STOPPED):
                    fill(piece, False)
                    raise IntegrationError(
                        f"{what}: integration failed at t = {progress.t:.6g}: {piece.message}"
                    )
                fill(piece, finished)
                if not breakpoints and piece.event_t.size:  # the kernel's own event
                    events.append((piece.event_t, piece.event_signs, piece(piece.event_t)))
                if finished:
                    break
                if spent >= max_steps:
                    raise IntegrationError(
                        f"{what}: run.max_steps = {max_steps} steps spent at t = "
                        f"{progress.t:.6g} of {t_end:.6g}"
                    )
                refused = pace_message(
                    progress.t, t_end, progress.h_abs, max_steps - spent, max_steps
                )
                if refused:
                    raise IntegrationError(f"{what}: {refused}")
                here = _Checkpoint(progress.t, run.y.copy(), progress.h_abs, watched, stop)
                checkpoints.add(here, fixed=False)
            steps += progress.n_steps
            nfev += progress.nfev
            first = float(progress.h_abs)  # the step the controller would try next
            t0, y = float(progress.t), run.y.copy()
            checkpoints.add(_Checkpoint(t0, y.copy(), first, None, t0), fixed=True)
            if progress.status == dop853.STOPPED:
                assert surface is not None  # only a watched surface stops a run
                if surface.restart is not None:
                    y = np.asarray(surface.restart(t0, y), dtype=float)
                surface = None  # crossed at most once
            if t0 >= t_end:
                break
            y = restart_at(breakpoints, t0, y)
        ev_t, ev_s, ev_y = (
            (np.concatenate([e[k] for e in events]) for k in range(3))
            if events
            else (np.empty(0), np.empty(0), np.empty((0, n)))
        )
        return Streamed(
            y_eval, nfev, Replay(checkpoints.points, rtol, atol, what), ev_t, ev_s, ev_y
        )
