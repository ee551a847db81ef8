"""Run one method of a registered model at requested sample times.

The methods are ``full`` (a full form of the equations of motion, integrated), ``averaged``
(the averaged equations, integrated) and ``closed_form`` (the averaged motion evaluated in
closed form). Each returns the values at exactly the requested times.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Literal, TypeVar

import numpy as np

from tumble._progress import advanced
from tumble._typing import ArrayLike, FloatArray
from tumble.errors import IntegrationError, ParameterError, TumbleError, warn
from tumble.integrate import dop853
from tumble.integrate.limits import MAX_STEPS, pace_message
from tumble.integrate.ode import (
    DEFAULT_ATOL,
    DEFAULT_RTOL,
    check_times,
    compiled_breakpoints,
    integrate,
)
from tumble.integrate.trajectory import (
    RunSpec,
    Trajectory,
    UnwrapStream,
    integrated,
    step_legs,
    turning_angles,
    unwrap_columns,
)
from tumble.kernels import Kernel
from tumble.models.base import (
    AveragedForm,
    AveragingOptions,
    ClosedForm,
    Columns,
    FullForm,
    Model,
)

__all__ = [
    "INTEGRATORS",
    "Integrator",
    "Method",
    "Trajectory",
    "integrator_named",
    "simulate",
    "simulate_batch",
]

Method = Literal["full", "averaged", "closed_form"]

P = TypeVar("P")
S = TypeVar("S")
J = TypeVar("J")

DEFAULT_AVERAGING = AveragingOptions()
"""The paper's averaged equations in the model's default coordinates, from the given state."""

_Job = tuple[int, Kernel, FloatArray]  # a point of a batch: its index, kernel, initial state

INTEGRATORS = ("auto", "numba", "scipy")
"""How the full equations are integrated (the scenario key ``[run] integrator``): ``"numba"``
the compiled DOP853 of :mod:`tumble.integrate.dop853`; ``"scipy"`` scipy's DOP853 on the model's
Python right-hand side (the reference); ``"auto"`` (default) the compiled one unless the
parameters hold a Python function (a user torque, a pressure given as a function)."""


def simulate(
    model: Model[P, S],
    p: P,
    initial: S,
    tau: ArrayLike,
    method: str,
    *,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    form: str | None = None,
    integrator: str = "auto",
    averaging: AveragingOptions = DEFAULT_AVERAGING,
    dense: bool = False,
    max_steps: int = MAX_STEPS,
) -> Trajectory:
    """Run one method of ``model`` from ``initial`` and sample it at ``tau``.

    Parameters
    ----------
    model : Model
        The registered model (e.g. ``tumble.models.resisting_medium.MODEL``).
    p : model Params
        Model parameters.
    initial : model State
        Initial state at τ = 0.
    tau : array_like
        Sample times, ascending, ≥ 0 [model time unit].
    method : {"full", "averaged", "closed_form"}
        Which description of the motion to compute.
    rtol, atol : float
        Integration tolerances (ignored by ``closed_form``).
    form : str, optional
        For ``full``: one of ``model.full.forms`` (default: the model's recommended form).
    integrator : {"auto", "numba", "scipy"}
        The compiled integrator or scipy's (see :data:`INTEGRATORS`). The averaged equations
        run compiled where their form has a kernel (the resisting medium's (2.2), (2.3), split
        at the equator; the rotating field's vector form, stopped at its separatrix by a
        terminal event; the nonlinear moment's Volosov equations in the energy form, stopped
        at a barrier of the potential); the others (the general engine's quadrature, the
        nonlinear moment's turning-point forms) are Python on scipy's.
    averaging : AveragingOptions
        For ``averaged``: the paper's right-hand side or the general engine, the slow
        coordinates, and the start (checked against the model's ``Averaged`` capability).
    dense : bool
        For ``full`` on the compiled integrator: keep the dense output, so that
        ``Trajectory.slow`` evaluates the run anywhere. By default the run keeps its samples
        (and events) only and its memory does not grow with its length.
    max_steps : int
        The step budget of the integration; the run stops with an
        :class:`~tumble.errors.IntegrationError` naming ``run.max_steps`` when it is spent, or
        as soon as its pace shows it would need a hundred times what is left. Integrations of
        Python right-hand sides (scipy: the averaged equations, ``integrator = "scipy"``) take
        at most :data:`tumble.integrate.ode.PYTHON_MAX_STEPS` (10⁶).

    Returns
    -------
    Trajectory
    """
    tau = check_times(tau)
    chosen = integrator_named(integrator)
    if method not in model.methods:
        raise ParameterError(
            f"run.methods: {method!r} is not a method of {model.name} "
            f"(allowed: {', '.join(model.methods)})"
        )
    model.check(p, method)
    run: RunSpec[P, S] = RunSpec(model, p, initial, tau, rtol, atol, max_steps)
    if method == "full":
        return chosen.run_full(run, model.full.form(form), dense)
    if method == "averaged" and model.averaged is not None:
        options = model.averaged.check(averaging)
        avg = model.averaged.form(p, initial, options)
        if options.hybrid:
            return chosen.run_hybrid(run, avg)
        return chosen.run_averaged(run, avg)
    assert model.closed_form is not None  # the methods follow the capabilities
    return _closed(model.closed_form, p, initial, tau)


class Integrator:
    """How a run's equations are integrated: one of :data:`INTEGRATORS` (the scenario key
    ``[run] integrator``), found by :func:`integrator_named`.

    An integrator chooses the compiled right-hand side of each form (None: scipy's DOP853 on
    the form's Python right-hand side); the runs are then the same for every integrator.
    """

    name: str = ""

    def full_kernel(self, model: Model[P, S], full: FullForm[P, S], p: P) -> Kernel | None:
        """The compiled kernel of a full form, or None for scipy's path."""
        raise NotImplementedError

    def averaged_kernel(self, avg: AveragedForm[P, S], p: P) -> Kernel | None:
        """The compiled averaged right-hand side to run, or None for scipy's path: none
        asked, none written, or breakpoint surfaces the compiled integrator cannot watch (more
        than one, or one without a compiled event function)."""
        if avg.kernel is None or not compiled_breakpoints(avg.breakpoints):
            return None
        return avg.kernel(p)

    def scipy_reason(
        self, model: Model[P, S], form: FullForm[P, S] | AveragedForm[P, S], p: P
    ) -> str:
        """Why ``form`` (a full or an averaged one) would run on scipy's DOP853 although the
        compiled integrator was not refused by the user (this integrator "auto"); "" where
        it runs compiled, or where the user asked for scipy."""
        if self.name == "scipy":
            return ""
        if isinstance(form, AveragedForm):
            if self.averaged_kernel(form, p) is not None:
                return ""
            if form.kernel is None:
                return f"the averaged form {form.name} of {model.name} has no compiled form"
            if not compiled_breakpoints(form.breakpoints):
                return "its breakpoints are more than the compiled integrator can watch"
            return ("its parameters hold a Python function, or time-dependent terms without "
                    "a common period")  # fmt: skip
        if self.full_kernel(model, form, p) is not None:
            return ""
        if form.kernel is None:
            return f"the {form.name} form of {model.name} has no compiled form"
        return "its parameters hold a Python function (a numba function runs compiled)"

    def _say_scipy(self, run: RunSpec[P, S], form: FullForm[P, S] | AveragedForm[P, S],
                   method: str) -> None:  # fmt: skip
        """The one-line warning of a run that goes to scipy's integrator (module notes)."""
        reason = self.scipy_reason(run.model, form, run.p)
        if reason:
            warn(
                f"the {method} run is integrated by scipy's DOP853 in Python, not compiled: "
                f"{reason}"
            )

    def run_full(self, run: RunSpec[P, S], full: FullForm[P, S], dense: bool) -> Trajectory:
        """A full form integrated and sampled at ``run.tau``: compiled, chunk by chunk
        (unless ``dense``), where this integrator has a kernel for it."""
        kernel = self.full_kernel(run.model, full, run.p)
        if kernel is not None and not dense:
            return _streamed(run, full)
        if kernel is None:
            self._say_scipy(run, full, "full")
        return _full(run, full, kernel)

    def run_averaged(self, run: RunSpec[P, S], avg: AveragedForm[P, S]) -> Trajectory:
        """The averaged equations integrated and sampled at ``run.tau``."""
        kernel = self.averaged_kernel(avg, run.p)
        if kernel is None:
            self._say_scipy(run, avg, "averaged")
        return _averaged(run, avg, kernel)

    def run_hybrid(self, run: RunSpec[P, S], avg: AveragedForm[P, S]) -> Trajectory:
        """The averaged form with its band crossed on the full equations
        (:func:`tumble.integrate.hybrid.hybrid`), sampled at ``run.tau``."""
        from tumble.integrate.hybrid import hybrid

        model, p, initial, tau = run.model, run.p, run.initial, run.tau
        if avg.crossing is None:
            raise ParameterError(
                f'run.averaged_method = "hybrid" is not available for the averaged form '
                f"{avg.name} of {model.name} (it has no band to hand to the full equations)"
            )
        start = time.perf_counter()
        full = model.full.form()
        kernel = self.full_kernel(model, full, p)
        legs = hybrid(avg, full, p, initial, run.t_end, run.rtol, run.atol, kernel,
                      run.max_steps)  # fmt: skip
        cols = legs.columns(tau)
        unwrap_columns(model, p, "averaged", cols, initial)

        def slow(t: FloatArray) -> Columns:
            return legs.columns(t, osculating=False)

        wall = time.perf_counter() - start
        return Trajectory(tau, cols, "averaged", f"{avg.name} hybrid", wall, legs.nfev, slow,
                          legs.steps, "numba" if kernel is not None else "scipy",
                          legs=legs.spans)  # fmt: skip


class _Compiled(Integrator):
    """The compiled DOP853 of :mod:`tumble.integrate.dop853`; a full form without a kernel
    (none written, or a Python function in its parameters) is refused."""

    name = "numba"

    def full_kernel(self, model: Model[P, S], full: FullForm[P, S], p: P) -> Kernel | None:
        kernel = full.kernel(p) if full.kernel is not None else None
        if kernel is None:
            why = (
                "it has no compiled form"
                if full.kernel is None
                else "its parameters hold a Python function"
            )
            raise ParameterError(
                f"run.integrator = 'numba' cannot integrate the {full.name} form of "
                f'{model.name}: {why} (use "auto" or "scipy")'
            )
        return kernel


class _Scipy(Integrator):
    """scipy's DOP853 on the forms' Python right-hand sides (the reference)."""

    name = "scipy"

    def full_kernel(self, model: Model[P, S], full: FullForm[P, S], p: P) -> Kernel | None:
        return None

    def averaged_kernel(self, avg: AveragedForm[P, S], p: P) -> Kernel | None:
        return None


class _Auto(Integrator):
    """The compiled integrator where a form has a kernel, scipy's elsewhere."""

    name = "auto"

    def full_kernel(self, model: Model[P, S], full: FullForm[P, S], p: P) -> Kernel | None:
        return full.kernel(p) if full.kernel is not None else None


_REGISTRY: dict[str, Integrator] = {i.name: i for i in (_Auto(), _Compiled(), _Scipy())}
assert tuple(_REGISTRY) == INTEGRATORS  # one registry, in the documented order
_COMPILED = _REGISTRY["numba"]


def integrator_named(name: str) -> Integrator:
    """The integrator called ``name`` (one of :data:`INTEGRATORS`).

    Raises
    ------
    ParameterError
        ``name`` is not an integrator.
    """
    if name not in _REGISTRY:
        allowed = ", ".join(f'"{n}"' for n in INTEGRATORS)
        raise ParameterError(f"run.integrator = {name!r} is not an integrator (allowed: {allowed})")
    return _REGISTRY[name]


def _full(run: RunSpec[P, S], full: FullForm[P, S], kernel: Kernel | None) -> Trajectory:
    """A full form integrated (compiled when ``kernel`` is given) and sampled at ``run.tau``."""
    start = time.perf_counter()
    p = run.p
    try:
        sol = integrate(
            lambda t, y: full.rhs(t, y, p),
            full.initial_state(p, run.initial),
            run.t_end,
            rtol=run.rtol,
            atol=run.atol,
            what=run.what(full),
            kernel=kernel,
            event=None if full.event is None else _bind(full.event, p),
            max_steps=run.max_steps,
        )
    except TumbleError as exc:
        _keep_before(exc, run, "full", full, start)
        raise
    return integrated(run, "full", full, sol, start)


def _keep_before(
    exc: TumbleError, run: RunSpec[P, S], method: str, form: Any, start: float
) -> None:
    """The samples of ``run`` before the failure ``exc`` (a user's torque, a spent budget),
    from the steps it carries (``exc.dense``), made its ``partial`` as a ``method`` run of
    ``form`` cut short."""
    if exc.dense is not None and exc.partial is None:
        passed = run.tau[run.tau <= exc.dense.ts[-1]]
        if passed.size:
            cut = dataclasses.replace(run, tau=passed)
            exc.partial = integrated(cut, method, form, exc.dense, start)


def _streamed(run: RunSpec[P, S], full: FullForm[P, S]) -> Trajectory:
    """A full form on the compiled integrator, consumed chunk by chunk: the samples come from
    the integrator's dense output as it passes them, the angle columns are unwrapped on each
    chunk's steps (which resolve every turn) continuing from the chunk before, and the steps
    are then dropped. Memory: the samples and one chunk."""
    start = time.perf_counter()
    kernel, y0 = _batch_job(run, full)
    return _consume(run, full, _integration(run, kernel, y0), start)


def _integration(run: RunSpec[Any, Any], kernel: Kernel, y0: FloatArray) -> dop853.Integration:
    """A compiled run that samples at ``run.tau`` and records its steps without
    interpolants."""
    options = dop853.Options(run.rtol, run.atol, 0.0, True, False)
    return dop853.Integration(kernel, y0, run.t_end, options, t_eval=run.tau)


def _consume(
    run: RunSpec[P, S], full: FullForm[P, S], integration: dop853.Integration, start: float
) -> Trajectory:
    """Advance ``integration`` to its end chunk by chunk, keeping the samples (see
    :func:`_streamed`); its wall time counted from ``start``.

    A chunk that fails (the integration, its step budget, its pace, a user's torque) raises
    its error with what the run computed until then attached (``TumbleError.partial``: the
    samples up to the last step taken), so that the caller can keep it.
    """
    p, tau = run.p, run.tau
    angles = [c.name for c in run.model.columns(p, "full") if c.unwrap]

    def angle_columns(p: P, t: FloatArray, Y: FloatArray) -> Columns:
        cols = full.angles(p, t, Y) if full.angles else full.to_columns(p, t, Y)
        return {name: cols[name] for name in angles}

    parts: list[Columns] = []
    events: list[tuple[FloatArray, FloatArray, FloatArray]] = []
    carry: dict[str, float] = {}
    done_samples = 0

    def keep(piece: dop853.Solution, upto: int) -> None:
        """The samples of ``piece`` up to ``upto`` (unwrapped on its steps), and its events."""
        nonlocal done_samples
        t_samples = tau[done_samples:upto]
        if t_samples.size:
            cols = full.to_columns(p, t_samples, piece.y_eval[done_samples:upto])
            parts.append(cols)
        else:  # no sample in this chunk: its steps still carry the turns of the angles
            cols = {name: np.empty(0) for name in angles}
        if angles and piece.ts.size:
            at_steps = angle_columns(p, piece.ts, piece.ys)
            _unwrap_streamed(cols, t_samples, at_steps, piece.ts, carry, run.initial)
        events.append((piece.event_t, piece.event_signs, piece.event_y))
        done_samples = upto

    def kept() -> Trajectory:
        """The trajectory of the samples kept so far."""
        columns = {name: np.concatenate([part[name] for part in parts]) for name in parts[0]}
        ev_t, ev_s, ev_y = (np.concatenate([e[k] for e in events]) for k in range(3))
        event_columns = full.to_columns(p, ev_t, ev_y) if ev_t.size else {}
        return Trajectory(
            tau[:done_samples],
            columns,
            "full",
            full.name,
            time.perf_counter() - start,
            int(integration.progress.nfev),
            _samples_only,
            np.empty(0),
            "numba",
            ev_t,
            ev_s,
            event_columns,
        )

    done = False
    while not done:
        left = max(1, run.max_steps - integration.progress.n_steps)
        piece: dop853.Solution | None = None
        try:
            done = integration.advance(min(dop853.CHUNK_STEPS, left))
            piece = integration.take()
            advanced(integration.progress.t, run.t_end)
            _check_chunk(run, run.what(full), integration.progress, piece, done)
        except TumbleError as exc:
            if piece is None:  # what the failed chunk computed before it stopped
                piece = integration.take()
            keep(piece, int(np.searchsorted(tau, piece.ts[-1], side="right")))
            if parts and exc.partial is None:
                exc.partial = kept()
            raise
        keep(piece, tau.size if done else int(np.searchsorted(tau, piece.ts[-1], side="right")))
    return kept()


def _samples_only(t: FloatArray) -> Columns:
    """The ``slow`` of a streamed full run, which keeps its samples only."""
    raise ParameterError(
        "this full run kept its samples only: simulate(..., dense=True) keeps the dense "
        "output to evaluate it anywhere"
    )


def _check_chunk(
    run: RunSpec[Any, Any], what: str, progress: Any, piece: dop853.Solution, done: bool
) -> None:
    """Raise the IntegrationError of a chunk of a streamed run (integrator ``progress`` after
    it, ``done`` if the run ended): the run failed, spent its step budget, or goes at a pace
    that would need a hundred times the steps it has left."""
    max_steps = run.max_steps
    if done and piece.status != 0:
        raise IntegrationError(f"{what}: integration failed at t = {piece.t:.6g}: {piece.message}")
    if not done and progress.n_steps >= max_steps:
        raise IntegrationError(
            f"{what}: run.max_steps = {max_steps} steps spent at t = {piece.t:.6g} of "
            f"{run.t_end:.6g} (raise run.max_steps, shorten the run, or check the "
            "input: a very fast or stiff motion)"
        )
    left = max_steps - progress.n_steps
    # The chunk's mean step, steadier than its last one (an orbit or a nutation makes the
    # step breathe), against the mean step of the whole run so far: its growth.
    taken = piece.ts.size - 1
    h_chunk = (piece.ts[-1] - piece.ts[0]) / taken if taken > 0 else progress.h_abs
    h_mean = piece.t / progress.n_steps if progress.n_steps else None
    refused = pace_message(piece.t, run.t_end, h_chunk, left, max_steps, h_mean=h_mean)
    if not done and refused:
        raise IntegrationError(f"{what}: {refused}")


def _unwrap_streamed(
    samples: Columns,
    t_samples: FloatArray,
    steps: Columns,
    t_steps: FloatArray,
    carry: dict[str, float],
    initial: object,
) -> None:
    """Unwrap the angle columns of one chunk's samples in place, on the union of its steps
    and samples. The chunk's first step is the previous chunk's last, whose unwrapped value
    ``carry`` holds (the initial value anchors the first chunk); ``carry`` gets this chunk's
    last."""
    order = np.argsort(np.concatenate([t_steps, t_samples]), kind="stable")
    where = np.empty_like(order)
    where[order] = np.arange(order.size)  # position of each step, then sample, in time order
    n = t_steps.size
    for name, at_steps in steps.items():
        angle = np.unwrap(np.concatenate([at_steps, samples[name]])[order])
        first = angle[where[0]]
        anchor = carry.get(name, getattr(initial, name, first))
        angle += 2.0 * np.pi * np.round((anchor - first) / (2.0 * np.pi))
        samples[name] = angle[where[n:]]
        carry[name] = float(angle[where[n - 1]])


def _closed(closed: ClosedForm[P, S], p: P, initial: S, tau: FloatArray) -> Trajectory:
    """The closed form evaluated at ``tau`` (and anywhere, for the validity checks)."""
    start = time.perf_counter()
    cols = closed.evaluate(p, initial, tau)

    def slow(t: FloatArray) -> Columns:
        return closed.evaluate(p, initial, t)

    wall = time.perf_counter() - start
    return Trajectory(tau, cols, "closed_form", "closed_form", wall, 0, slow)


def _averaged(run: RunSpec[P, S], avg: AveragedForm[P, S], kernel: Kernel | None) -> Trajectory:
    """The averaged equations integrated (compiled when ``kernel`` is given) and sampled at
    ``run.tau``."""
    start = time.perf_counter()
    p = run.p
    y0 = avg.initial_state(p, run.initial)
    try:
        if kernel is not None and run.t_end > 0.0 and np.all(np.isfinite(y0)):
            return _averaged_streamed(run, avg, kernel, np.asarray(y0, dtype=float), start)
        sol = integrate(
            lambda t, y: avg.rhs(t, y, p),
            y0,
            run.t_end,
            rtol=run.rtol,
            atol=run.atol,
            what=run.what(avg),
            breakpoints=avg.breakpoints,
            kernel=kernel,
            max_steps=run.max_steps,
        )
    except IntegrationError as exc:
        reason = avg.failure() if avg.failure else None
        if reason is None and kernel is not None:
            reason = start_refusal(avg, p, 0.0, y0)
        if reason is None:
            _keep_before(exc, run, "averaged", avg, start)
            raise
        said = IntegrationError(f"{exc}; last refused state: {reason}")
        said.partial = exc.partial  # what ran before (a streamed run's samples)
        raise said from None
    except TumbleError as exc:  # a user's torque: the samples before its fault kept
        _keep_before(exc, run, "averaged", avg, start)
        raise
    return integrated(run, "averaged", avg, sol, start)


def _averaged_streamed(
    run: RunSpec[P, S], avg: AveragedForm[P, S], kernel: Kernel, y0: FloatArray, start: float
) -> Trajectory:
    """The averaged equations on the compiled integrator, kept at the samples only
    (:func:`tumble.integrate.replay.stream`): the angle columns are unwrapped chunk by chunk
    on the steps and samples, which the chunk's interpolants give as the whole dense output
    would, and the steps are then dropped; ``Trajectory.slow`` replays the run from its
    checkpoints. Memory: the samples, one chunk and the checkpoints, whatever the span."""
    from tumble.integrate.replay import Filled, stream

    p, tau, initial = run.p, run.tau, run.initial
    angles = turning_angles(run.model, p, avg, initial, y0.size)
    parts: list[Columns] = []
    unwrap = UnwrapStream(angles, initial)

    def to_columns(t: FloatArray, Y: FloatArray) -> Columns:
        return avg.to_columns(p, initial, t, Y)

    def angle_columns(t: FloatArray, Y: FloatArray) -> Columns:
        if avg.angles is not None:
            return avg.angles(p, initial, t, Y)
        return to_columns(t, Y)

    def on_chunk(piece: dop853.Solution, steps: FloatArray, rows: slice) -> None:
        # The steps and the samples in one ascending grid (a step first where they meet), as
        # the dense output's sampling merges them.
        times = np.concatenate([steps, tau[rows]])
        order = np.argsort(times, kind="stable")
        cols = angle_columns(times[order], piece(times[order]))
        unwrap(cols)
        where = np.empty(times.size, dtype=np.intp)
        where[order] = np.arange(times.size)
        at = where[steps.size :]
        parts.append({name: cols[name][at] for name in angles if name in cols})

    def sampled(tau: FloatArray, y_eval: FloatArray) -> Columns:
        cols = to_columns(tau, y_eval)
        for name in parts[0] if parts else ():
            cols[name] = np.concatenate([part[name] for part in parts])
        if avg.osculating is not None:
            cols.update(avg.osculating(p, initial, tau, y_eval))
        return cols

    try:
        kept = stream(kernel, y0, tau, avg.breakpoints, run.rtol, run.atol, run.what(avg),
                      run.max_steps, on_chunk if angles else None)  # fmt: skip
    except TumbleError as exc:  # the samples before the failure, kept as a run cut short
        if isinstance(exc.partial, Filled):
            n = exc.partial.rows
            cut = sampled(tau[:n], exc.partial.y_eval[:n])
            exc.partial = Trajectory(tau[:n], cut, "averaged", avg.name,
                                     time.perf_counter() - start, 0, _samples_only)  # fmt: skip
        raise
    cols = sampled(tau, kept.y_eval)
    replay = kept.replay

    def slow(t: FloatArray) -> Columns:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return to_columns(t, replay(t))

    events = kept.events
    event_columns = to_columns(events, kept.event_y) if events.size else {}
    return Trajectory(tau, cols, "averaged", avg.name, time.perf_counter() - start, kept.nfev,
                      slow, np.empty(0), "numba", events, kept.event_signs,
                      event_columns, step_legs(avg, run.t_end))  # fmt: skip


def start_refusal(avg: AveragedForm[P, S], p: P, t: float, y: FloatArray) -> str | None:
    """Why the Python form refuses the state (t, y) (its error's message), or None: what a
    compiled kernel's NaN at a run's start meant, for the message of the failed run."""
    try:
        avg.rhs(t, np.asarray(y, dtype=float), p)
    except TumbleError as exc:
        return str(exc)
    return None


def simulate_batch(
    model: Model[P, S],
    params: Sequence[P],
    initials: Sequence[S],
    tau: ArrayLike,
    *,
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    form: str | None = None,
    threads: int | None = 1,
    max_steps: int = MAX_STEPS,
    method: Literal["full", "averaged"] = "full",
    averaging: AveragingOptions = DEFAULT_AVERAGING,
    dense: bool = False,
) -> list[Trajectory | TumbleError]:
    """The full or the averaged method of many points of one model at once.

    ``full``: every point whose full form has a compiled kernel is integrated by the compiled
    DOP853, its samples kept chunk by chunk as :func:`simulate` keeps them (memory bounded by
    the samples), on a pool of ``threads`` (the compiled parts release the GIL); each
    Trajectory then equals ``simulate(model, p, initial, tau, "full", integrator="numba")``
    to the bit, except its wall time.

    ``averaged`` (an ensemble: initial states or parameter sets by the thousand): the points
    whose averaged form has a kernel go in blocks through one compiled call per piece of
    their runs (:mod:`tumble.integrate.ensemble`). By default they keep their samples only:
    each equals ``simulate(model, p, initial, tau, "averaged")`` to the integration's
    round-off (the same steps; the samples are interpolated in the loop rather than from the
    dense output), and its ``slow`` integrates the point again, alone, on first use. With
    ``dense`` they keep every step's interpolant too: each then equals ``simulate``'s to the
    bit, ``slow`` included (what a sweep needs for the validity checks), at the cost of the
    columns on every step. The others (a Python right-hand side: the triaxial engine, a user
    torque) run one by one through :func:`simulate`.

    Parameters
    ----------
    model : Model
    params, initials : sequence
        Parameters and initial state of each point.
    tau : array_like, shape (n_samples,) or (n_points, n_samples)
        Sample times, ascending, ≥ 0 [model time unit]: shared by all points, or a row per
        point (points of a physical scenario, whose time units differ).
    rtol, atol : float
        Integration tolerances.
    form : str, optional
        Full form (default: the model's recommended one).
    threads : int, optional
        Threads of the pool (None: every core numba may use). The default 1 suits a caller
        that already runs one task per core, as a Dask worker does.
    max_steps : int
        Step budget of each run.

    method : {"full", "averaged"}
        Which description of the motion to compute.
    averaging : AveragingOptions
        For ``averaged``: as in :func:`simulate`, shared by every point.
    dense : bool
        For ``averaged``: keep the dense output of every point.

    Returns
    -------
    list
        Per point, its Trajectory or the :class:`~tumble.errors.TumbleError` it met (a failed
        integration, a full form without a compiled kernel): a batch never stops for one point.
    """
    taus = batch_times(tau, len(params))
    if method == "averaged":
        from tumble.integrate.ensemble import averaged_batch  # builds on this module

        return averaged_batch(
            model, params, initials, taus, rtol=rtol, atol=atol, averaging=averaging,
            threads=threads, max_steps=max_steps, dense=dense,
        )  # fmt: skip
    if method != "full":
        raise ParameterError(f"simulate_batch: method {method!r} is not 'full' or 'averaged'")
    runs: list[RunSpec[P, S]] = [RunSpec(model, p, initial, tau_i, rtol, atol, max_steps)
            for p, initial, tau_i in zip(params, initials, taus, strict=True)]  # fmt: skip
    return _full_batch(runs, model.full.form(form), form, threads)


def _full_batch(
    runs: Sequence[RunSpec[P, S]], full: FullForm[P, S], form: str | None, threads: int | None
) -> list[Trajectory | TumbleError]:
    """The full form ``full`` (named ``form``) of every run, compiled and streamed, on a pool
    of ``threads`` (see :func:`simulate_batch`)."""
    out: list[Trajectory | TumbleError | None] = [None] * len(runs)
    jobs: list[_Job] = []
    for i, run in enumerate(runs):
        try:
            jobs.append((i, *_batch_job(run, full)))
        except TumbleError as exc:
            out[i] = exc

    def work(job: _Job) -> None:
        i, kernel, y0 = job
        start = time.perf_counter()
        run = runs[i]
        try:
            if run.t_end == 0.0:  # nothing to integrate: simulate's own path
                out[i] = simulate(run.model, run.p, run.initial, run.tau, "full", rtol=run.rtol,
                                  atol=run.atol, form=form, integrator="numba")  # fmt: skip
                return
            out[i] = _consume(run, full, _integration(run, kernel, y0), start)
        except TumbleError as exc:
            out[i] = exc

    each_on_threads(work, jobs, threads)
    return [o for o in out if o is not None]


def batch_times(tau: ArrayLike, n_points: int) -> list[FloatArray]:
    """Each point's sample times: ``tau`` shared (one row) or one row per point (the points of
    a physical scenario, each with its own time unit), every row checked as ``run.tau``."""
    t = np.asarray(tau, dtype=float)
    if t.ndim == 2:
        if t.shape[0] != n_points:
            raise ParameterError(f"{t.shape[0]} rows of sample times for {n_points} points")
        return [check_times(row) for row in t]
    shared = check_times(t)
    return [shared] * n_points


def each_on_threads(work: Callable[[J], None], jobs: Sequence[J], threads: int | None) -> None:
    """``work(job)`` for every job, on a pool of ``threads`` (None: every core numba uses),
    in the calling thread when there is one worker or one job.

    Parameters
    ----------
    work : callable
        Called once per job; its results go where it puts them (the compiled integrators
        release the GIL, so the jobs run in parallel).
    jobs : sequence
        The jobs.
    threads : int, optional
        Threads of the pool (at most one per job).
    """
    workers = dop853.available_threads() if threads is None else max(1, int(threads))
    if workers == 1 or len(jobs) < 2:
        for job in jobs:
            work(job)
    else:
        with ThreadPoolExecutor(max_workers=min(workers, len(jobs))) as pool:
            list(pool.map(work, jobs))


def _batch_job(run: RunSpec[P, S], full: FullForm[P, S]) -> tuple[Kernel, FloatArray]:
    """The kernel and initial state vector of one point of a batch; TumbleError if the point
    cannot run compiled (a Python function in it, times beyond its tables, no finite start)."""
    run.model.check(run.p, "full")
    kernel = _COMPILED.full_kernel(run.model, full, run.p)
    assert kernel is not None  # "numba" raises instead of returning None
    kernel.check_end(run.t_end)
    y0 = np.asarray(full.initial_state(run.p, run.initial), dtype=np.float64)
    if not np.all(np.isfinite(y0)):
        raise IntegrationError(f"{run.what(full)}: the initial state is not finite: {y0}")
    return kernel, y0


def _bind(
    event: Callable[[float, FloatArray, P], float], p: P
) -> Callable[[float, FloatArray], float]:
    """A form's event at parameters ``p``, as the integrator calls it."""
    return lambda t, y: event(t, y, p)
