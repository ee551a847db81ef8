"""The record of a checked claim and the plain description of its figure.

A claim function measures one statement of a paper and returns a :class:`Claim`: the verdict is
computed from the measurement, never written in. Its figure is described as data
(:class:`FigureSpec`: panels of series, reference lines, scales), so the numerics here import
no matplotlib; :mod:`tumble.plot.claims` draws it.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from tumble._typing import FloatArray
from tumble.analysis.json_values import plain
from tumble.errors import ParameterError

__all__ = [
    "AGREES",
    "CONFIRMED",
    "DECLARED",
    "DISAGREES",
    "EXPLAINS",
    "OBSERVATIONS",
    "PAPERS",
    "QUALIFIED",
    "REFUTED",
    "REGISTRY",
    "VERDICTS",
    "Claim",
    "ClaimInfo",
    "FigureSpec",
    "Measurement",
    "Panel",
    "Series",
    "claim",
    "claim_id",
    "plain",
    "verdict",
]

CONFIRMED = "confirmed"
QUALIFIED = "confirmed with qualification"
REFUTED = "refuted"
AGREES = "agrees"
EXPLAINS = "explains qualitatively"
DISAGREES = "does not agree"
VERDICTS = (CONFIRMED, QUALIFIED, REFUTED, AGREES, EXPLAINS, DISAGREES)
"""A paper's claim is confirmed, confirmed with qualification or refuted; a published
observation agrees with tumble within the band its record states, is explained qualitatively
(the form of the observed behaviour and its size within a factor the record states), or does
not agree."""

OBSERVATIONS = "observations"
"""The set of published observations of real objects, checked as the papers' claims are."""

PAPERS = {
    "resisting_medium": "A. V. Medvedev (1987); docs/theory/resisting-medium.md",
    "rotating_field": "Yu. G. Martynenko (1979); docs/theory/rotating-field.md",
    "nonlinear_moment": "V. M. Serov (1991); docs/theory/nonlinear-moment.md",
    OBSERVATIONS: "Published observations of objects in orbit; docs/theory/observations.md",
}

Style = Literal["line", "dashed", "dotted", "markers", "line+markers", "bar"]
Scale = Literal["linear", "log"]


@dataclass(frozen=True)
class Series:
    """One curve (or bar set) of a panel.

    Attributes
    ----------
    x, y : ndarray
        Abscissae and ordinates, same length.
    label : str
        Legend entry ("" for none).
    style : {"line", "dashed", "dotted", "markers", "line+markers", "bar"}
    """

    x: FloatArray
    y: FloatArray
    label: str = ""
    style: Style = "line"

    def __post_init__(self) -> None:
        object.__setattr__(self, "x", np.asarray(self.x, dtype=float))
        object.__setattr__(self, "y", np.asarray(self.y, dtype=float))
        if self.x.shape != self.y.shape:
            raise ValueError(f"series {self.label!r}: x {self.x.shape} and y {self.y.shape}")


@dataclass(frozen=True)
class Panel:
    """One axes of a figure.

    ``kind = "lines"`` draws ``series`` with the reference lines ``hlines``/``vlines``
    ((value, label) pairs) and optional ``xticks`` ((value, label) pairs). Other kinds hand
    ``data`` as keyword arguments to a drawing function of :mod:`tumble.plot`:
    ``"stability_map"`` → ``plot_stability_map`` (``ds`` = a stability-grid Dataset, …),
    ``"envelope"`` → ``plot_envelope`` (``datasets``, ``extrema``, …).
    """

    series: tuple[Series, ...] = ()
    xlabel: str = ""
    ylabel: str = ""
    title: str = ""
    xscale: Scale = "linear"
    yscale: Scale = "linear"
    hlines: tuple[tuple[float, str], ...] = ()
    vlines: tuple[tuple[float, str], ...] = ()
    xticks: tuple[tuple[float, str], ...] | None = None
    kind: Literal["lines", "stability_map", "envelope"] = "lines"
    data: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class FigureSpec:
    """A figure: panels in a grid of ``ncols`` columns, and its title."""

    panels: tuple[Panel, ...]
    ncols: int = 1
    title: str = ""


@dataclass(frozen=True)
class Claim:
    """One claim of one paper, checked.

    Attributes
    ----------
    id : str
        ``rm-1`` …, ``rf-1`` …, ``nm-1`` …: the short alias that published verdict lists use.
    paper : str
        Model name (``resisting_medium``, ``rotating_field``, ``nonlinear_moment``).
    title : str
        Short title.
    statement : str
        The claim as the paper makes it, with its equation or section numbers.
    theory_ref : str
        The sections and corrections of the theory page that state or qualify it.
    verdict : str
        One of :data:`VERDICTS`, computed from ``measured``.
    measured : dict
        Plain JSON values: ``value``, ``units``, ``what``, ``threshold``, ``criterion`` and,
        where it applies, ``qualification`` and ``details``.
    figure : FigureSpec
        The figure of the check.
    name : str
        What the claim states, in snake_case (``rotation_about_middle_axis_is_unstable`` for
        ``rf-6``); it selects the claim as the id does. Keyword-only, after the fields above.
    """

    id: str
    paper: str
    title: str
    statement: str
    theory_ref: str
    verdict: str
    measured: dict[str, Any]
    figure: FigureSpec
    name: str = field(kw_only=True)

    def to_dict(self) -> dict[str, Any]:
        """Everything but the figure, as plain JSON values (for ``claims.json``)."""
        return plain(
            {
                "id": self.id,
                "name": self.name,
                "paper": self.paper,
                "title": self.title,
                "statement": self.statement,
                "theory_ref": self.theory_ref,
                "verdict": self.verdict,
                "measured": self.measured,
            }
        )


@dataclass(frozen=True)
class Measurement:
    """What a claim's check measured: whether the claim holds (as the theory page qualifies
    it), whether the theory page qualifies the paper's statement, the ``measured`` record and the
    figure's panels (side by side unless ``ncols`` says otherwise)."""

    holds: bool | np.bool_
    qualified: bool | np.bool_
    measured: dict[str, Any]
    panels: Sequence[Panel]
    ncols: int | None = None


@dataclass(frozen=True)
class ClaimInfo:
    """What a claim's declaration says, known without running its check.

    Attributes
    ----------
    id, name : str
        The short id (``rm-3``) and the name that states the claim; either selects it.
    paper, title, theory_ref : str
        As in :class:`Claim`.
    """

    id: str
    name: str
    paper: str
    title: str
    theory_ref: str


REGISTRY: dict[str, list[Callable[[], Claim]]] = {}
"""Every claim, by paper, in the order the modules define them (:func:`claim` fills it)."""

DECLARED: dict[str, ClaimInfo] = {}
"""Every claim's declaration by id, known without running it."""

_NAME = re.compile(r"[a-z][a-z0-9]*(_[a-z0-9]+)*")


def claim(
    cid: str, paper: str, title: str, statement: str, theory_ref: str, *, name: str
) -> Callable[[Callable[[], Measurement]], Callable[[], Claim]]:
    """Declare a claim: its id, paper, title, the paper's statement, the references that
    state or qualify it and the name that states it, ahead of the check that measures it.

    The decorated function returns a :class:`Measurement`; calling the registered function
    returns the :class:`Claim`, its verdict computed by :func:`verdict` and its figure titled
    ``"<name> (<id>): <title>"``. A name that is not snake_case, or an id or name declared
    twice, raises ``ValueError`` when the module is imported.
    """
    if not _NAME.fullmatch(name):
        raise ValueError(f"claim {cid}: name {name!r} is not snake_case")
    taken = {c.name for c in DECLARED.values()} | set(PAPERS) | {"all"}
    if cid in DECLARED or name in taken:
        raise ValueError(f"claim {cid}: its id or its name {name!r} is already taken")

    def register(check: Callable[[], Measurement]) -> Callable[[], Claim]:
        @functools.wraps(check)
        def run() -> Claim:
            got = check()
            figure = FigureSpec(
                panels=tuple(got.panels),
                ncols=len(got.panels) if got.ncols is None else got.ncols,
                title=f"{name} ({cid}): {title}",
            )
            found = verdict(bool(got.holds), bool(got.qualified), paper)
            return Claim(
                cid, paper, title, statement, theory_ref, found, got.measured, figure, name=name
            )

        REGISTRY.setdefault(paper, []).append(run)
        DECLARED[cid] = ClaimInfo(cid, name, paper, title, theory_ref)
        return run

    return register


def claim_id(selector: str) -> str:
    """The id of the claim that ``selector`` names: its name or its id.

    Raises
    ------
    ParameterError
        For a selector that is neither; the message lists every name with its id, in one line.
    """
    if selector in DECLARED:
        return selector
    for c in DECLARED.values():
        if c.name == selector:
            return c.id
    papers = list(PAPERS)
    in_order = sorted(DECLARED.values(), key=lambda c: papers.index(c.paper))
    allowed = ", ".join(f"{c.name} ({c.id})" for c in in_order)
    raise ParameterError(f"claim {selector!r} is not declared (allowed: {allowed})")


def verdict(holds: bool, qualified: bool, paper: str = "") -> str:
    """The verdict from a measurement: whether the claim holds (as the theory page qualifies
    it), and whether the theory page qualifies the paper's statement. For an observation
    (``paper`` :data:`OBSERVATIONS`): whether tumble explains it at least qualitatively, and
    whether only qualitatively (outside the record's band of agreement)."""
    if paper == OBSERVATIONS:
        if not holds:
            return DISAGREES
        return EXPLAINS if qualified else AGREES
    if not holds:
        return REFUTED
    return QUALIFIED if qualified else CONFIRMED
