"""Averaged ensembles: the averaged equations of many points of one model in blocks of
compiled runs over a thread pool (:func:`tumble.integrate.simulate_batch` with
``method = "averaged"``).

Each thread takes a block of points at a time: it builds their averaged forms (Python), then
advances the whole block piece by piece in one compiled call per piece
(:func:`tumble.integrate.dop853.block.advance_block`, the GIL released) and turns the samples
into columns. The Python work of one thread overlaps the compiled work of the others.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import IntegrationError, TumbleError
from tumble.integrate import dop853
from tumble.integrate.dop853.block import block_entry, empty_block
from tumble.integrate.dop853.core import BAD_START, OK, RUNNING, STOPPED, Chunk
from tumble.integrate.dop853.driver import _cut, in_call, starting_step
from tumble.integrate.limits import FIRST_CHUNK, MAX_STEPS, pace_message
from tumble.integrate.ode import compiled_breakpoints, joined_pieces, restart_at, split_plan
from tumble.integrate.simulate import each_on_threads, simulate, start_refusal
from tumble.integrate.trajectory import (
    RunSpec,
    Trajectory,
    integrated,
    step_legs,
    turning_angles,
    unwrap_columns,
)
from tumble.kernels import EVENT_NONE, Kernel
from tumble.kernels.user import raise_fault
from tumble.models.base import AveragedForm, AveragingOptions, Breakpoint, Model

__all__ = ["BLOCK_SIZE", "averaged_batch"]

P = TypeVar("P")
S = TypeVar("S")

BLOCK_SIZE = 32
"""Points per block: a thread's unit of work (large enough that the compiled call dominates
its Python, small enough that every thread gets several)."""


@dataclass
class _Point(Generic[P, S]):
    """One point of a block: its form, kernel and breakpoints."""

    index: int
    tau: FloatArray  # its sample times
    params: P
    initial: S
    form: AveragedForm[P, S]
    kernel: Kernel
    y0: FloatArray
    stops: list[float]  # breakpoint times inside (0, t_end), ascending, then t_end
    surface: Breakpoint | None  # the one surface, with its compiled event
    samples: FloatArray = field(default_factory=lambda: np.empty(0))  # (tau.size, dim)
    nfev: int = 0
    pieces: list[dop853.Solution] = field(default_factory=list)  # with ``dense``


def averaged_batch(
    model: Model[P, S],
    params: Sequence[P],
    initials: Sequence[S],
    taus: Sequence[FloatArray],
    *,
    rtol: float,
    atol: float,
    averaging: AveragingOptions,
    threads: int | None,
    max_steps: int = MAX_STEPS,
    dense: bool = False,
) -> list[Trajectory | TumbleError]:
    """The averaged method of many points, each with its sample times ``taus[i]`` (all of one
    length; see :func:`tumble.integrate.simulate_batch`)."""
    assert model.averaged is not None
    options = model.averaged.check(averaging)
    n_points = len(params)
    if len(initials) != n_points:
        raise ValueError(f"{n_points} parameter sets but {len(initials)} initial states")
    out: list[Trajectory | TumbleError | None] = [None] * n_points
    # A form's kernel is a function of the parameters alone: points that share both the
    # function and the parameter object (an ensemble over initial states) share the kernel.
    # The key holds the function itself (alive while cached) and the id of a parameter set
    # that ``params`` keeps alive: no id is reused while the batch runs.
    kernels: _Kernels[P] = {}

    def single(i: int) -> Trajectory | TumbleError:
        try:
            return simulate(model, params[i], initials[i], taus[i], "averaged", rtol=rtol,
                            atol=atol, averaging=averaging, max_steps=max_steps)  # fmt: skip
        except TumbleError as exc:
            return exc

    def run_block(indices: Sequence[int]) -> None:
        points: list[_Point[P, S]] = []
        for i in indices:
            try:
                pt = _prepare(model, options, kernels, i, params[i], initials[i], taus[i])
            except TumbleError as exc:
                out[i] = exc
                continue
            if pt is not None:
                points.append(pt)
            else:
                out[i] = single(i)
        groups: dict[tuple[int, int, int, int], list[_Point[P, S]]] = {}
        for pt in points:
            key = (pt.kernel.kind, pt.kernel.params.size, pt.y0.size, _watched(pt))
            groups.setdefault(key, []).append(pt)
        for group in groups.values():
            start = time.perf_counter()
            _integrate_group(model.name, group, rtol, atol, max_steps, dense, out)
            wall = (time.perf_counter() - start) / len(group)
            for pt in group:
                if out[pt.index] is None:
                    run = RunSpec(model, pt.params, pt.initial, pt.tau, rtol, atol, max_steps)
                    out[pt.index] = _finished(run, pt, wall, dense, single)

    blocks = [range(k, min(k + BLOCK_SIZE, n_points)) for k in range(0, n_points, BLOCK_SIZE)]
    each_on_threads(run_block, blocks, threads)
    done = [o for o in out if o is not None]
    assert len(done) == n_points  # every point is a Trajectory or its error
    return done


_Kernels = dict[tuple[Callable[[P], Kernel | None], int], Kernel | None]
"""The kernels built so far, by the form's kernel function and the id of the parameters."""


def _prepare(
    model: Model[P, S],
    options: AveragingOptions,
    kernels: _Kernels[P],
    i: int,
    p: P,
    initial: S,
    tau: FloatArray,
) -> _Point[P, S] | None:
    """Point ``i``'s compiled run, or None for the single path (no kernel, nothing to
    integrate); raises the TumbleError of an invalid point."""
    t_end = float(tau[-1])
    model.check(p, "averaged")
    form = model.averaged.form(p, initial, options)  # type: ignore[union-attr]
    if t_end == 0.0 or form.kernel is None or not compiled_breakpoints(form.breakpoints):
        return None
    key = (form.kernel, id(p))
    if key not in kernels:
        kernels[key] = form.kernel(p)
    kernel = kernels[key]
    if kernel is None:
        return None
    kernel.check_end(t_end)
    y0 = np.asarray(form.initial_state(p, initial), dtype=np.float64)
    stops, surface = split_plan(form.breakpoints, y0, t_end)
    return _Point(i, tau, p, initial, form, kernel, y0, stops, surface)


def _finished(
    run: RunSpec[P, S],
    pt: _Point[P, S],
    wall: float,
    dense: bool,
    single: Callable[[int], Trajectory | TumbleError],
) -> Trajectory | TumbleError:
    """The Trajectory of a point whose run is done, ``wall`` [s] its share of the block's
    time: with ``dense`` from its pieces, as :func:`simulate` builds it, else from its
    samples."""
    if not dense:
        return _trajectory(run.model, pt, wall, single)
    sol = joined_pieces(pt.pieces, run.what(pt.form))
    return integrated(run, "averaged", pt.form, sol, time.perf_counter() - wall)


def _watched(pt: _Point[Any, Any]) -> int:
    """The event (``EVENT_*``) the run of ``pt`` watches: its surface's, or none."""
    return pt.surface.event if pt.surface is not None else EVENT_NONE


def _integrate_group(
    name: str,
    group: Sequence[_Point[Any, Any]],
    rtol: float,
    atol: float,
    max_steps: int,
    dense: bool,
    out: list[Any],
) -> None:
    """Advance every run of ``group`` (one kind, one parameter length, one event watched or
    none) to its end, piece by piece; a failed run gets its IntegrationError in ``out``, the
    others their samples and evaluation counts in their ``_Point``."""
    n = len(group)
    dim = group[0].y0.size
    n_eval = group[0].tau.size
    arrays = empty_block(n, dim, n_eval)
    P = np.stack([pt.kernel.params for pt in group])
    t_eval = np.stack([pt.tau for pt in group])
    for r, pt in enumerate(group):
        arrays["Y"][r] = pt.y0
        arrays["events"][r] = _watched(pt)
    piece = np.zeros(n, dtype=np.int64)  # index into each run's stops
    spent = np.zeros(n, dtype=np.int64)  # steps of the calls that ended with the budget spent
    active = np.arange(n)
    kind = group[0].kernel.kind
    event = _watched(group[0])
    arrays["first"][:] = starting_step(kind)  # as a single run of the kind starts
    # Steps a run may take in one call: from FIRST_CHUNK, doubled each call, so that a run
    # whose pace is hopeless is refused early (as a single run is), not after its budget.
    allowance = FIRST_CHUNK
    while active.size:
        for r in active.tolist():
            arrays["T"][r] = group[r].stops[piece[r]]
        steps = min(allowance, max_steps)
        args = (active, P, arrays["T"], arrays["events"], arrays["first"], arrays["t0"],
                arrays["ie"], float(rtol), float(atol), int(steps), bool(dense), t_eval,
                arrays["Y"], arrays["F"], arrays["Y_eval"], arrays["status"],
                arrays["nfev"])  # fmt: skip
        allowance *= 2
        entry = block_entry(kind, event, args)
        with in_call():
            pieces = {int(pc[0]): pc[1:] for pc in entry(*args)}
        raise_fault()  # a user's compiled torque that failed in the block: its own error
        going = []
        for r in active.tolist():
            pt, status = group[r], int(arrays["status"][r])
            t = float(arrays["t0"][r])
            if dense:  # the piece as a Solution of the single run's integrator
                pt.pieces.append(_piece_solution(pieces[r], status, t, arrays["Y"][r], dim))
            try:
                spent[r] += steps if status == RUNNING else 0
                if _goes_on(f"{name} averaged equations {pt.form.equation}", pt, status, t,
                            arrays, r, piece, int(spent[r]), max_steps):  # fmt: skip
                    going.append(r)
            except TumbleError as exc:
                out[pt.index] = exc
        active = np.array(going, dtype=np.int64)
    for r, pt in enumerate(group):
        pt.samples = arrays["Y_eval"][r].reshape(n_eval, dim)
        pt.nfev = int(arrays["nfev"][r])


def _piece_solution(
    piece: tuple[Any, ...], status: int, t: float, y: FloatArray, dim: int
) -> dop853.Solution:
    """One run's piece of a block call (its recorded steps, evaluations, times, states and
    interpolants) as the :class:`~tumble.integrate.dop853.Solution` a single run's integrator
    returns, ending at (t, y) with ``status``."""
    n_rec, nfev, ts, ys, Fs = piece
    no_events = np.empty(0)
    chunk = Chunk(int(n_rec), ts, ys, Fs, no_events, no_events, no_events, 0)
    ts_, ys_, F_, ev_t, ev_s, ev_y = _cut(chunk, dim, True)
    return dop853.Solution(status, t, y.copy(), int(nfev), ts_, ys_, F_, np.empty((0, dim)),
                           ev_t, ev_s, ev_y)  # fmt: skip


def _goes_on(
    what: str,
    pt: _Point[Any, Any],
    status: int,
    t: float,
    arrays: dict[str, Any],
    r: int,
    piece: Any,
    spent: int,
    max_steps: int,
) -> bool:
    """Whether run ``r`` of a block goes on after a call that left it at ``t`` with
    ``status``: across its watched surface (restarted there), into its next piece, or on in
    the same piece (its budget not spent, its pace not hopeless); False at its end. Raises
    the IntegrationError of a failed run."""
    if status == STOPPED:
        surface = pt.surface
        assert surface is not None  # only a watched surface stops a run
        if surface.restart is not None:
            arrays["Y"][r] = surface.restart(t, arrays["Y"][r].copy())
        arrays["events"][r] = EVENT_NONE  # crossed at most once
        return True
    if status == OK:
        if piece[r] + 1 < len(pt.stops):
            arrays["Y"][r] = restart_at(pt.form.breakpoints, t, arrays["Y"][r].copy())
            piece[r] += 1
            return True
        return False
    if status == RUNNING:
        if spent >= max_steps:
            raise IntegrationError(
                f"{what}: run.max_steps = {max_steps} steps spent at t = {t:.6g}"
            )
        # Against the run's mean step so far, as a single run's pace (a run speeding up).
        refused = pace_message(t, float(pt.tau[-1]), float(arrays["first"][r]),
                               max_steps - spent, max_steps,
                               h_mean=t / spent if spent else None)  # fmt: skip
        if refused:
            raise IntegrationError(f"{what}: {refused}")
        return True  # the same piece, on from where it stopped
    reason = pt.form.failure() if pt.form.failure else None
    if reason is None and status == BAD_START:
        reason = start_refusal(pt.form, pt.params, t, arrays["Y"][r].copy())
    message = dop853.status_message(status)
    text = f"{what}: integration failed at t = {t:.6g}: {message}"
    if reason:
        text += f"; last refused state: {reason}"
    raise IntegrationError(text)


def _trajectory(
    model: Model[P, S],
    pt: _Point[P, S],
    wall: float,
    single: Callable[[int], Trajectory | TumbleError],
) -> Trajectory | TumbleError:
    """The Trajectory of a point of a block from its samples."""
    try:
        cols = pt.form.to_columns(pt.params, pt.initial, pt.tau, pt.samples)
        turning = turning_angles(model, pt.params, pt.form, pt.initial, pt.y0.size)
        unwrap_columns(model, pt.params, "averaged", cols, pt.initial, turning)
    except TumbleError as exc:
        return exc
    rerun: list[Trajectory] = []

    def slow(t: FloatArray) -> Any:
        # The block kept the samples only: the first call integrates this point again, alone,
        # with its dense output (the same equations and tolerances).
        if not rerun:
            again = single(pt.index)
            if isinstance(again, TumbleError):
                raise again
            rerun.append(again)
        return rerun[0].slow(t)

    return Trajectory(
        pt.tau,
        cols,
        "averaged",
        pt.form.name,
        wall,
        pt.nfev,
        slow,
        np.empty(0),
        "numba",
        legs=step_legs(pt.form, float(pt.tau[-1])),
    )
