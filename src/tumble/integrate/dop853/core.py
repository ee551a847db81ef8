"""The compiled DOP853 driver loop: a run that advances in chunks of steps.

:func:`advance` integrates until ``t_end`` or until it has taken ``Options.max_steps`` steps,
and returns where the run stands (:class:`Progress`) with what it recorded on the way
(:class:`Chunk`). The state ``y`` and its derivative ``f`` are updated in place, so that Python
can call it again to resume, stop between chunks (an interrupt, a time limit), or keep only the
requested samples: memory is then bounded by ``t_eval``, not by the number of steps.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from tumble._typing import FloatArray
from tumble.integrate.dop853.dense import dense_coefficients, interpolate
from tumble.integrate.dop853.events import event_root
from tumble.integrate.dop853.functions import EVENT, RHS, STEP, function_at
from tumble.integrate.dop853.steps import STEP_OK, attempt_step, initial_step, min_step
from tumble.integrate.dop853.tableau import N_INTERPOLANT, N_STAGES, N_STAGES_EXTENDED
from tumble.kernels.codes import EVENT_NONE
from tumble.kernels.jit import ENTRY, INLINE, INNER, INNER_INLINE, KERNEL, jit

__all__ = ["BAD_START", "FRESH", "NOT_FINITE", "OK", "RUNNING", "SLOW_START", "STEP_TOO_SMALL",
           "STOPPED", "Chunk", "Options", "Progress", "advance"]  # fmt: skip

_NF = N_INTERPOLANT  # rows of a step's interpolant

# Status of a run.
OK = 0  # reached t_end
STEP_TOO_SMALL = -1  # the step size fell below the resolution of t
NOT_FINITE = -2  # the state stopped being finite
BAD_START = -3  # the right-hand side is not finite at the start (a state it refuses)
RUNNING = 1  # stopped after max_steps, to be resumed
FRESH = 2  # not started: advance() first evaluates f and chooses the starting step
STOPPED = 3  # reached the first zero of a terminal event function (a breakpoint)

SLOW_START = -1.0
"""``Options.first_step`` of a slow system (averaged equations, a kind declared ``slow``):
Hairer's starting step, but no shorter than the time in which the state changes by 1 %
(:func:`~tumble.integrate.dop853.steps.initial_step`)."""


class Options(NamedTuple):
    """How to integrate: one typed record, passed as it is to the compiled code."""

    rtol: float  # relative tolerance of the local error (as scipy's DOP853 reads it)
    atol: float  # absolute tolerance
    first_step: float = 0.0  # initial step size; 0: Hairer's estimate; SLOW_START: see there
    record: bool = True  # keep every step's time and state
    dense: bool = True  # keep every step's interpolant (with record)
    event: int = EVENT_NONE  # EVENT_* whose sign changes are located
    max_steps: int = 0  # steps per call of advance() before it returns; 0: no limit
    terminal: bool = False  # stop at the event's first zero (the run ends there, STOPPED)


class Progress(NamedTuple):
    """Where a run stands between two calls of :func:`advance`."""

    status: int  # FRESH, RUNNING, OK or a failure
    t: float  # time reached
    h_abs: float  # size of the next step to try
    g: float  # event function at t
    nfev: int  # right-hand-side evaluations so far
    n_steps: int  # accepted steps so far
    n_eval: int  # samples of t_eval filled so far


class Chunk(NamedTuple):
    """What one call of :func:`advance` recorded; flat buffers, cut by the caller.

    ``ts`` and ``ys`` start with the state the chunk started from, then hold one entry per
    step (``n_steps`` in all); ``F`` holds each step's 7 interpolant rows. Events: times, the
    sign of the event function before each, and the states there (``n_events`` of them).
    """

    n_steps: int
    ts: FloatArray
    ys: FloatArray
    F: FloatArray
    event_t: FloatArray
    event_signs: FloatArray
    event_y: FloatArray
    n_events: int


@jit(INNER)
def _grow(a: FloatArray) -> FloatArray:
    """``a`` with twice the size, its values first."""
    b = np.empty(2 * a.size)
    for i in range(a.size):
        b[i] = a[i]
    return b


@jit(INLINE)
def _copy(src: FloatArray, dst: FloatArray, at: int) -> None:
    """dst[at : at + src.size] = src."""
    for j in range(src.size):
        dst[at + j] = src[j]


@jit(INLINE)
def _finite(y: FloatArray) -> bool:
    """Whether every component of y is finite."""
    for j in range(y.size):
        if not math.isfinite(y[j]):
            return False
    return True


@jit(INNER)
def _start(
    rhs_fn: Any, event_fn: Any, p: FloatArray, t_end: float, opts: Options, prog: Progress,
    y: FloatArray, f: FloatArray, t_eval: FloatArray, y_eval: FloatArray,
) -> Progress:  # fmt: skip
    """Evaluate f at the start, choose the first step, fill the samples at or before t0."""
    n = y.size
    t0 = prog.t
    ie = prog.n_eval
    while ie < t_eval.size and t_eval[ie] <= t0:
        _copy(y, y_eval, ie * n)
        ie += 1
    rhs_fn(t0, y, p, f)
    nfev = 1
    h_abs = 0.0
    if t_end > t0:
        if opts.first_step > 0.0:
            h_abs = min(opts.first_step, t_end - t0)
        else:
            h_abs = initial_step(rhs_fn, p, t0, y, f, t_end, opts.rtol, opts.atol,
                                 opts.first_step < 0.0)  # fmt: skip
            nfev += 1
    g = event_fn(t0, y, p) if opts.event != EVENT_NONE else 1.0
    return Progress(RUNNING, t0, h_abs, g, nfev, 0, ie)


@jit(INNER_INLINE)
def _sample(
    t: float, h: float, t_new: float, y: FloatArray, y_new: FloatArray, F: FloatArray,
    t_eval: FloatArray, y_eval: FloatArray, ie: int, tmp: FloatArray,
) -> int:  # fmt: skip
    """Fill the samples of t_eval inside the step (t, t_new]; return the next index."""
    n = y.size
    while ie < t_eval.size and t_eval[ie] <= t_new:
        if t_eval[ie] == t_new:
            _copy(y_new, y_eval, ie * n)
        else:
            interpolate(F, y, (t_eval[ie] - t) / h, tmp)
            _copy(tmp, y_eval, ie * n)
        ie += 1
    return ie


@jit(KERNEL)
def _step_events(
    event_fn: Any, p: FloatArray, t: float, h: float, y: FloatArray, y_new: FloatArray,
    F: FloatArray, g_old: float, found: FloatArray, states: FloatArray, tmp: FloatArray,
) -> tuple[float, int]:  # fmt: skip
    """Sign changes of the event function on the step, sampled at quarters so that no swing
    is missed: up to four, as (time, sign before) rows of ``found`` and states in the rows of
    ``states``. Returns the event function at the end of the step and the number found."""
    count = 0
    xa, ga = 0.0, g_old
    for quarter in range(1, 5):
        xb = 0.25 * quarter
        if quarter == 4:
            gb = event_fn(t + h, y_new, p)
        else:
            interpolate(F, y, xb, tmp)
            gb = event_fn(t + xb * h, tmp, p)
        if (ga < 0.0 < gb) or (gb < 0.0 < ga):
            x = event_root(event_fn, p, t, h, y, F, xa, ga, xb, gb, tmp)
            found[count, 0] = t + x * h
            found[count, 1] = 1.0 if ga > 0.0 else -1.0
            interpolate(F, y, x, states[count])
            count += 1
        if gb != 0.0:
            xa, ga = xb, gb
    return ga, count


@jit(INLINE)
def _store(dst: FloatArray, row: int, src: FloatArray) -> None:
    """Row ``row`` of the flat buffer ``dst`` (rows of src.size) = src."""
    _copy(src, dst, row * src.size)


@jit(INNER)
def _fit(buffer: FloatArray, rows: int, width: int) -> FloatArray:
    """``buffer`` (flat rows of ``width``), grown by doubling until it holds ``rows`` rows."""
    while rows * width > buffer.size:
        buffer = _grow(buffer)
    return buffer


@jit(ENTRY)
def advance(
    fns: tuple[int, ...], p: FloatArray, t_end: float, opts: Options, prog: Progress,
    y: FloatArray, f: FloatArray, t_eval: FloatArray, y_eval: FloatArray,
) -> tuple[tuple[Any, ...], tuple[Any, ...]]:  # fmt: skip
    """Integrate from ``prog.t`` towards ``t_end`` (at most ``opts.max_steps`` steps).

    The right-hand side comes as the compiled functions of its kind, its step and its
    right-hand side, and the event function the run watches (``opts.event``), by their
    addresses ``fns`` (:func:`~.functions.addresses`): this loop is compiled once for every
    kind.

    ``y`` holds the state at ``prog.t`` and ``f`` its derivative; both are updated in place.
    Samples at the times ``t_eval`` go to the flat ``y_eval`` as the run passes them. Returns
    the fields of the new :class:`Progress` and of the :class:`Chunk`, as plain tuples.
    """
    step_fn = function_at(fns[0], fns[1], STEP)
    rhs_fn = function_at(fns[2], fns[3], RHS)
    event_fn = function_at(fns[4], fns[5], EVENT)
    n = y.size
    if prog.status == FRESH:
        prog = _start(rhs_fn, event_fn, p, t_end, opts, prog, y, f, t_eval, y_eval)
    t, h_abs, g, nfev, ie = prog.t, prog.h_abs, prog.g, prog.nfev, prog.n_eval
    # The record: the start, then one row per step (buffers grow by doubling).
    dense = opts.dense and opts.record
    cap = 1024 if opts.record else 1
    ts, ys, Fs = np.empty(cap), np.empty(cap * n), np.empty((cap if dense else 1) * _NF * n)
    ts[0] = t
    _store(ys, 0, y)
    ev_t, ev_s, ev_y = np.empty(16), np.empty(16), np.empty(16 * n)
    found, states = np.empty((4, 2)), np.empty((4, n))
    K, F = np.empty((N_STAGES_EXTENDED, n)), np.empty((_NF, n))
    y_new, tmp = np.empty(n), np.empty(n)
    _copy(f, K[0], 0)
    status, n_rec, n_ev = RUNNING, 0, 0
    if not (_finite(f) and h_abs == h_abs):  # no step can start from there
        status = BAD_START
    # A terminal event stops the run at its first zero: the step that crosses it is not
    # taken; the run goes on to the zero instead, as if it were the end, with the usual step
    # control (its last step lands on it), and the event is not looked for again.
    looking = opts.event != EVENT_NONE
    t_stop = t_end
    while status == RUNNING and t < t_stop and (opts.max_steps <= 0 or n_rec < opts.max_steps):
        step, h, h_abs, used = attempt_step(step_fn, rhs_fn, p, t, t_stop, h_abs, y, K, y_new,
                                            tmp, opts.rtol, opts.atol)  # fmt: skip
        nfev += used
        if step != STEP_OK:
            status = STEP_TOO_SMALL
            break
        if not _finite(y_new):
            status = NOT_FINITE
            break
        t_new = t + h
        if opts.dense or looking or (ie < t_eval.size and t_eval[ie] <= t_new):
            dense_coefficients(step_fn, rhs_fn, p, t, h, y, y_new, K, F, tmp)
            nfev += N_STAGES_EXTENDED - N_STAGES - 1
        if looking:
            g_new, count = _step_events(event_fn, p, t, h, y, y_new, F, g, found, states, tmp)
            if count > 0 and opts.terminal:
                looking = False  # this step is not taken: the run ends at the zero instead
                ev_t, ev_s = _fit(ev_t, n_ev + 1, 1), _fit(ev_s, n_ev + 1, 1)
                ev_y = _fit(ev_y, n_ev + 1, n)
                ev_t[n_ev], ev_s[n_ev] = found[0, 0], found[0, 1]
                _store(ev_y, n_ev, states[0])
                n_ev += 1
                if found[0, 0] - t <= min_step(t):  # already there, to the resolution of t
                    t_stop = t
                    break
                t_stop, h_abs = found[0, 0], found[0, 0] - t
                continue
            g = g_new
            if count > 0:
                ev_t, ev_s = _fit(ev_t, n_ev + count, 1), _fit(ev_s, n_ev + count, 1)
                ev_y = _fit(ev_y, n_ev + count, n)
                for k in range(count):
                    ev_t[n_ev], ev_s[n_ev] = found[k, 0], found[k, 1]
                    _store(ev_y, n_ev, states[k])
                    n_ev += 1
        ie = _sample(t, h, t_new, y, y_new, F, t_eval, y_eval, ie, tmp)
        if opts.record:
            if n_rec + 2 > ts.size:
                ts, ys = _fit(ts, n_rec + 2, 1), _fit(ys, n_rec + 2, n)
            ts[n_rec + 1] = t_new
            _store(ys, n_rec + 1, y_new)
            if dense:
                if (n_rec + 1) * _NF * n > Fs.size:
                    Fs = _fit(Fs, n_rec + 1, _NF * n)
                for r in range(_NF):
                    _copy(F[r], Fs, (n_rec * _NF + r) * n)
        n_rec += 1
        t = t_new
        for j in range(n):
            y[j] = y_new[j]
            K[0, j] = K[N_STAGES, j]
    if status == RUNNING and t >= t_end:
        status = OK
    elif status == RUNNING and t >= t_stop:
        status = STOPPED
    _copy(K[0], f, 0)
    # Plain tuples, not the named ones: numba boxes a named tuple by calling its class, Python
    # code during which a signal handler that raises (Ctrl-C, an alarm) used to leave a
    # half-built object and crash the interpreter; a plain tuple is built in C.
    progress = (status, t, h_abs, g, nfev, prog.n_steps + n_rec, ie)
    return progress, (n_rec, ts, ys, Fs, ev_t, ev_s, ev_y, n_ev)
