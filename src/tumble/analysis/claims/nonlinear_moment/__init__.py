"""Claims of V. M. Serov (1991) on a body under a nonlinear moment (model ``nonlinear_moment``).

One function per claim, :func:`nm_1` … :func:`nm_11`, in the order of the paper. Each runs its
check with tumble's public API and returns a :class:`~tumble.analysis.claims.base.Claim`: the
paper's statement with its equation numbers, the sections of the theory page that qualify it, one
measured figure against a threshold justified in a comment, the verdict computed from it, and the
figure as a :class:`~tumble.analysis.claims.base.FigureSpec`. Time is the paper's t (slow time
τ = εt), angles are radians (degrees only in figures). Parameters are the §13 test
cases, tumble's example scenarios and its illustrative Soyuz-class capsule; none is tuned
toward an expected number.

The claims live in modules grouped by what they check,
:mod:`~tumble.analysis.claims.nonlinear_moment.cases` holding the cases they share:

* :mod:`~tumble.analysis.claims.nonlinear_moment.unperturbed` (nm-1 … nm-4): the unperturbed motion
  in closed form;
* :mod:`~tumble.analysis.claims.nonlinear_moment.averaged` (nm-5, nm-6): the averaged equations
  and their elliptic averages;
* :mod:`~tumble.analysis.claims.nonlinear_moment.envelope` (nm-7, nm-8): the accuracy of the
  averaged envelope;
* :mod:`~tumble.analysis.claims.nonlinear_moment.applications` (nm-9 … nm-11): the paper's
  applications.

References
----------
V. M. Serov (1991); sections (§) and corrections (S1–S16) are those of
docs/theory/nonlinear-moment.md.
"""

from __future__ import annotations

# The modules are imported in the order of the paper: importing one registers its claims,
# and the registry keeps that order (its tests and the claims page check it).
# isort: off
from tumble.analysis.claims.nonlinear_moment.cases import NM
from tumble.analysis.claims.nonlinear_moment.unperturbed import nm_1, nm_2, nm_3, nm_4
from tumble.analysis.claims.nonlinear_moment.averaged import nm_5, nm_6
from tumble.analysis.claims.nonlinear_moment.envelope import nm_7, nm_8
from tumble.analysis.claims.nonlinear_moment.applications import nm_9, nm_10, nm_11
# isort: on

__all__ = [
    "NM",
    "nm_1",
    "nm_2",
    "nm_3",
    "nm_4",
    "nm_5",
    "nm_6",
    "nm_7",
    "nm_8",
    "nm_9",
    "nm_10",
    "nm_11",
]
