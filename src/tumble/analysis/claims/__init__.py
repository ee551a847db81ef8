"""The papers' claims, each run and checked as its spec states and qualifies it.

One function per claim (``rm_1`` … in :mod:`~tumble.analysis.claims.resisting_medium`,
``rf_1`` … in :mod:`~tumble.analysis.claims.rotating_field`, ``nm_1`` … in
:mod:`~tumble.analysis.claims.nonlinear_moment`) returns a :class:`Claim`: the paper's
statement with its equation numbers, the spec sections that qualify it, one measured figure
against a justified threshold, the verdict computed from it, and its figure as a
:class:`FigureSpec` (drawn by :func:`tumble.plot.claim_figure`). Importing this package runs
nothing; call the functions of :data:`CLAIMS`.

References
----------
spec/medvedev.md (``resisting_medium``, seed 000), spec/martynenko.md (``rotating_field``,
seed 002), spec/serov.md (``nonlinear_moment``, seed 003); each spec supersedes its seed
where they differ.
"""

from __future__ import annotations

from collections.abc import Callable

from tumble.analysis.claims import nonlinear_moment as _nm
from tumble.analysis.claims import resisting_medium as _rm
from tumble.analysis.claims import rotating_field as _rf
from tumble.analysis.claims.base import (
    CONFIRMED,
    PAPERS,
    QUALIFIED,
    REFUTED,
    VERDICTS,
    Claim,
    FigureSpec,
    Panel,
    Series,
    plain,
    verdict,
)

__all__ = [
    "CLAIMS",
    "CONFIRMED",
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
    "resisting_medium": (
        _rm.rm_1,
        _rm.rm_2,
        _rm.rm_3,
        _rm.rm_4,
        _rm.rm_5,
        _rm.rm_6,
        _rm.rm_7,
        _rm.rm_8,
        _rm.rm_9,
        _rm.rm_10,
        _rm.rm_11,
        _rm.rm_12,
        _rm.rm_13,
        _rm.rm_14,
        _rm.rm_15,
        _rm.rm_16,
    ),
    "rotating_field": (
        _rf.rf_1,
        _rf.rf_2,
        _rf.rf_3,
        _rf.rf_4,
        _rf.rf_5,
        _rf.rf_6,
        _rf.rf_7,
        _rf.rf_8,
        _rf.rf_9,
        _rf.rf_10,
        _rf.rf_11,
        _rf.rf_12,
        _rf.rf_13,
        _rf.rf_14,
        _rf.rf_15,
        _rf.rf_16,
        _rf.rf_17,
        _rf.rf_18,
    ),
    "nonlinear_moment": (
        _nm.nm_1,
        _nm.nm_2,
        _nm.nm_3,
        _nm.nm_4,
        _nm.nm_5,
        _nm.nm_6,
        _nm.nm_7,
        _nm.nm_8,
        _nm.nm_9,
        _nm.nm_10,
        _nm.nm_11,
    ),
}
"""Every claim function, by model name, in the order of the papers (``rm-1`` … ``nm-11``)."""
