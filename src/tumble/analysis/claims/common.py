"""Pieces shared by the claim modules: tolerances, the measured record, the measurement of the
usual criteria (:func:`by_convergence`, :func:`by_forms`, :func:`by_order`, :func:`within`;
:func:`judged` for a claim's own), the usual figures (``*_panel``) and small numerics.

The verdicts of the claims follow three rules (see each module): "to integration accuracy"
is decided by convergence (:func:`converged`: the difference falls as the tolerance is
tightened, or is within the round-off budget of the runs), never by a fixed multiple of rtol;
"first order" is a fitted order of the averaging error ≥ :data:`FIRST_ORDER`; and limits of
the full model are judged within O(ε) of the averaged limit.
"""

from __future__ import annotations

import contextlib
import functools
import warnings
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Any, Literal, TypedDict, TypeVar, cast

import numpy as np

from tumble._typing import FloatArray
from tumble.analysis.claims.base import Measurement, Panel, Series, plain
from tumble.errors import TumbleWarning

__all__ = [
    "FIRST_ORDER",
    "TIGHT",
    "Convergence",
    "Difference",
    "Tolerances",
    "budget_panel",
    "by_convergence",
    "by_forms",
    "by_order",
    "cache_per_scale",
    "converged",
    "eps_panel",
    "forms_panel",
    "judged",
    "max_abs",
    "measured",
    "measured_by",
    "quiet",
    "threshold_panel",
    "time_panel",
    "tolerance_scale",
    "tolerances",
    "within",
    "wrap",
]


T = TypeVar("T")

Difference = float | dict[str, float]
"""What a compared pair of runs differs by: one figure, or one per case."""


class Tolerances(TypedDict):
    """Keyword arguments ``rtol``, ``atol`` of :func:`tumble.integrate.simulate`."""

    rtol: float
    atol: float


TIGHT: Tolerances = {"rtol": 1e-12, "atol": 1e-14}
"""Tolerances of the reference integrations (DOP853: the global error of the O(10⁴)-step runs
is ~1e-9 relative, far below any error a wrong formula leaves, O(ε) ≥ 1e-3 or O(1))."""

_SCALE: ContextVar[float] = ContextVar("tolerance_scale", default=1.0)

LEVELS = (1.0, 10.0, 100.0, 1000.0, 10000.0)
""":func:`converged` runs the comparison at these multiples of the claim's tolerances."""

SLOPE = 0.5
"""...and the difference must fall with the tolerance at least this fast: the slope of
log(difference) against log(rtol), fitted over the levels. DOP853's global error goes as
rtol^0.7–1.1 (measured on the claims' runs at 0.1, 1 and 10 × their tolerances: 0.71–1.09; one
trajectory's error scatters by a few times around the trend as the step sequence changes,
which the fit over four decades absorbs), while a wrong formula leaves a difference that does
not move with the tolerance (slope ≈ 0)."""

ROUNDOFF = 10.0 * float(np.finfo(float).eps)
"""Round-off budget per right-hand-side evaluation: below ``ROUNDOFF × evaluations`` a
difference is rounding, whatever the tolerance."""


def tolerances(base: Tolerances = TIGHT) -> Tolerances:
    """``base`` times the scale in force (:func:`tolerance_scale`; 1 by default)."""
    f = _SCALE.get()
    return {"rtol": base["rtol"] * f, "atol": base["atol"] * f}


@contextlib.contextmanager
def tolerance_scale(factor: float) -> Iterator[None]:
    """Run the claims with every reference tolerance multiplied by ``factor`` (their verdicts
    must not change: the test of the claims runs them at 0.1 and 10)."""
    token = _SCALE.set(factor)
    try:
        yield
    finally:
        _SCALE.reset(token)


def cache_per_scale(fn: Callable[..., T]) -> Callable[..., T]:
    """:func:`functools.cache` for a claim's shared runs, keyed by the tolerance scale in
    force too (the runs at another scale are other runs)."""

    @functools.cache
    def cached(scale: float, *args: Any) -> T:
        return fn(*args)

    @functools.wraps(fn)
    def wrapper(*args: Any) -> T:
        return cached(_SCALE.get(), *args)

    return wrapper


@dataclass(frozen=True)
class Convergence:
    """Two numerical results compared at several tolerances (:data:`LEVELS` × the claim's),
    case by case: a claim may compare several runs, and each must converge on its own.

    Attributes
    ----------
    cases : dict
        Case → its difference at each level (the first: the claim's tolerances).
    budget : float
        The round-off budget of the runs (``ROUNDOFF`` × right-hand-side evaluations).
    rtol : float
        The claim's relative tolerance.
    """

    cases: dict[str, tuple[float, ...]]
    budget: float
    rtol: float

    def slope(self, case: str) -> float:
        """Fitted slope of log(difference) against log(rtol) over the levels."""
        d = np.maximum(np.asarray(self.cases[case]), 1e-300)
        return float(np.polyfit(np.log10(LEVELS), np.log10(d), 1)[0])

    def _agrees(self, case: str) -> bool:
        return self.cases[case][0] <= self.budget or self.slope(case) >= SLOPE

    @property
    def critical(self) -> str:
        """The case that decides: the first that fails, else the largest difference."""
        failing = [c for c in self.cases if not self._agrees(c)]
        return failing[0] if failing else max(self.cases, key=lambda c: self.cases[c][0])

    @property
    def holds(self) -> bool:
        """The results agree in every case: the difference is rounding, or integration error
        (it falls with the tolerance at slope ≥ ``SLOPE``)."""
        return all(self._agrees(c) for c in self.cases)

    @property
    def difference(self) -> float:
        """The measured figure: the deciding case's difference at the claim's tolerance."""
        return self.cases[self.critical][0]

    @property
    def threshold(self) -> str:
        return (
            f"slope ≥ {SLOPE:g} (measured {self.slope(self.critical):.2f}) or ≤ round-off "
            f"budget {self.budget:.2g}"
        )

    @property
    def criterion(self) -> str:
        several = " in every case (the figure: the deciding case)" if len(self.cases) > 1 else ""
        return (
            f"agree if the difference falls with the tolerance (slope of log difference vs "
            f"log rtol over rtol × {', '.join(f'{x:g}' for x in LEVELS)} ≥ {SLOPE:g}: "
            f"integration error, not a discrepancy) or is within the round-off budget{several}"
        )

    def record(self) -> dict[str, Any]:
        """The figures behind the verdict, for the claim's details."""
        out: dict[str, Any] = {
            "rtol": [self.rtol * x for x in LEVELS],
            "roundoff_budget": self.budget,
        }
        for c, d in self.cases.items():
            entry = {"difference": list(d), "slope": self.slope(c)}
            if len(self.cases) == 1:
                out.update(entry)
            else:
                out.setdefault("cases", {})[c] = entry
        return out


def measured_by(
    conv: Convergence,
    units: str,
    what: str,
    qualification: str = "",
    *,
    also: str = "",
    **details: Any,
) -> dict[str, Any]:
    """The :func:`measured` record of a claim decided by ``conv``: its figure, threshold and
    criterion (with ``also``, a further condition of the claim), and the convergence figures
    under ``details.convergence``."""
    return measured(
        conv.difference,
        units,
        what,
        conv.threshold,
        conv.criterion + also,
        qualification,
        convergence=conv.record(),
        **details,
    )


def by_convergence(
    conv: Convergence,
    panels: Iterable[Panel],
    units: str,
    what: str,
    qualification: str = "",
    *,
    also: str = "",
    condition: bool = True,
    **details: Any,
) -> Measurement:
    """The :class:`~tumble.analysis.claims.base.Measurement` of a claim decided by ``conv``.

    Parameters
    ----------
    conv : Convergence
        The comparison that decides the claim.
    panels : iterable of Panel
        The figure's panels.
    units, what, qualification, also, **details
        As for :func:`measured_by`.
    condition : bool, optional
        A further condition of the claim (the one ``also`` states): the claim holds if ``conv``
        does and this holds.

    Returns
    -------
    Measurement
        Holds if ``conv.holds`` and ``condition``; qualified if the theory page's
        ``qualification`` is given.
    """
    m = measured_by(conv, units, what, qualification, also=also, **details)
    return Measurement(conv.holds and condition, bool(qualification), m, tuple(panels))


def by_forms(
    conv: Convergence,
    tau: Any,
    differences: Mapping[str, Any],
    ylabel: str,
    title: str,
    units: str,
    what: str,
    qualification: str = "",
    **details: Any,
) -> Measurement:
    """The :class:`~tumble.analysis.claims.base.Measurement` of a claim that compares a run with
    another form or a closed form, decided by ``conv``: its one panel is :func:`forms_panel`.

    Parameters
    ----------
    conv : Convergence
        The comparison that decides the claim.
    tau : array_like
        Sample times of the compared runs [the paper's time unit].
    differences : mapping of str to array_like
        Each variable's difference along ``tau`` [its own unit].
    ylabel, title : str
        The panel's y label and title (as for :func:`forms_panel`).
    units, what, qualification, **details
        As for :func:`by_convergence`.

    Returns
    -------
    Measurement
        As :func:`by_convergence` gives it, with that one panel.
    """
    panels = (forms_panel(conv, tau, differences, ylabel, title),)
    return by_convergence(conv, panels, units, what, qualification, **details)


def converged(
    difference: Callable[[Tolerances], tuple[Difference, int, T]],
    base: Tolerances = TIGHT,
) -> tuple[Convergence, T]:
    """Compare two numerical results by convergence instead of a fixed threshold.

    Parameters
    ----------
    difference : callable
        ``difference(tolerances) -> (value, evaluations, payload)``: the largest difference of
        the two results computed at those tolerances (or case → difference, for a claim that
        compares several runs), the right-hand-side evaluations it took, and whatever the
        claim keeps of the run (its curves).
    base : Tolerances
        The claim's tolerances (scaled by :func:`tolerance_scale`).

    Returns
    -------
    Convergence, payload
        The comparison, and the payload of the run at the claim's tolerances.
    """
    tol = tolerances(base)
    values, evaluations, payload = [], 0, None
    for i, x in enumerate(LEVELS):
        value, n, got = difference({"rtol": tol["rtol"] * x, "atol": tol["atol"] * x})
        values.append({"all": float(value)} if not isinstance(value, dict) else dict(value))
        evaluations = max(evaluations, n)
        if i == 0:
            payload = got
    cases = {c: tuple(v[c] for v in values) for c in values[0]}
    return Convergence(cases, ROUNDOFF * evaluations, tol["rtol"]), cast(T, payload)


FIRST_ORDER = 0.75
"""A fitted order of the averaging error at or above this is first order: the ±0.25 band that
tumble's own error studies use (three to five values of ε; the O(ε²) remainder and the phase of
the O(ε) oscillation at the sampled maxima scatter the slope by up to ±0.2)."""


def by_order(
    order: float,
    panels: Iterable[Panel],
    what: str,
    qualification: str = "",
    *,
    criterion: str = "order ≥ 0.75",
    condition: bool = True,
    qualified: bool | None = None,
    **details: Any,
) -> Measurement:
    """The :class:`~tumble.analysis.claims.base.Measurement` of a claim that holds to first
    order: its error's fitted order against ε is at least :data:`FIRST_ORDER`.

    Parameters
    ----------
    order : float
        The fitted order [1].
    panels : iterable of Panel
        The figure's panels.
    what : str
        What was fitted, with the values of ε and the runs.
    qualification : str, optional
        The theory page's qualification of the paper's statement.
    criterion : str, optional
        The rule of the verdict, where the claim adds a condition to the order's.
    condition : bool, optional
        That further condition (the one ``criterion`` states).
    qualified : bool, optional
        Whether the theory page qualifies the paper's statement; by default, whether a
        ``qualification`` is given.
    **details
        Further measurements, stored under ``details``.

    Returns
    -------
    Measurement
        Holds if ``order`` ≥ :data:`FIRST_ORDER` and ``condition``.
    """
    return judged(
        order >= FIRST_ORDER and condition,
        panels,
        order,
        "1 (fitted order)",
        what,
        FIRST_ORDER,
        criterion,
        qualification,
        qualified=bool(qualification) if qualified is None else qualified,
        **details,
    )


def judged(
    holds: bool | np.bool_,
    panels: Iterable[Panel],
    value: float,
    units: str,
    what: str,
    threshold: float | str,
    criterion: str,
    qualification: str = "",
    *,
    qualified: bool,
    **details: Any,
) -> Measurement:
    """The :class:`~tumble.analysis.claims.base.Measurement` of a claim judged by its own
    criterion: whether it ``holds`` and whether the theory page ``qualified`` it, its figure's
    ``panels``, and its :func:`measured` record (the other arguments, as there)."""
    m = measured(value, units, what, threshold, criterion, qualification, **details)
    return Measurement(holds, qualified, m, tuple(panels))


def measured(
    value: float,
    units: str,
    what: str,
    threshold: float | str,
    criterion: str,
    qualification: str = "",
    **details: Any,
) -> dict[str, Any]:
    """The ``measured`` record of a :class:`Claim`, as plain JSON values.

    Parameters
    ----------
    value : float
        The one measured figure, in ``units``.
    units : str
        Its unit ("1" for a ratio or a fitted order, "rad", "1/τ" …).
    what : str
        What was measured, with the parameters of the run.
    threshold : float or str
        The figure it is judged against (same units).
    criterion : str
        The rule that turns value and threshold into the verdict.
    qualification : str, optional
        The theory page's qualification of the paper's statement ("" if none).
    **details
        Further measurements (per case, per variable …), stored under ``details``.

    Returns
    -------
    dict
        ``value``, ``units``, ``what``, ``threshold``, ``criterion`` and, where given,
        ``qualification`` and ``details``; numpy values converted by :func:`plain`.
    """
    out: dict[str, Any] = {
        "value": value,
        "units": units,
        "what": what,
        "threshold": threshold,
        "criterion": criterion,
    }
    if qualification:
        out["qualification"] = qualification
    if details:
        out["details"] = details
    result: dict[str, Any] = plain(out)
    return result


def within(
    value: float,
    threshold: float,
    panels: Iterable[Panel],
    units: str,
    what: str,
    qualification: str = "",
    **details: Any,
) -> Measurement:
    """The :class:`~tumble.analysis.claims.base.Measurement` of a claim that holds if the
    measured figure is at most a threshold.

    Parameters
    ----------
    value : float
        The measured figure [``units``].
    threshold : float
        Its bound [``units``], justified where the claim calls this.
    panels : iterable of Panel
        The figure's panels.
    units, what, qualification, **details
        As for :func:`measured`.

    Returns
    -------
    Measurement
        Holds if ``value`` ≤ ``threshold`` (criterion "value ≤ <threshold>"); qualified if the
        theory page's ``qualification`` is given.
    """
    bound = f"{threshold:g}".replace("e-0", "e-")  # 1e-09 written 1e-9
    return judged(
        value <= threshold,
        panels,
        value,
        units,
        what,
        threshold,
        f"value ≤ {bound}",
        qualification,
        qualified=bool(qualification),
        **details,
    )


def quiet(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Any:
    """Call ``fn`` with tumble's validity warnings silenced: the claims record the conditions
    they need explicitly (e.g. ``rm.validity``), and the runner's output stays readable."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TumbleWarning)
        return fn(*args, **kwargs)


def max_abs(x: Any) -> float:
    """max |x| over every element of an array-like, as a float."""
    return float(np.max(np.abs(np.asarray(x, dtype=float))))


def wrap(x: Any) -> FloatArray:
    """Angle difference wrapped to (−π, π] [rad]: angles are compared modulo 2π
    (docs/theory/resisting-medium.md §14)."""
    return np.asarray(np.angle(np.exp(1j * np.asarray(x, dtype=float))), dtype=float)


def budget_panel(
    series: Iterable[Series], conv: Convergence, xlabel: str, ylabel: str, title: str = ""
) -> Panel:
    """Differences on a logarithmic axis, with the round-off budget of ``conv`` as a reference
    line (the figure of a claim decided by :func:`converged`)."""
    return threshold_panel(
        series, conv.budget, xlabel, ylabel, label="round-off budget", title=title
    )


def forms_panel(
    conv: Convergence, tau: Any, differences: Mapping[str, Any], ylabel: str, title: str
) -> Panel:
    """The figure of a run compared by :func:`converged` with another form or a closed form:
    each variable's difference against τ on a logarithmic axis (floored at 1e-17, so that exact
    zeros can be drawn), with the round-off budget of ``conv``."""
    series = (Series(tau, np.maximum(d, 1e-17), name) for name, d in differences.items())
    return budget_panel(series, conv, "τ", ylabel, title)


def threshold_panel(
    series: Iterable[Series],
    threshold: float,
    xlabel: str = "",
    ylabel: str = "",
    *,
    label: str = "",
    xscale: Literal["linear", "log"] = "linear",
    xticks: tuple[tuple[float, str], ...] | None = None,
    title: str = "",
) -> Panel:
    """Differences on a logarithmic axis with the claim's threshold [their units] as a reference
    line (labelled ``label``)."""
    return Panel(
        series=tuple(series),
        xlabel=xlabel,
        ylabel=ylabel,
        title=title,
        xscale=xscale,
        yscale="log",
        hlines=((threshold, label),),
        xticks=xticks,
    )


def time_panel(
    series: Iterable[Series], ylabel: str, title: str = "", *, xlabel: str = "τ", **options: Any
) -> Panel:
    """Curves against time: the paper's τ unless ``xlabel`` names another (ετ, t / T);
    ``options`` are the panel's other fields (scales, reference lines)."""
    return Panel(series=tuple(series), xlabel=xlabel, ylabel=ylabel, title=title, **options)


def eps_panel(series: Iterable[Series], ylabel: str, title: str = "") -> Panel:
    """Errors against ε on logarithmic axes (the figure of a fitted order)."""
    return Panel(
        series=tuple(series), xlabel="ε", ylabel=ylabel, title=title, xscale="log", yscale="log"
    )
