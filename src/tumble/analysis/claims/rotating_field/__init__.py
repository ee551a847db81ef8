"""Claims of Yu. G. Martynenko (1979) on a body in a rotating magnetic field (``rotating_field``).

One function per claim, :func:`rf_1` … :func:`rf_18`, in the order of the paper. Each runs its
check with tumble's public API and returns a :class:`~tumble.analysis.claims.base.Claim`: the
paper's statement with its equation numbers, the sections of the theory page that qualify
it, one measured figure against a threshold justified in a comment, the verdict computed from
it, and the figure as a :class:`~tumble.analysis.claims.base.FigureSpec`. Time is the paper's
τ = ωt, angles are radians, rates are z = Ω/ω. Parameters are the test cases of §15, tumble's
example scenarios or the theory page's own counterexamples; none is tuned toward an expected
number.

The claims live in modules grouped by what they check,
:mod:`~tumble.analysis.claims.rotating_field.cases` holding the cases they share:

* :mod:`~tumble.analysis.claims.rotating_field.equations` (rf-1 … rf-4): the torque, the equations
  of motion and their linearization;
* :mod:`~tumble.analysis.claims.rotating_field.stability` (rf-5 … rf-9): the stability of the
  rotation about each axis;
* :mod:`~tumble.analysis.claims.rotating_field.averaged` (rf-10 … rf-12): the Euler–Poinsot motion
  and the averaged equations;
* :mod:`~tumble.analysis.claims.rotating_field.evolution` (rf-13 … rf-18): the evolution the
  averaged equations predict, and their accuracy.

References
----------
Yu. G. Martynenko (1979); sections (§) and corrections (C1–C7) are those of
docs/theory/rotating-field.md.
"""

from __future__ import annotations

# The modules are imported in the order of the paper: importing one registers its claims,
# and the registry keeps that order (its tests and the claims page check it).
# isort: off
from tumble.analysis.claims.rotating_field.cases import RF
from tumble.analysis.claims.rotating_field.equations import rf_1, rf_2, rf_3, rf_4
from tumble.analysis.claims.rotating_field.stability import rf_5, rf_6, rf_7, rf_8, rf_9
from tumble.analysis.claims.rotating_field.averaged import rf_10, rf_11, rf_12
from tumble.analysis.claims.rotating_field.evolution import rf_13, rf_14, rf_15, rf_16, rf_17, rf_18
# isort: on

__all__ = [
    "RF",
    "rf_1",
    "rf_2",
    "rf_3",
    "rf_4",
    "rf_5",
    "rf_6",
    "rf_7",
    "rf_8",
    "rf_9",
    "rf_10",
    "rf_11",
    "rf_12",
    "rf_13",
    "rf_14",
    "rf_15",
    "rf_16",
    "rf_17",
    "rf_18",
]
