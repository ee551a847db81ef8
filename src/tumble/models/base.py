"""The shape every paper model exposes to the rest of tumble (STYLE.md section 2).

A model module provides plain numerics; this record tells the integration and analysis layers
how to drive it: which state vectors its full and averaged forms use, how to convert them to
the output columns, and which closed forms and validity checks it has.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels import Kernel

__all__ = [
    "AveragedForm",
    "Breakpoint",
    "Column",
    "FullForm",
    "ModelRecord",
    "Report",
    "StationaryMotion",
    "ValidityIssue",
    "check_averaging",
    "first_time",
    "frozen_array",
]


@dataclass(frozen=True, slots=True)
class Column:
    """Metadata of one output column; exports and axis labels read it, never retype it."""

    name: str
    long_name: str
    units: str
    equation: str = ""
    angle: bool = False  # compare modulo 2π
    unwrap: bool = False  # reported as a continuous function of time (spec/medvedev.md §14)


@dataclass(frozen=True, slots=True)
class FullForm:
    """One form of the full equations of motion.

    ``rhs(t, y, p)`` is the right-hand side; ``from_slow(p, initial)`` builds the state vector;
    ``to_columns(t, Y, p)`` turns states ``Y`` of shape (n, dim) into output columns.
    ``kernel(p)`` gives the same right-hand side compiled (:class:`tumble.kernels.Kernel`), or
    None where ``p`` holds a Python function; ``rhs`` stays the reference that the scipy
    integrator runs.
    """

    name: str
    equation: str
    rhs: Callable[[float, FloatArray, Any], FloatArray]
    from_slow: Callable[[Any, Any], FloatArray]
    to_columns: Callable[[FloatArray, FloatArray, Any], dict[str, FloatArray]]
    kernel: Callable[[Any], Kernel | None] | None = None


@dataclass(frozen=True)
class Breakpoint:
    """A surface ``condition(t, y) = 0`` that the solution crosses at most once, where the
    right-hand side is not smooth (a separatrix).

    The integration stops exactly there and restarts from ``restart(t, y)`` (default: the same
    state). A restart map lets a solution leave a non-Lipschitz point it would otherwise stick
    to (e.g. the spurious k² ≡ 1 solution on a separatrix); one that raises stops the run
    there. A breakpoint at a known time (``Breakpoint.at_time``) splits the integration
    interval there instead, so that no step ever straddles it.
    """

    condition: Callable[[float, FloatArray], float] | None
    restart: Callable[[float, FloatArray], FloatArray] | None = None
    time: float | None = None  # a known time instead of a condition (a kink in a forcing)

    @classmethod
    def at_time(cls, t: float) -> Breakpoint:
        """A breakpoint at a fixed time ``t`` (the integration is split there)."""
        return cls(None, None, float(t))


@dataclass(frozen=True, slots=True)
class AveragedForm:
    """The averaged (evolution) equations in the coordinates used to integrate them."""

    name: str
    equation: str
    rhs: Callable[[float, FloatArray, Any], FloatArray]
    from_slow: Callable[[Any, Any], FloatArray]
    to_columns: Callable[[FloatArray, FloatArray, Any, Any], dict[str, FloatArray]]
    breakpoints: tuple[Breakpoint, ...] = ()  # non-smooth surfaces: stop and restart there
    # The reason the right-hand side last refused a state (it returned NaN so the solver would
    # reject the step); reported if the integration then fails.
    failure: Callable[[], str | None] | None = None


@dataclass(frozen=True, slots=True)
class ValidityIssue:
    """A region where a method loses accuracy, entered first at time ``tau``."""

    condition: str  # short stable identifier, e.g. "theta_crossing"
    tau: float  # first time the condition holds [model time unit]
    message: str  # one sentence for the user, citing the spec section
    label: str = ""  # a few words for verdicts ("ϑ = π/2", "resonance ν1 = 2ν2"); "" → condition


@dataclass(frozen=True)
class StationaryMotion:
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
    rhs: Callable[[float, Any, Any], Any]
    embed: Callable[[Any], Any]
    tangent: Callable[[Any, Any], Any]
    coordinates: tuple[str, ...]
    keep: tuple[int, ...]
    leading: float = 1.0  # the characteristic polynomial is reported as leading·det(λE − J)
    coefficients: FloatArray | None = None  # closed form, highest power first
    approx_roots: Any = None  # complex ndarray: the paper's approximate roots
    approx_note: str = ""  # where the approximation is invalid
    structural_zero: bool = False  # the closed-form constant coefficient is exactly zero
    # Members of a one-parameter family of stationary motions this one belongs to (e.g. the
    # free phase of a co-rotation), by parameter value; None if isolated.
    family: Callable[[float], StationaryMotion] | None = None


@dataclass(frozen=True)
class Report:
    """Model-specific results of a run beyond the per-method columns.

    ``tables`` maps a file stem (e.g. ``"full_extrema"``) to its header and rows; ``summary``
    holds keys added at the top level of ``summary.json``.
    """

    tables: Mapping[str, tuple[tuple[str, ...], list[tuple[Any, ...]]]] = field(
        default_factory=dict
    )
    summary: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class ModelRecord:
    """Registry entry of a paper model.

    Attributes
    ----------
    name : str
        Registered name (the scenario's ``model`` key).
    description : str
        One line for ``tumble models``.
    paper : str
        Citation of the seed paper and the spec that supersedes it.
    methods : tuple of str
        Methods a scenario may request.
    columns : mapping
        Output columns of each method, in contract order.
    full : FullForm
        Default form of the full equations; ``full_forms`` lists every form by name.
    averaged_form : callable
        ``(p, initial) -> AveragedForm`` — the coordinates to integrate the averaged system in.
    closed_form : callable
        ``(p, initial, tau) -> columns``.
    check_method : callable
        ``(p, method) -> None``; raises ``ParameterError`` when a method cannot apply.
    validity : callable
        ``(p, initial, slow, tau_end) -> list[ValidityIssue]`` for an averaged trajectory given
        as ``slow(tau) -> columns``.
    limits : callable
        ``(p, initial) -> dict`` of the paper's predicted limits as τ → ∞.
    stationary : callable, optional
        ``p -> StationaryMotion``: the stationary motion whose stability the paper analyses.
    diagnostics : callable, optional
        ``(p, initial, columns) -> columns``: extra per-sample quantities of an averaged run
        (e.g. the fast frequencies), written beside it; ``diagnostic_columns`` describes them.
    figure : str
        File name of the run's figure.
    plot_variables : tuple of str
        Columns drawn in the figure, one panel each.
    time_name, time_units : str
        Name and unit of the time column in the output files (the paper's time variable).
    columns_for : callable, optional
        ``p -> columns``: output columns that depend on the parameters (e.g. perturbed and
        unperturbed runs write different columns); overrides ``columns`` when given.
    report : callable, optional
        ``(p, initial, trajectories) -> Report``: extra tables and summary keys of a run.
    plot_kind : {"comparison", "envelope"}
        Which figure the run draws.
    verify_variables : tuple of str
        The slow variables whose averaged-vs-full error ``tumble verify`` measures (columns
        of both methods), unless ``slow_errors`` is given.
    slow_errors : callable, optional
        ``(p, full, averaged) -> {variable: (times, |error|)}`` for trajectories of the two
        methods: the model's own measure of the averaging error where the slow variables are
        not plain columns of the full run (e.g. an envelope compared at the extrema).
    """

    name: str
    description: str
    paper: str
    methods: tuple[str, ...]
    columns: Mapping[str, tuple[Column, ...]]
    full: FullForm
    full_forms: Mapping[str, FullForm]
    averaged_form: Callable[[Any, Any], AveragedForm]
    closed_form: Callable[[Any, Any, FloatArray], dict[str, FloatArray]]
    check_method: Callable[[Any, str], None]
    validity: Callable[
        [Any, Any, Callable[[FloatArray], dict[str, FloatArray]], float], list[ValidityIssue]
    ]
    limits: Callable[[Any, Any], dict[str, Any]]
    stationary: Callable[[Any], StationaryMotion] | None = None
    diagnostics: Callable[[Any, Any, dict[str, FloatArray]], dict[str, FloatArray]] | None = None
    diagnostic_columns: tuple[Column, ...] = ()
    figure: str = "comparison.png"
    plot_variables: tuple[str, ...] = ("k", "theta")
    time_name: str = "tau"
    time_units: str = "1"
    columns_for: Callable[[Any], Mapping[str, tuple[Column, ...]]] | None = None
    report: Callable[[Any, Any, Mapping[str, Any]], Report] | None = None
    plot_kind: str = "comparison"
    verify_variables: tuple[str, ...] = ()
    slow_errors: Callable[[Any, Any, Any], Mapping[str, tuple[FloatArray, FloatArray]]] | None = (
        None
    )

    def method_columns(self, p: Any, method: str) -> tuple[Column, ...]:
        """Output columns of ``method`` for parameters ``p``."""
        columns = self.columns if self.columns_for is None else self.columns_for(p)
        return columns[method]


def first_time(condition: Callable[[FloatArray], FloatArray], grid: FloatArray) -> float | None:
    """First τ on ``grid`` where ``condition(τ) > 0``, refined by root finding; None if never.

    Parameters
    ----------
    condition : callable
        Vectorized ``condition(tau) -> values``; the region is where the values are positive.
    grid : ndarray
        Ascending times to scan [model time unit]; the first crossing is then bracketed.
    """
    values = condition(grid)
    hits = np.flatnonzero(values > 0.0)
    if hits.size == 0:
        return None
    i = int(hits[0])
    if i == 0:
        return float(grid[0])
    return float(
        brentq(lambda t: float(condition(np.array([t]))[0]), grid[i - 1], grid[i], xtol=1e-12)
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


AVERAGING_METHODS = ("closed_form", "numeric")
"""How an averaged method forms its right-hand side: the paper's closed form, or the general
engine of :mod:`tumble.averaging` (the scenario key ``[run] averaging``)."""


def check_averaging(value: str) -> None:
    """ParameterError unless ``value`` is one of :data:`AVERAGING_METHODS`."""
    if value not in AVERAGING_METHODS:
        raise ParameterError(
            f"run.averaging = {value!r} is not a method of averaging "
            '(allowed: "closed_form", "numeric")'
        )
