"""Claims of A. V. Medvedev (1987) on a body in a resisting medium (model ``resisting_medium``).

One function per claim, :func:`rm_1` … :func:`rm_16`, in the order of the paper. Each runs its
check with tumble's public API and returns a :class:`~tumble.analysis.claims.base.Claim`: the
paper's statement with its equation numbers, the sections of the theory page that qualify
it, one measured figure against a threshold justified in a comment, the verdict computed
from it, and the figure as a :class:`~tumble.analysis.claims.base.FigureSpec`. Time is the
paper's τ, angles are radians. Parameters are the test cases of §13, tumble's tests or the
theory page's own counterexamples; none is tuned toward an expected number.

The claims live in modules grouped by what they check,
:mod:`~tumble.analysis.claims.resisting_medium.cases` holding the cases they share:

* :mod:`~tumble.analysis.claims.resisting_medium.equations` (rm-1 … rm-4): the equations of motion
  and their averaged forms;
* :mod:`~tumble.analysis.claims.resisting_medium.closed_forms` (rm-5 … rm-7): the closed forms of
  the averaged system;
* :mod:`~tumble.analysis.claims.resisting_medium.limits` (rm-8 … rm-12): the paper's conclusions on
  the limiting motions;
* :mod:`~tumble.analysis.claims.resisting_medium.accuracy` (rm-13 … rm-16): the full model against
  the averaged one.

References
----------
A. V. Medvedev (1987). Sections (§) and corrections (E1–E10) are those of
docs/theory/resisting-medium.md.
"""

from __future__ import annotations

# The modules are imported in the order of the paper: importing one registers its claims,
# and the registry keeps that order (its tests and the claims page check it).
# isort: off
from tumble.analysis.claims.resisting_medium.cases import RM
from tumble.analysis.claims.resisting_medium.equations import rm_1, rm_2, rm_3, rm_4
from tumble.analysis.claims.resisting_medium.closed_forms import rm_5, rm_6, rm_7
from tumble.analysis.claims.resisting_medium.limits import rm_8, rm_9, rm_10, rm_11, rm_12
from tumble.analysis.claims.resisting_medium.accuracy import rm_13, rm_14, rm_15, rm_16
# isort: on

__all__ = [
    "RM",
    "rm_1",
    "rm_2",
    "rm_3",
    "rm_4",
    "rm_5",
    "rm_6",
    "rm_7",
    "rm_8",
    "rm_9",
    "rm_10",
    "rm_11",
    "rm_12",
    "rm_13",
    "rm_14",
    "rm_15",
    "rm_16",
]
