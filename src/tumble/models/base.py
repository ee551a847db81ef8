"""The model contract: the one typed shape every model exposes to the rest of tumble.

A model module holds plain numerics and declares, in one :class:`Model`, the capabilities it
has: a full form of the equations of motion (always), averaged equations, a closed form, the
regions where those lose accuracy and the limits they predict, a stationary motion to
linearize, and extra results of a run. A capability it lacks is None, never a stub; the
methods a scenario may ask for follow from the capabilities.

The contract is generic in the model's ``Params`` (physics only) and ``State`` (the initial
state, in the model's own variables). One argument order holds everywhere: parameters first,
then the initial state, then times or states (``closed_form(p, initial, tau)``,
``to_columns(p, t, Y)``, ``invariants(p, Y)``); the right-hand sides alone keep the ODE
solvers' ``rhs(t, y, p)``.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Generic, Literal, Protocol, TypeAlias, TypeVar

import numpy as np

from tumble._typing import ArrayLike, ComplexArray, FloatArray, Json
from tumble.catalogue import CATALOGUE, Paper
from tumble.errors import ParameterError
from tumble.kernels import Kernel
from tumble.models.columns import (
    QUATERNION_STATE,
    TIME_T,
    TIME_TAU,
    Column,
    Columns,
    attitude_columns,
    attitude_values,
    fixed_columns,
    mean_columns,
)
from tumble.models.family import DEFAULT_FAMILY, family_params, scaling_family
from tumble.models.schema import ScenarioSchema

__all__ = [
    "DEFAULT_FAMILY",
    "QUATERNION_STATE",
    "TIME_T",
    "TIME_TAU",
    "Averaged",
    "AveragedForm",
    "AveragingOptions",
    "Breakpoint",
    "ClosedForm",
    "Column",
    "Columns",
    "Crossing",
    "Declaration",
    "Diagnostics",
    "Full",
    "FullForm",
    "Json",
    "Model",
    "Paper",
    "Report",
    "Sampled",
    "SlowPath",
    "StationaryMotion",
    "Validity",
    "ValidityIssue",
    "attitude_columns",
    "attitude_values",
    "family_params",
    "first_time",
    "fixed_columns",
    "frozen_array",
    "mean_columns",
    "scaling_family",
    "separatrix_issue",
    "separatrix_time",
]

P = TypeVar("P")  # a model's Params
S = TypeVar("S")  # a model's initial State

SlowPath: TypeAlias = Callable[[FloatArray], Columns]
"""A trajectory's columns anywhere in its time span: ``slow(tau) -> columns``."""
Method = Literal["full", "averaged", "closed_form"]


AVERAGING_METHODS = ("closed_form", "numeric")
"""How an averaged method forms its right-hand side: the paper's closed form, or the general
engine of :mod:`tumble.averaging` (the scenario key ``[run] averaging``)."""


@dataclass(frozen=True, slots=True)
class AveragingOptions:
    """How a run forms and starts its averaged equations: choices of the run, not physics.

    Attributes
    ----------
    averaging : {"closed_form", "numeric"}
        The paper's averaged right-hand side, or the general engine's quadrature of the full
        torque over the unperturbed motion (scenario key ``[run] averaging``).
    coordinates : str
        The slow coordinates to integrate in, among the model's ``Averaged.coordinates``;
        "" for its default (``[run] averaged_form``).
    start : {"exact", "corrected"}
        Start the averaged run from the initial state as given, or from the mean state
        corrected to first order where the model has that map (``[run] averaged_init``).
    order : {1, 2}
        The order of the averaged equations (``[run] averaging_order``): F₁, or F₁ + F₂ with
        the mean ↔ osculating map to second order (:mod:`tumble.averaging.second_order`),
        where the model offers it (``Averaged.orders``).
    initial : {"osculating", "mean"}
        What the initial state of a run of order 2 is (``[run] initial``): the physical
        (osculating) state, converted to the mean one before the run; or the mean state
        itself. Output columns of such a run are the osculating variables rebuilt at the
        sample times, with the mean ones beside them (``*_mean``).
    hybrid : bool
        Hand the bands where averaging fails (a resonance, the stop of a fast phase) to the
        full equations and re-enter the averaged ones through the osculating → mean map
        (``[run] averaged_method = "hybrid"``), where the averaged form has such a band
        (``AveragedForm.crossing``).
    averaged_only : bool
        The averaged equations alone: no asymptotic crossing step where the model's theory
        gives one (``[run] averaged_only``; ``AveragedForm.steps``).
    """

    averaging: Literal["closed_form", "numeric"] = "closed_form"
    coordinates: str = ""
    start: Literal["exact", "corrected"] = "exact"
    order: int = 1
    initial: Literal["osculating", "mean"] = "osculating"
    hybrid: bool = False
    averaged_only: bool = False

    def __post_init__(self) -> None:
        if self.averaging not in AVERAGING_METHODS:
            raise ParameterError(
                f"run.averaging = {self.averaging!r} is not a method of averaging "
                '(allowed: "closed_form", "numeric")'
            )
        if self.start not in ("exact", "corrected"):
            raise ParameterError(
                f"run.averaged_init = {self.start!r} is not an initialisation "
                '(allowed: "exact", "corrected")'
            )
        if self.order not in (1, 2):
            raise ParameterError(
                f"run.averaging_order = {self.order!r} is not an order of averaging (allowed: 1, 2)"
            )
        if self.initial not in ("osculating", "mean"):
            raise ParameterError(
                f"run.initial = {self.initial!r} is not a meaning of the initial state "
                '(allowed: "osculating", "mean")'
            )
        if self.averaged_only and self.hybrid:
            raise ParameterError(
                'run.averaged_only = true excludes run.averaged_method = "hybrid" (allowed: '
                "one of them)"
            )


@dataclass(frozen=True, slots=True)
class FullForm(Generic[P, S]):
    """One form of the full equations of motion.

    ``state`` names the components of the state vector; ``rhs(t, y, p)`` is the right-hand
    side; ``initial_state(p, initial)`` builds the state vector; ``to_columns(p, t, Y)``
    turns states ``Y`` of shape (n, dim) into output columns (the slow variables, converted
    from the full state); ``state_of(p, y)`` is the inverse of ``initial_state``: the
    initial-condition record of a state vector taken at t = 0 (through it a full state
    converts to any averaged form's slow state, :meth:`Model.slow_state`). ``kernel(p)``
    gives the same
    right-hand side compiled (:class:`tumble.kernels.Kernel`), or None where ``p`` holds a
    Python function; ``rhs`` stays the reference that the scipy integrator runs.
    ``invariants(p, Y)`` are the quantities the unperturbed motion (ε = 0) conserves.
    ``event(t, y, p)`` is a function whose zeros every run of this form records, with the
    sign before each (e.g. θ' = 0, the extrema of the nutation angle); the kernel's event
    must be the same function. ``angles(p, t, Y)``, where ``to_columns`` is costly, gives
    its unwrapped angle columns alone: a run evaluates them on every integrator step (to
    count the turns between samples) and the other columns at the samples only.
    """

    name: str
    equation: str
    state: tuple[str, ...]
    rhs: Callable[[float, FloatArray, P], FloatArray]
    initial_state: Callable[[P, S], FloatArray]
    to_columns: Callable[[P, FloatArray, FloatArray], Columns]
    state_of: Callable[[P, FloatArray], S]
    kernel: Callable[[P], Kernel | None] | None = None
    invariants: Callable[[P, FloatArray], Columns] | None = None
    event: Callable[[float, FloatArray, P], float] | None = None
    angles: Callable[[P, FloatArray, FloatArray], Columns] | None = None


@dataclass(frozen=True)
class Breakpoint:
    """A surface ``condition(t, y) = 0`` that the solution crosses at most once, where the
    right-hand side is not smooth (a separatrix).

    The integration stops exactly there and restarts from ``restart(t, y)`` (default: the same
    state). A restart map lets a solution leave a non-Lipschitz point it would otherwise stick
    to (e.g. the spurious k² ≡ 1 solution on a separatrix); one that raises stops the run
    there. A breakpoint at a known time (``Breakpoint.at_time``) splits the integration
    interval there instead, so that no step ever straddles it, and its restart map, if any, is
    a jump the theory gives at that time (an asymptotic crossing step). ``event``, an
    ``EVENT_*`` code of :mod:`tumble.kernels`, is the same surface as a compiled event function
    of the form's kernel: with it the compiled integrator stops there too (0: scipy's path
    only).
    """

    condition: Callable[[float, FloatArray], float] | None
    restart: Callable[[float, FloatArray], FloatArray] | None = None
    time: float | None = None  # a known time instead of a condition (a kink in a forcing)
    event: int = 0  # the condition compiled (an EVENT_* code of the form's kernel)

    @classmethod
    def at_time(
        cls, t: float, restart: Callable[[float, FloatArray], FloatArray] | None = None
    ) -> Breakpoint:
        """A breakpoint at a fixed time ``t`` (the integration is split there and goes on from
        ``restart(t, y)``, by default the same state)."""
        return cls(None, restart, float(t))


@dataclass(frozen=True)
class Crossing:
    """A band of the slow variables where the averaged equations fail (a fast phase that stops,
    a resonance), which a hybrid run crosses with the full equations.

    ``band(z)`` on the averaged form's state and ``band_full(y)`` on a full state are the same
    measure: negative inside the band, 0 on its edge, 1 at twice its half-width. A hybrid run
    integrates the averaged equations until ``band`` falls to 0 (or ``signed`` changes sign
    within a step: the band was jumped, its edge is found inside the step), converts the state with
    ``to_full(t, z)``, integrates the full equations until ``band_full`` exceeds
    ``LEAVE`` (the hysteresis keeps an oscillating osculating state from re-entering at once)
    and re-enters the averaged ones through ``to_mean(t, y, z_entry)`` (the mean state at
    entry picks the branch of angles such as an azimuth, so that they stay continuous).
    """

    band: Callable[[FloatArray], float]
    band_full: Callable[[FloatArray], float]
    to_full: Callable[[float, FloatArray], FloatArray]
    to_mean: Callable[[float, FloatArray, FloatArray], FloatArray]
    label: str
    chunk: float  # length of one full-equation leg between checks of the band [time unit]
    # The signed distances of the state from each resonance whose band this is, keyed by the
    # resonance (e.g. a harmonic k, the distance k·ν/w_k): a step of the averaged equations
    # long enough to jump a whole band (at small ε a step outlasts a band's crossing) shows
    # as a change of sign, where ``band``, positive on both sides, would not.
    signed: Callable[[FloatArray], dict[tuple[int, ...], float]] | None = None

    LEAVE = 0.5


@dataclass(frozen=True, slots=True)
class AveragedForm(Generic[P, S]):
    """The averaged (evolution) equations in the coordinates used to integrate them, for one
    parameter set and initial state; ``slow`` names the components of the slow state.

    ``kernel(p)`` gives the same right-hand side compiled (:class:`tumble.kernels.Kernel`),
    run by the compiled integrator when every breakpoint is at a known time; ``rhs`` stays
    the reference (and the scipy path).
    """

    name: str
    equation: str
    slow: tuple[str, ...]
    rhs: Callable[[float, FloatArray, P], FloatArray]
    initial_state: Callable[[P, S], FloatArray]
    to_columns: Callable[[P, S, FloatArray, FloatArray], Columns]
    breakpoints: tuple[Breakpoint, ...] = ()  # non-smooth surfaces: stop and restart there
    # The reason the right-hand side last refused a state (it returned NaN so the solver would
    # reject the step); reported if the integration then fails.
    failure: Callable[[], str | None] | None = None
    kernel: Callable[[P], Kernel | None] | None = None
    # The osculating variables rebuilt from the mean ones (a run of order 2): costly, so a run
    # evaluates it at the sample times only, over the columns of ``to_columns`` (the mean
    # ones, which the validity checks and the unwrapping of angles read).
    osculating: Callable[[P, S, FloatArray, FloatArray], Columns] | None = None
    # The band a hybrid run hands to the full equations (AveragingOptions.hybrid).
    crossing: Crossing | None = None
    # Its unwrapped angle columns alone, equal to those of ``to_columns``, where that is
    # costly: a compiled run evaluates them on every step (to count the turns between samples)
    # and the other columns at the samples only, as FullForm.angles. A column it leaves out
    # does not turn (it is constant along the form's solutions) and is not unwrapped.
    angles: Callable[[P, S, FloatArray, FloatArray], Columns] | None = None
    # The inner regions (start, end) of the crossings the form takes by an asymptotic step (a
    # jump its theory gives, through a breakpoint's restart map, and the inner solution in its
    # columns): a run reports them as legs of kind "asymptotic".
    steps: tuple[tuple[float, float], ...] = ()


@dataclass(frozen=True, slots=True)
class ValidityIssue:
    """A region where a method loses accuracy, entered first at time ``tau``."""

    condition: str  # short stable identifier, e.g. "theta_crossing"
    tau: float  # first time the condition holds [model time unit]
    message: str  # one sentence for the user, citing the equation or the theory page
    label: str = ""  # a few words for verdicts ("ϑ = π/2", "resonance ν1 = 2ν2"); "" → condition


class Sampled(Protocol):
    """What a model reads of a computed trajectory (:class:`tumble.integrate.Trajectory`)."""

    @property
    def tau(self) -> FloatArray: ...
    @property
    def columns(self) -> Columns: ...
    @property
    def method(self) -> str: ...
    @property
    def wall_time(self) -> float: ...
    @property
    def nfev(self) -> int: ...
    @property
    def steps(self) -> FloatArray: ...
    @property
    def integrator(self) -> str: ...
    @property
    def events(self) -> FloatArray: ...
    @property
    def event_columns(self) -> Columns: ...
    @property
    def event_signs(self) -> FloatArray: ...
    @property
    def slow(self) -> SlowPath: ...


@dataclass(frozen=True, slots=True)
class Full(Generic[P, S]):
    """The full equations of motion: every form by name, the default one, the output columns."""

    forms: Mapping[str, FullForm[P, S]]
    default: str
    columns: Callable[[P], tuple[Column, ...]]

    def __post_init__(self) -> None:
        if self.default not in self.forms:
            raise ValueError(f"default full form {self.default!r} is not among {list(self.forms)}")

    @classmethod
    def of(cls, columns: Callable[[P], tuple[Column, ...]], *forms: FullForm[P, S]) -> Full[P, S]:
        """The full equations in ``forms``, each under its own name, the first the default,
        with output ``columns``."""
        return cls({form.name: form for form in forms}, forms[0].name, columns)

    def form(self, name: str | None = None) -> FullForm[P, S]:
        """The form called ``name`` (None: the default); ParameterError naming the others."""
        if name is None:
            return self.forms[self.default]
        if name not in self.forms:
            raise ParameterError(
                f"form = {name!r} is not a full form (allowed: {', '.join(self.forms)})"
            )
        return self.forms[name]


@dataclass(frozen=True, slots=True)
class Diagnostics(Generic[P, S]):
    """Extra per-sample quantities of an averaged run (e.g. the fast frequencies), written
    beside it: ``compute(p, initial, columns) -> columns`` described by ``columns``."""

    compute: Callable[[P, S, Columns], Columns]
    columns: tuple[Column, ...]


@dataclass(frozen=True, slots=True)
class Averaged(Generic[P, S]):
    """The averaged equations.

    ``form(p, initial, options)`` gives the equations in the coordinates to integrate them in;
    ``columns(p)`` their output columns. The averaging error that ``tumble verify`` measures
    is the difference of the ``compare`` columns between the full and the averaged runs, or,
    where the slow variables are not plain columns of the full run (an envelope compared at
    the extrema), ``errors(p, full, averaged) -> {variable: (times, |error|)}``.
    """

    form: Callable[[P, S, AveragingOptions], AveragedForm[P, S]]
    columns: Callable[[P], tuple[Column, ...]]
    compare: tuple[str, ...] = ()
    coordinates: tuple[str, ...] = ()  # choices of AveragingOptions.coordinates; first: default
    corrected_start: bool = False  # whether it has the first-order mean ↔ osculating start
    numeric: bool = False  # whether the general engine can replace the paper's right-hand side
    orders: tuple[int, ...] = (1,)  # orders of averaging it offers (AveragingOptions.order)
    hybrid: bool = False  # whether its forms have bands a hybrid run crosses (Crossing)
    steps: bool = False  # whether its forms take asymptotic crossing steps (AveragedForm.steps)
    engine: bool = False  # whether its only averaged equations are the general engine's
    errors: Callable[[P, Sampled, Sampled], Mapping[str, tuple[FloatArray, FloatArray]]] | None = (
        None
    )
    diagnostics: Diagnostics[P, S] | None = None

    def check(self, options: AveragingOptions) -> AveragingOptions:
        """``options`` with the default coordinates filled in; ParameterError naming the key
        if this model cannot honour them."""
        if options.coordinates and options.coordinates not in self.coordinates:
            allowed = ", ".join(f'"{c}"' for c in self.coordinates) or "none: one form only"
            raise ParameterError(
                f"run.averaged_form = {options.coordinates!r} is not a form of the averaged "
                f"equations (allowed: {allowed})"
            )
        if options.start == "corrected" and not self.corrected_start:
            raise ParameterError(
                'run.averaged_init = "corrected" is not available for this model (allowed: "exact")'
            )
        if options.hybrid and not self.hybrid:
            raise ParameterError(
                'run.averaged_method = "hybrid" is not available for this model (allowed: "plain")'
            )
        if options.averaged_only and not self.steps:
            raise ParameterError(
                "run.averaged_only is not available for this model: its averaged runs take "
                "no asymptotic crossing step"
            )
        if options.order not in self.orders:
            allowed = ", ".join(map(str, self.orders))
            raise ParameterError(
                f"run.averaging_order = {options.order} is not available for this model "
                f"(allowed: {allowed})"
            )
        if not options.coordinates and self.coordinates:
            return replace(options, coordinates=self.coordinates[0])
        return options


@dataclass(frozen=True, slots=True)
class Unperturbed(Generic[P, S]):
    """The exact unperturbed motion (ε = 0): the generating solution the averaging is taken
    over, in closed form (elliptic functions).

    ``motion(p, initial)`` is the motion through the initial state, a function of times
    t (n,) → states of the default full form, shape (n, dim); ``rhs(t, y, p)`` is the default
    full form's right-hand side with the perturbation removed, whose solution that motion is
    (a test integrates one against the other for every model).
    """

    equation: str
    motion: Callable[[P, S], Callable[[FloatArray], FloatArray]]
    rhs: Callable[[float, FloatArray, P], FloatArray]


@dataclass(frozen=True, slots=True)
class ClosedForm(Generic[P, S]):
    """The averaged motion in closed form: ``evaluate(p, initial, tau) -> columns``."""

    evaluate: Callable[[P, S, FloatArray], Columns]
    columns: Callable[[P], tuple[Column, ...]]


@dataclass(frozen=True, slots=True)
class Validity(Generic[P, S]):
    """Where the averaged descriptions lose accuracy, and what the paper predicts.

    ``check(p, initial, slow, tau_end)`` lists the regions an averaged or closed-form
    trajectory ``slow`` enters before ``tau_end``; ``limits(p, initial)`` gives the paper's
    predicted limits as τ → ∞ (keys of ``summary.json``).
    """

    check: Callable[[P, S, SlowPath, float], list[ValidityIssue]]
    limits: Callable[[P, S], Mapping[str, Json]] | None = None


@dataclass(frozen=True)
class StationaryMotion(Generic[P]):
    """A stationary motion of a full form, and the local coordinates to linearize it in.

    ``embed(x)`` maps local coordinates (zero at the stationary motion) to a state of the full
    form, exactly to first order in ``x``; ``tangent(y, dy)`` maps a state rate to the rates of
    the local coordinates. Both, and ``rhs``, must accept complex arrays (the Jacobian is taken
    by complex-step differentiation). Coordinates outside ``keep`` must not feed back into the
    others (they only add roots of their own, e.g. a free phase).
    """

    name: str
    equation: str
    state: FloatArray
    rhs: Callable[[float, ComplexArray, P], ComplexArray]
    embed: Callable[[ComplexArray], ComplexArray]
    tangent: Callable[[ComplexArray, ComplexArray], ComplexArray]
    coordinates: tuple[str, ...]
    keep: tuple[int, ...]
    leading: float = 1.0  # the characteristic polynomial is reported as leading·det(λE − J)
    coefficients: FloatArray | None = None  # closed form, highest power first
    approx_roots: ComplexArray | None = None  # the paper's approximate roots
    approx_note: str = ""  # where the approximation is invalid
    structural_zero: bool = False  # the closed-form constant coefficient is exactly zero
    # Members of a one-parameter family of stationary motions this one belongs to (e.g. the
    # free phase of a co-rotation), by parameter value; None if isolated.
    family: Callable[[float], StationaryMotion[P]] | None = None


@dataclass(frozen=True)
class Report:
    """Model-specific results of a run beyond the per-method columns.

    ``tables`` maps a file stem (e.g. ``"full_extrema"``) to its header and rows; ``summary``
    holds keys added at the top level of ``summary.json``.
    """

    tables: Mapping[str, tuple[tuple[str, ...], list[tuple[Json, ...]]]] = field(
        default_factory=dict
    )
    summary: Mapping[str, Json] = field(default_factory=dict)


@dataclass(frozen=True)
class Model(Generic[P, S]):
    """A registered model: what it is, and the capabilities it has.

    Attributes
    ----------
    name : str
        Registered name (the scenario's ``model`` key).
    description : str
        One line for ``tumble models``.
    paper : Paper or None
        The paper the model implements (None for a model no paper derives).
    time : Column
        The time variable of its outputs (the paper's own: τ or t) and its unit.
    full : Full
        The full equations of motion.
    check : callable
        ``check(p, method)``: ParameterError when ``method`` cannot apply to ``p`` (e.g. κ = 0
        for the averaged equations); called before any work.
    check_initial : callable, optional
        ``check_initial(p, initial, method)``: ParameterError when ``method`` cannot start
        from ``initial`` (a body at rest for averaged equations that follow its angular
        momentum); called before any work, and by the scenario loader before user code loads.
    averaged, closed_form, validity : optional
        The averaged equations, their closed form, and where they lose accuracy.
    unperturbed : Unperturbed, optional
        The exact motion at ε = 0 through an initial state.
    stationary : callable, optional
        ``stationary(p)``: the stationary motion whose stability the paper analyses.
    report : callable, optional
        ``report(p, initial, trajectories)``: extra tables and summary keys of a run.
    scenario : ScenarioSchema, optional
        The keys of its scenario files and how they become ``Params`` and ``State``
        (:mod:`tumble.models.schema`); None: Python only.
    methods : tuple of str
        The methods in the order a run computes and compares them; exactly those the
        capabilities provide ("full", and "averaged", "closed_form" where present).
    """

    name: str
    description: str
    paper: Paper | None
    time: Column
    full: Full[P, S]
    check: Callable[[P, str], None]
    methods: tuple[Method, ...]
    averaged: Averaged[P, S] | None = None
    closed_form: ClosedForm[P, S] | None = None
    unperturbed: Unperturbed[P, S] | None = None
    validity: Validity[P, S] | None = None
    stationary: Callable[[P], StationaryMotion[P]] | None = None
    report: Callable[[P, S, Mapping[str, Sampled]], Report] | None = None
    scenario: ScenarioSchema[P, S] | None = None
    check_initial: Callable[[P, S, str], None] | None = None

    def __post_init__(self) -> None:
        provided = {"full"}
        provided |= {"averaged"} if self.averaged is not None else set()
        provided |= {"closed_form"} if self.closed_form is not None else set()
        if set(self.methods) != provided or len(self.methods) != len(provided):
            raise ValueError(
                f"model {self.name}: methods {self.methods} must list exactly the capabilities "
                f"it has: {sorted(provided)}"
            )

    def columns(self, p: P, method: str) -> tuple[Column, ...]:
        """Output columns of ``method`` for parameters ``p``."""
        if method == "averaged" and self.averaged is not None:
            return self.averaged.columns(p)
        if method == "closed_form" and self.closed_form is not None:
            return self.closed_form.columns(p)
        if method == "full":
            return self.full.columns(p)
        raise ParameterError(
            f"run.methods: {method!r} is not a method of {self.name} "
            f"(allowed: {', '.join(self.methods)})"
        )

    def slow_state(
        self, p: P, y: FloatArray, options: AveragingOptions | None = None, form: str | None = None
    ) -> FloatArray:
        """The averaged form's slow state for the full state vector ``y`` at t = 0.

        ``y`` is a state of the full form ``form`` (default: the model's default form); it is
        turned into the model's initial-condition record (``FullForm.state_of``) and that into
        the slow state of the averaged form ``options`` selects, exactly as a run started from
        it would (``options.start = "corrected"`` gives the mean state of an osculating one).
        """
        if self.averaged is None:
            raise ParameterError(f"model {self.name} has no averaged form")
        opts = self.averaged.check(options or AveragingOptions())
        st = self.full.form(form).state_of(p, np.asarray(y, dtype=float))
        return self.averaged.form(p, st, opts).initial_state(p, st)


@dataclass(frozen=True)
class Declaration(Generic[P, S]):
    """What a scenario of a model may ask for, known without the model's numerics.

    A scenario is validated against this alone (its keys, its ``[run]`` choices, the methods
    its parameters allow), so that an input error is reported before numba, scipy and the
    model's equations load. A shipped model declares it in its package's ``inputs`` module and
    builds its :class:`Model` from it; for any other model it is read off the model
    (:meth:`of`).

    Attributes
    ----------
    name, time, methods, check, scenario
        As the :class:`Model` fields of those names.
    check_initial
        As the :class:`Model` field of that name.
    numeric, coordinates, corrected_start, orders, hybrid, steps, engine
        As the :class:`Averaged` fields of those names (False, (), False, (1,), False, False,
        False without averaged equations). ``engine``: the averaged equations are the general
        engine's quadrature alone, with no paper right-hand side, so that a run's
        ``averaging`` is "numeric" whatever the default.
    """

    name: str
    time: Column
    methods: tuple[Method, ...]
    check: Callable[[P, str], None]
    scenario: ScenarioSchema[P, S] | None = None
    numeric: bool = False
    coordinates: tuple[str, ...] = ()
    corrected_start: bool = False
    orders: tuple[int, ...] = (1,)
    hybrid: bool = False
    check_initial: Callable[[P, S, str], None] | None = None
    engine: bool = False
    steps: bool = False

    def averaged(
        self,
        form: Callable[[P, S, AveragingOptions], AveragedForm[P, S]],
        columns: Callable[[P], tuple[Column, ...]],
        **details: Any,
    ) -> Averaged[P, S]:
        """The model's averaged equations ``form`` with output ``columns``, offering exactly
        the choices declared here (``numeric``, ``coordinates``, ``corrected_start``,
        ``orders``, ``hybrid``, ``steps``); ``details`` are the other :class:`Averaged` fields
        (``compare``, ``errors``, ``diagnostics``)."""
        return Averaged(
            form,
            columns,
            coordinates=self.coordinates,
            corrected_start=self.corrected_start,
            numeric=self.numeric,
            orders=self.orders,
            hybrid=self.hybrid,
            steps=self.steps,
            engine=self.engine,
            **details,
        )

    def model(self, full: Full[P, S], **capabilities: Any) -> Model[P, S]:
        """The shipped model declared here: its name, description and paper from
        :data:`tumble.catalogue.CATALOGUE`, its time, methods, method check and scenario keys
        from this declaration, its full equations ``full``; ``capabilities`` are the other
        :class:`Model` fields (``averaged``, ``closed_form``, ``unperturbed``, ``validity``,
        ``stationary``, ``report``)."""
        entry = CATALOGUE[self.name]
        return Model(
            name=entry.name,
            description=entry.description,
            paper=entry.paper,
            time=self.time,
            full=full,
            check=self.check,
            check_initial=self.check_initial,
            methods=self.methods,
            scenario=self.scenario,
            **capabilities,
        )

    @classmethod
    def of(cls, model: Model[P, S]) -> Declaration[P, S]:
        """The declaration of ``model``."""
        avg = model.averaged
        return cls(
            model.name,
            model.time,
            model.methods,
            model.check,
            model.scenario,
            numeric=avg is not None and avg.numeric,
            coordinates=avg.coordinates if avg is not None else (),
            corrected_start=avg is not None and avg.corrected_start,
            orders=avg.orders if avg is not None else (1,),
            hybrid=avg is not None and avg.hybrid,
            check_initial=model.check_initial,
            engine=avg is not None and avg.engine,
            steps=avg is not None and avg.steps,
        )


def first_time(
    condition: Callable[[FloatArray], FloatArray],
    grid: FloatArray,
    values: FloatArray | None = None,
    xtol: float = 1e-12,
) -> float | None:
    """First τ on ``grid`` where ``condition(τ) > 0``, refined by root finding; None if never.

    Parameters
    ----------
    condition : callable
        Vectorized ``condition(tau) -> values``; the region is where the values are positive.
    grid : ndarray
        Ascending times to scan [model time unit]; the first crossing is then bracketed.
    values : ndarray, optional
        ``condition(grid)``, where the caller has it (a streamed run's ``slow`` replays the
        run at every call).
    xtol : float
        How closely the root is found [model time unit].
    """
    values = condition(grid) if values is None else values
    hits = np.flatnonzero(values > 0.0)
    if hits.size == 0:
        return None
    i = int(hits[0])
    if i == 0:
        return float(grid[0])
    from scipy.optimize import brentq  # loaded where a run is checked, not where it is read

    return float(
        brentq(lambda t: float(condition(np.array([t]))[0]), grid[i - 1], grid[i], xtol=xtol)
    )


def separatrix_time(
    slow: SlowPath, grid: FloatArray, I2: float, cols: Columns | None = None
) -> float | None:
    """First time a triaxial body's averaged motion crosses the separatrix L² = 2T·I2 (where
    the polhode frequency vanishes), refined by root finding; None if it never does.

    Parameters
    ----------
    slow : callable
        ``slow(t) -> columns`` with ``L`` and ``T``.
    grid : ndarray
        Ascending times to scan [model time unit].
    I2 : float
        The middle principal moment [inertia unit].
    cols : dict, optional
        ``slow(grid)``, where the caller has it: a streamed run's ``slow`` integrates the run
        again at every call, which over a long run costs more than the run's own samples.
    """
    cols = slow(grid) if cols is None else cols
    gap = cols["L"] ** 2 - 2.0 * cols["T"] * I2
    flips = np.flatnonzero(np.sign(gap[1:]) * np.sign(gap[:-1]) < 0.0)
    if not flips.size:
        return None
    s0 = np.sign(gap[0])

    def other_side(t: FloatArray) -> FloatArray:
        c = slow(t)
        return -s0 * (c["L"] ** 2 - 2.0 * c["T"] * I2)

    # To 1e-7 of the span, finer than the message's six digits: near the separatrix the gap
    # falls to zero like 1/ln, which slows the root finder to bisection, and each evaluation
    # of a streamed run's ``slow`` integrates a stretch of the run again (0.1 s on a decade).
    found = first_time(other_side, grid, -s0 * gap, 1e-7 * float(grid[-1] - grid[0]))
    return float(found if found is not None else grid[flips[0] + 1])


def separatrix_issue(
    slow: SlowPath, grid: FloatArray, I2: float, time: str = "t", cols: Columns | None = None
) -> ValidityIssue | None:
    """The first crossing of the separatrix L² = 2T·I2 by a triaxial body's averaged motion
    (:func:`separatrix_time`; ``cols``, ``slow(grid)`` if the caller has it) as a validity
    issue; ``time`` is the model's name for its time column (``"t"``, ``"τ"``) in the
    message."""
    tau_s = separatrix_time(slow, grid, I2, cols)
    if tau_s is None:
        return None
    return ValidityIssue(
        "separatrix",
        tau_s,
        f"the averaged motion crosses the separatrix L² = 2T·I2 at {time} = {tau_s:.6g}: "
        "the polhode frequency ν1 → 0 there and averaging is locally invalid; the error after "
        "the crossing is usually first order, theory allows ε|ln ε| (Neishtadt 1975), but the "
        "direction of L can lose more where the torque turns it: on the way there ν2/ν1 "
        "runs through every integer, each a resonance that can turn L by O(√ε) (theory of "
        "separatrix crossing, §5)",
        label="the separatrix",
    )


def frozen_array(name: str, value: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """``value`` as a read-only float array of ``shape``; ParameterError naming ``name`` if it
    has another shape or a non-finite entry."""
    arr = np.array(value, dtype=float)
    if arr.shape != shape:
        raise ParameterError(f"{name} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must contain finite numbers only, got {value!r}")
    arr.setflags(write=False)
    return arr
