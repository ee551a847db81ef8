"""The papers' claims, each run and checked as tumble's theory pages state and qualify it.

One function per claim (``rm_1`` … in :mod:`~tumble.analysis.claims.resisting_medium`,
``rf_1`` … in :mod:`~tumble.analysis.claims.rotating_field`, ``nm_1`` … in
:mod:`~tumble.analysis.claims.nonlinear_moment`) returns a :class:`Claim`: the paper's
statement with its equation numbers, the theory sections that qualify it, one measured figure
against a justified threshold, the verdict computed from it, and its figure as a
:class:`FigureSpec` (drawn by :func:`tumble.plot.claim_figure`). Beside the papers, the set
``observations`` (``obs_1`` … in :mod:`~tumble.analysis.claims.observations`) checks published
observations of objects in orbit the same way, with the verdicts agrees, explains qualitatively
or does not agree. Importing this package runs nothing; call the functions of :data:`CLAIMS`.

Each claim also has a name that states it (``rotation_about_middle_axis_is_unstable``), declared
in its registration beside its id (``rf-6``), which stays as the name's short alias;
:func:`~tumble.analysis.claims.base.claim_id` finds a claim by either.

References
----------
A. V. Medvedev (1987), Yu. G. Martynenko (1979) and V. M. Serov (1991); the theory pages
docs/theory/resisting-medium.md, rotating-field.md and nonlinear-moment.md state where tumble
departs from each printed paper and why.
"""

from __future__ import annotations

from collections.abc import Callable

# Importing the paper modules registers their claims.
from tumble.analysis.claims import nonlinear_moment as nonlinear_moment
from tumble.analysis.claims import observations as observations
from tumble.analysis.claims import resisting_medium as resisting_medium
from tumble.analysis.claims import rotating_field as rotating_field
from tumble.analysis.claims.base import (
    AGREES,
    CONFIRMED,
    DISAGREES,
    EXPLAINS,
    PAPERS,
    QUALIFIED,
    REFUTED,
    REGISTRY,
    VERDICTS,
    Claim,
    FigureSpec,
    Panel,
    Series,
    plain,
    verdict,
)

__all__ = [
    "AGREES",
    "CLAIMS",
    "CONFIRMED",
    "DISAGREES",
    "EXPLAINS",
    "PAPERS",
    "QUALIFIED",
    "REFUTED",
    "VERDICTS",
    "Claim",
    "FigureSpec",
    "Panel",
    "Series",
    "plain",
    "verdict",
]

CLAIMS: dict[str, tuple[Callable[[], Claim], ...]] = {
    paper: tuple(REGISTRY[paper]) for paper in PAPERS
}
"""Every claim, by paper, in the order of the papers' text (registered by
:func:`~tumble.analysis.claims.base.claim` where each is defined)."""
