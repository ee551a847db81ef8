"""The compiled DOP853 from Python: one run, a resumable run, and batches over threads."""

from __future__ import annotations

import _signal
import contextlib
import functools
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, cast

import numba
import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, UserCodeTimeout
from tumble.integrate.dop853 import core
from tumble.integrate.dop853.core import Chunk, Options, Progress
from tumble.integrate.dop853.dense import evaluate_dense
from tumble.integrate.dop853.functions import addresses
from tumble.integrate.dop853.tableau import N_INTERPOLANT
from tumble.integrate.limits import user_code_wait
from tumble.kernels import Kernel
from tumble.kernels.jit import compile_lock, compile_notice
from tumble.kernels.kinds import KINDS
from tumble.kernels.user import any_armed, armed_names, calls, raise_fault

__all__ = [
    "CHUNK_STEPS",
    "BatchResult",
    "Integration",
    "Options",
    "Solution",
    "available_threads",
    "solve",
    "solve_batch",
    "solve_many",
    "starting_step",
    "status_message",
]

_MAX_THREADS = numba.get_num_threads()  # the cores, or NUMBA_NUM_THREADS

_MESSAGES = {
    core.OK: "",
    core.RUNNING: "the run was stopped before its end",
    core.STEP_TOO_SMALL: "the step size fell below the resolution of t",
    core.NOT_FINITE: "the state stopped being finite",
    core.BAD_START: "the right-hand side is not finite at the initial state",
    core.STOPPED: "the run stopped at its terminal event",
}


CHUNK_STEPS = 20_000
"""Steps per compiled call of :func:`solve` (≈ 10–50 ms): between two calls Python runs, so
an interrupt (Ctrl-C) stops a run within a fraction of a second."""


IN_CALL = [0]
"""Compiled runs in progress (not compiling): what a guard against user code that never
returns watches (:mod:`tumble.app.guard`)."""


ABANDONED = [0]
"""Compiled calls left running because the user's torque they call did not return
(:meth:`Integration.advance`): nothing can stop them but the end of the process, which the
command line brings about (``os._exit``) once it has written its outputs."""

_WAIT_POLL_S = 0.05  # how often a watched compiled call's heartbeat is read [s]
WATCHED_FIRST_STEPS = 250
"""Steps of the first watched chunk (:meth:`Integration.advance` with a user's compiled
torque): each next one twice as many, up to the caller's. A function that never returns loses
the chunk it hangs in, what ran before is kept: at most half the run early on, and a chunk's
worth (of many) later, for a thread started per chunk (~0.1 ms, under 1 % of a chunk of
thousands of steps)."""


def _watched(entry: Callable[..., tuple[Any, Any]], args: tuple[Any, ...]) -> tuple[Any, Any]:
    """``entry(*args)`` run in a thread of its own while this one follows the heartbeat of
    the user's compiled torques (:func:`tumble.kernels.user.calls`): a call in which no user
    function began for :func:`~tumble.integrate.limits.user_code_wait` seconds is one that
    never returns; it is left behind (:data:`ABANDONED`) and :class:`UserCodeTimeout` raised
    here, where the caller can still keep what the run computed before that call. The
    compiled code holds no lock, so the wait costs nothing but the thread's start (~0.1 ms a
    chunk), and Ctrl-C reaches this thread at once."""
    box: list[Any] = []

    def work() -> None:
        try:
            box.append(entry(*args))
        except BaseException as exc:  # handed to the caller's thread
            box.append(exc)

    worker = threading.Thread(target=work, name="tumble-compiled-call", daemon=True)
    worker.start()
    beat, since = calls(), time.monotonic()
    while worker.is_alive():
        worker.join(_WAIT_POLL_S)
        now, seen = time.monotonic(), calls()
        if seen != beat:
            beat, since = seen, now
        elif worker.is_alive() and now - since > user_code_wait():
            ABANDONED[0] += 1
            raise UserCodeTimeout(UserCodeTimeout.said(armed_names(), user_code_wait()))
    if isinstance(box[0], BaseException):
        raise box[0]
    return cast(tuple[Any, Any], box[0])


@contextlib.contextmanager
def in_call() -> Iterator[None]:
    """Count a compiled run in progress (:data:`IN_CALL`)."""
    IN_CALL[0] += 1
    try:
        yield
    finally:
        IN_CALL[0] -= 1


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Defer Ctrl-C (SIGINT) during a compiled call: its handler runs once the call returned.

    The compiled call boxes its results into Python objects as it returns, and a named tuple
    is built by Python code; a KeyboardInterrupt raised in the middle of that left a
    half-built result behind and crashed the interpreter (segmentation fault). While the call
    runs, SIGINT only records itself; afterwards the handler in force before (Python's
    default raises KeyboardInterrupt) is called. Python handles signals in the main thread
    only, so elsewhere nothing changes.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    # The C module's signal(): the same call without the enum conversions of the signal
    # module's wrapper (0.7 µs for the pair instead of 9 µs, felt by short averaged runs).
    previous = _signal.signal(signal.SIGINT, lambda signum, frame: received.append(signum))
    try:
        yield
    finally:
        _signal.signal(signal.SIGINT, previous)
    if received and callable(previous):
        previous(signal.SIGINT, None)
    elif received and previous == signal.SIG_DFL:  # deliver it as it would have been
        os.kill(os.getpid(), signal.SIGINT)


def starting_step(kind: int, first: float = 0.0) -> float:
    """``Options.first_step`` of a run of ``kind`` asked to start with ``first``: ``first``,
    or :data:`~tumble.integrate.dop853.core.SLOW_START` where it is 0 (the estimate) and the
    kind is declared slow (averaged equations)."""
    first = float(first)
    return core.SLOW_START if first == 0.0 and KINDS[int(kind)].slow else first


def status_message(status: int) -> str:
    """Why a run with ``status`` (of :mod:`~.core`) stopped early (empty on success)."""
    return _MESSAGES.get(status, f"status {status}")


def available_threads() -> int:
    """Threads the batch integrator can use (the cores, or ``NUMBA_NUM_THREADS``)."""
    return _MAX_THREADS


_LOOPS: dict[tuple[Any, ...], Callable[..., tuple[Any, Any]]] = {}
_ENTRIES: dict[tuple[Any, ...], Callable[..., tuple[Any, Any]]] = {}

LOOP_COMPILE_S = 5.0
"""About how long the loop (:func:`core.advance`) takes to compile from an empty cache [s] (4.5 s
CPU measured on 2 cores); each kind adds its own (:attr:`tumble.kernels.kinds.Kind.compile_s`)."""


def _specialised(kind: int, event: int, args: tuple[Any, ...]) -> Callable[..., tuple[Any, Any]]:
    """:func:`core.advance` for the kernel kind ``kind`` watching the event ``event``: the
    loop, compiled once for every kind, with the kind's compiled functions and the event's
    bound to it (:mod:`~.functions`), as ``entry(*args)``.

    Each piece compiles on first use and is cached on disk like any other signature; the
    batches run the same ones. The entry is kept per kind, event and writability of the
    arrays (the only part of the loop's argument types that varies between runs): a short
    run (an averaged one) would feel the lookups again (~0.5 ms).
    """
    key = (kind, event, *(a.flags.writeable if isinstance(a, np.ndarray) else type(a)
                          for a in args))  # fmt: skip
    entry = _ENTRIES.get(key)
    if entry is None:
        estimate = KINDS[kind].compile_s + (LOOP_COMPILE_S if not _LOOPS else 0.0)
        with compile_notice(estimate):  # from the disk cache in well under a second
            fns = addresses(kind, event)
            loop = _LOOPS.get(key[2:])
            if loop is None:
                signature = (numba.typeof(fns), *(numba.typeof(a) for a in args))
                with compile_lock(f"advance-{signature}"):
                    loop = cast(Any, core.advance).compile(signature)
                _LOOPS[key[2:]] = loop
            entry = functools.partial(loop, fns)
        _ENTRIES[key] = entry
    return entry


@dataclass(frozen=True)
class Solution:
    """Result of a compiled run.

    Attributes
    ----------
    status : int
        0 on success; −1 if the step size fell below the resolution of t; −2 if the state
        stopped being finite; 1 if the run was stopped before its end; 3 if it stopped at the
        first zero of a terminal event (at ``t``).
    t : float
        Time reached.
    y : ndarray
        State at ``t``.
    nfev : int
        Right-hand-side evaluations.
    ts, ys : ndarray
        Step times and states (when recorded), the start included.
    F : ndarray, shape (steps, 7, n)
        Coefficients of the interpolant on each step (when dense).
    y_eval : ndarray
        States at the requested ``t_eval``.
    event_t, event_signs, event_y : ndarray
        Zeros of the event function, its sign just before each, and the states there.
    """

    status: int
    t: float
    y: FloatArray
    nfev: int
    ts: FloatArray
    ys: FloatArray
    F: FloatArray
    y_eval: FloatArray
    event_t: FloatArray
    event_signs: FloatArray
    event_y: FloatArray

    @property
    def message(self) -> str:
        """Why the integration stopped early (empty on success)."""
        return status_message(self.status)

    def __call__(self, t: ArrayLike) -> FloatArray:
        """Dense output at times ``t`` within the recorded steps, shape (m, n)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.F.shape[0] == 0:
            raise ValueError("this solution was computed without dense output")
        return evaluate_dense(self.ts, self.ys, self.F, np.ascontiguousarray(t))  # type: ignore[no-any-return]


class Integration:
    """A compiled run that advances in chunks of steps and can be stopped between them.

    Parameters
    ----------
    kernel : Kernel
        The right-hand side.
    y0 : array_like
        State at ``t0``.
    t_end : float
        Final time [the kernel's time unit].
    options : Options
        Tolerances, what to keep and the event to locate (``max_steps`` is set per call of
        :meth:`advance`).
    t0 : float
        Initial time.
    t_eval : array_like, optional
        Ascending times in [t0, t_end] at which to keep states (``Solution.y_eval``).

    Examples
    --------
    >>> run = Integration(kernel, y0, 1e6, Options(rtol=1e-10, atol=1e-12, record=False),
    ...                   t_eval=np.linspace(0.0, 1e6, 101))
    >>> while not run.advance(max_steps=10_000):
    ...     pass  # check a deadline, an interrupt, the memory here
    >>> sol = run.solution()
    """

    def __init__(
        self,
        kernel: Kernel,
        y0: ArrayLike,
        t_end: float,
        options: Options,
        *,
        t0: float = 0.0,
        t_eval: ArrayLike | None = None,
    ) -> None:
        self.kernel = kernel
        p = kernel.params
        self._params = p if p.flags.writeable else p.copy()
        self.t_end = float(t_end)
        self.options = options._replace(
            rtol=float(options.rtol),
            atol=float(options.atol),
            first_step=starting_step(kernel.kind, options.first_step),
            record=bool(options.record),
            dense=bool(options.dense and options.record),
            event=int(kernel.event),
            terminal=bool(kernel.terminal),
        )
        self.y = np.array(y0, dtype=np.float64)  # updated in place by the compiled code
        self._f = np.empty_like(self.y)
        self.t_eval = np.empty(0) if t_eval is None else np.ascontiguousarray(t_eval, float)
        self._y_eval = np.full(self.t_eval.size * self.y.size, np.nan)
        self.progress = Progress(core.FRESH, float(t0), 0.0, 1.0, 0, 0, 0)
        self._chunks: list[Chunk] = []
        self._entry: Callable[..., tuple[Any, Any]] | None = None
        self.abandoned = False  # a call that did not return (or was interrupted) ended it
        self._watched_steps = WATCHED_FIRST_STEPS

    def _args(self, max_steps: int) -> tuple[Any, ...]:
        """The arguments of :func:`core.advance` after its compiled functions (the parameters
        as a writable array: the functions' types are fixed)."""
        opts = self.options._replace(max_steps=int(max_steps))
        return (self._params, self.t_end, opts, self.progress, self.y, self._f,
                self.t_eval, self._y_eval)  # fmt: skip

    @property
    def done(self) -> bool:
        """Whether the run reached ``t_end`` or failed."""
        return self.progress.status not in (core.FRESH, core.RUNNING)

    def advance(self, max_steps: int | None = None) -> bool:
        """Take at most ``max_steps`` more steps (None: to the end); return :attr:`done`."""
        if self.done or self.abandoned:
            return True
        if any_armed():  # a user's compiled torque, which may never return
            return self._advance_watched(max_steps)
        args = self._args(0 if max_steps is None else max(1, int(max_steps)))
        with _signals_held():  # compiling, then the call: neither survives an interrupt
            self._compiled(args)
            with in_call():
                progress, chunk = self._entry(*args)  # type: ignore[misc]
        return self._record(progress, chunk)

    def _compiled(self, args: tuple[Any, ...]) -> None:
        """The compiled entry for ``args``, looked up (or compiled) on first use."""
        if self._entry is None:
            self._entry = _specialised(self.kernel.kind, self.options.event, args)

    def _record(self, progress: Any, chunk: Any) -> bool:
        """A compiled call's results kept; a fault of a user's torque in it raised."""
        self.progress = Progress(*progress)
        self._chunks.append(Chunk(*chunk))
        raise_fault()  # a user's compiled torque that failed in this chunk: its own error
        return self.done

    def _advance_watched(self, max_steps: int | None) -> bool:
        """:meth:`advance` with each compiled call watched (:func:`_watched`), in chunks that
        start at :data:`WATCHED_FIRST_STEPS` steps and double: a call that never returns is
        left behind with the state, samples and chunks from before it kept."""
        left = None if max_steps is None else max(1, int(max_steps))
        while True:
            n = self._watched_steps if left is None else min(self._watched_steps, left)
            args = self._args(n)
            with _signals_held():
                self._compiled(args)
            self._watched_steps = min(2 * self._watched_steps, CHUNK_STEPS)
            y_before, steps_before = self.y.copy(), self.progress.n_steps
            try:
                progress, chunk = _watched(self._entry, args)  # type: ignore[arg-type]
            except BaseException:
                # The call may still be running and writing to the state and samples: they
                # are set aside, the run is over, and what it computed before stays readable.
                self.y, self._y_eval = y_before, self._y_eval.copy()
                self.abandoned = True
                raise
            if self._record(progress, chunk):
                return True
            if left is not None:
                left -= self.progress.n_steps - steps_before
                if left <= 0:
                    return False

    def take(self) -> Solution:
        """What the run computed since the last :meth:`take` (steps, events), and forget it;
        ``y_eval`` holds every sample passed so far. A caller that consumes the run chunk by
        chunk this way keeps its memory bounded by the samples, whatever the steps."""
        piece = self.solution()
        self._chunks.clear()
        return piece

    def solution(self) -> Solution:
        """What the run has computed so far."""
        n = self.y.size
        pieces = [_cut(c, n, self.options.dense) for c in self._chunks] or [_nothing(n)]
        ts, ys, F, ev_t, ev_s, ev_y = (_join([pc[k] for pc in pieces], k < 2) for k in range(6))
        if ts.size == 0:
            ts, ys = np.array([self.progress.t]), self.y[None, :].copy()
        return Solution(
            int(self.progress.status),
            float(self.progress.t),
            self.y.copy(),
            int(self.progress.nfev),
            ts,
            ys,
            F if self.options.dense else np.empty((0, N_INTERPOLANT, n)),
            self._y_eval.reshape(-1, n),
            ev_t,
            ev_s,
            ev_y,
        )


def _cut(c: Chunk, n: int, dense: bool) -> tuple[FloatArray, ...]:
    """A chunk's buffers cut to what it filled: ts, ys (start included), F, events."""
    kept = c.n_steps + 1 if c.ts.size > 1 else 1
    m = c.n_events
    return (
        c.ts[:kept],
        c.ys[: kept * n].reshape(kept, n),
        c.F[: c.n_steps * N_INTERPOLANT * n].reshape(-1, N_INTERPOLANT, n)
        if dense
        else np.empty((0, N_INTERPOLANT, n)),
        c.event_t[:m],
        c.event_signs[:m],
        c.event_y[: m * n].reshape(m, n),
    )


def _nothing(n: int) -> tuple[FloatArray, ...]:
    """The pieces of no chunk (a run whose call did not return before any other)."""
    return (np.empty(0), np.empty((0, n)), np.empty((0, N_INTERPOLANT, n)), np.empty(0),
            np.empty(0), np.empty((0, n)))  # fmt: skip


def _join(parts: list[FloatArray], starts_with_point: bool) -> FloatArray:
    """Concatenate the chunks' pieces; each chunk after the first repeats the previous end
    point first, which is dropped."""
    if len(parts) == 1:
        return parts[0]
    if starts_with_point:
        parts = [parts[0]] + [p[1:] for p in parts[1:]]
    return np.concatenate(parts)


def solve(
    kernel: Kernel,
    y0: ArrayLike,
    t_end: float,
    *,
    t0: float = 0.0,
    rtol: float,
    atol: float,
    t_eval: ArrayLike | None = None,
    record: bool = True,
    dense: bool = True,
    first_step: float | None = None,
) -> Solution:
    """Integrate a compiled kernel from ``t0`` to ``t_end`` with DOP853 (in chunks of
    :data:`CHUNK_STEPS` steps, between which an interrupt is honoured).

    Parameters
    ----------
    kernel : Kernel
        The compiled right-hand side.
    y0 : array_like
        Initial state, at ``t0``.
    t_end : float
        End of the run [the kernel's time unit].
    rtol, atol : float
        Tolerances of the local error (as scipy's DOP853 interprets them).
    t_eval : array_like, optional
        Ascending times in [t0, t_end] at which to return states (``y_eval``).
    record : bool
        Keep every step's time and state.
    dense : bool
        Keep the interpolant of every step (needs ``record``), for evaluation anywhere.
    first_step : float, optional
        Initial step size; by default Hairer's estimate.

    Returns
    -------
    Solution
        Check ``status`` (or use :func:`tumble.integrate.integrate`, which raises on failure).
    """
    options = Options(rtol, atol, first_step or 0.0, record, dense)
    run = Integration(kernel, y0, t_end, options, t0=t0, t_eval=t_eval)
    while not run.advance(CHUNK_STEPS):  # Python runs between chunks: Ctrl-C is honoured
        pass
    return run.solution()


def _pool_map(work: Callable[[int], None], count: int, threads: int | None) -> None:
    """``work(i)`` for i < count on a thread pool (the compiled code releases the GIL)."""
    workers = max(1, min(_MAX_THREADS if threads is None else int(threads), _MAX_THREADS, count))
    if workers == 1:
        for i in range(count):
            work(i)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            list(pool.map(work, range(count)))


def solve_many(
    kernels: Sequence[Kernel],
    y0: Sequence[ArrayLike],
    t_end: Sequence[float],
    *,
    rtol: float,
    atol: float,
    threads: int | None = None,
) -> list[tuple[Solution, float]]:
    """:func:`solve` of many problems at once, over a thread pool, with dense output.

    The kernels may differ in kind and parameters. Each problem runs through the integrator
    :func:`solve` uses, with the GIL released, so each result equals that of :func:`solve`
    to the bit, whatever the number of threads.

    Parameters
    ----------
    kernels : sequence of Kernel
        The right-hand sides.
    y0 : sequence of array_like
        Initial states at t = 0, one per kernel.
    t_end : sequence of float
        Final times, one per kernel [the kernel's time unit].
    rtol, atol : float
        Tolerances.
    threads : int, optional
        Number of threads (default: :func:`available_threads`).

    Returns
    -------
    list of (Solution, float)
        Per problem, its solution (check ``status``) and the seconds it took [s].
    """
    if not len(kernels) == len(y0) == len(t_end):
        raise ParameterError(
            f"solve_many needs as many initial states and end times as kernels, got "
            f"{len(kernels)}, {len(y0)} and {len(t_end)}"
        )
    options = Options(float(rtol), float(atol))
    runs = [Integration(k, y, t, options) for k, y, t in zip(kernels, y0, t_end, strict=True)]
    # Look every kind's specialisation up first: compiling inside the pool would compile
    # the same function in several threads at once.
    entries = {
        (r.kernel.kind, r.options.event): _specialised(r.kernel.kind, r.options.event, r._args(0))
        for r in runs
    }
    out: list[Any] = [None] * len(runs)

    def one(i: int) -> None:
        run = runs[i]
        run._entry = entries[run.kernel.kind, run.options.event]
        start = time.perf_counter()
        run.advance()
        out[i] = (run.solution(), time.perf_counter() - start)

    _pool_map(one, len(runs), threads)
    return out


@dataclass(frozen=True)
class BatchResult:
    """Result of :func:`solve_batch`: states (N, len(t_eval), n), and per trajectory the
    status (0 = success), the time reached and the right-hand-side evaluations."""

    y: FloatArray
    status: Any
    t: FloatArray
    nfev: Any


def solve_batch(
    kind: int,
    params: ArrayLike,
    y0: ArrayLike,
    t_end: ArrayLike,
    t_eval: ArrayLike,
    *,
    rtol: float,
    atol: float,
    threads: int | None = None,
) -> BatchResult:
    """Integrate N trajectories of one kernel kind in parallel over the cores.

    Parameters
    ----------
    kind : int
        ``KIND_*`` of every trajectory.
    params : array_like, shape (N, m)
        One parameter array per trajectory (equal length; pad with zeros).
    y0 : array_like, shape (N, n)
        Initial states at t = 0.
    t_end : float or array_like, shape (N,)
        Final times.
    t_eval : array_like
        Ascending sample times, shared by all trajectories (beyond a trajectory's ``t_end``
        its samples are NaN).
    rtol, atol : float
        Tolerances.
    threads : int, optional
        Number of threads (default: :func:`available_threads`). Each runs whole trajectories
        through the integrator :func:`solve` uses, with the GIL released: the results do not
        depend on the number of threads.

    Returns
    -------
    BatchResult
    """
    P = np.ascontiguousarray(params, dtype=np.float64)
    Y0 = np.ascontiguousarray(y0, dtype=np.float64)
    if P.ndim != 2 or Y0.ndim != 2 or P.shape[0] != Y0.shape[0]:
        raise ParameterError(
            f"solve_batch needs params (N, m) and y0 (N, n) with the same N, "
            f"got {P.shape} and {Y0.shape}"
        )
    N, n = Y0.shape
    T = np.broadcast_to(np.asarray(t_end, dtype=float), (N,))
    te = np.ascontiguousarray(t_eval, dtype=np.float64)
    y = np.empty((N, te.size, n))
    status = np.empty(N, dtype=np.int64)
    t = np.empty(N)
    nfev = np.empty(N, dtype=np.int64)
    if N == 0:
        return BatchResult(y, status, t, nfev)
    options = Options(float(rtol), float(atol), record=False, dense=False)
    runs = [Integration(Kernel(int(kind), P[i]), Y0[i], float(T[i]), options, t_eval=te)
            for i in range(N)]  # fmt: skip
    # The same compiled integrator as solve() (no second, parallel compile), looked up once;
    # it releases the GIL, so threads run the trajectories concurrently.
    entry = _specialised(int(kind), runs[0].options.event, runs[0]._args(0))

    def one(i: int) -> None:
        run = runs[i]
        run._entry = entry
        run.advance()
        status[i], t[i], nfev[i] = run.progress.status, run.progress.t, run.progress.nfev
        y[i] = run.solution().y_eval

    _pool_map(one, N, threads)
    return BatchResult(y, status, t, nfev)
