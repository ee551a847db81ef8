"""Triaxial conducting body in a rotating magnetic field: eddy-current torque, stability of the
stationary rotation, and the averaged transient.

Yu. G. Martynenko, *On the stability of stationary rotations of a rigid body in a magnetic
field* (1979). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/rotating-field.md``, which states where tumble departs from the printed paper and
why (corrections C1–C7 of its §14: the Γ′ equation of (1.5) and the middle term of (3.6) among
them).

Variables (§2, §4): time τ = ωt, body angular velocity z = Ω/ω, ε = M0/ω with M0 = k_f H²
(in the units of the moments of inertia), Γ the body → field-frame rotation (v_η = Γ v_x). The
full model keeps the user's axis labels (the stationary rotation is about body axis x3). The
averaged transient (§§8–10) needs I1 < I2 < I3: it relabels the axes internally by a proper
permutation, and its outputs (L, ρ, σ, T, k²) do not depend on the labels. ``regime = "x3"``
means the angular momentum encircles the axis of the largest moment, ``"x1"`` the smallest.

A model package (:mod:`tumble.models.package`): its names load from ``model`` on first use.
"""

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.rotating_field.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
