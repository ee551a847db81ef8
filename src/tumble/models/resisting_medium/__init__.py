"""Fast-spinning symmetric gyroscope under a constant body-fixed moment in a resisting medium.

A. V. Medvedev, *Motion of a fast-spinning gyroscope under a constant moment in a resisting
medium* (1987). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/resisting-medium.md``, which states where tumble departs from the printed paper
and why (corrections E1–E10).

Everything here is in the paper's normalized variables (1.3): time τ, angular momentum
``k = |K|/K0``, inertia ``I1 = 1``, ``I3 = 1 + κ``, moment ``ε m`` with
``m = a − b w − s (w ∘ |w|)``, body angular velocity ``w = (p, q, r)``. Angles follow §2:
ρ, σ locate K in the inertial frame; ψ, ϑ, φ are the 3-1-3 Euler angles of the body in the
K-frame. The averaged system and its closed forms are written in the slow time ``s = ε τ``
internally and take τ at the interface.

A model package (:mod:`tumble.models.package`): its names load from ``model`` on first use.
"""

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.resisting_medium.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
