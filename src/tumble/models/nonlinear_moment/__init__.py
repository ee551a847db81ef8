"""Symmetric body under the nonlinear moment M0(θ) = A(a·sinθ + b·sin2θ): full motion, the
exact unperturbed motion, and Volosov's averaged equations for the nutation envelope.

V. M. Serov, *Rotational motion of a dynamically symmetric rigid body under the action of a
nonlinear moment* (1991). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/nonlinear-moment.md``, which states where tumble departs from the printed paper and
why (corrections S1–S16 of its §12: A is the equatorial moment; β, τ0, γ0, χ±, λ±, L± and the
coefficient of L±).

Variables (§1): time t in the unit of the coefficients (a, b [1/t²], R, G [1/t]),
μ = C/A, classical z–x–z Euler angles ψ, θ, φ of the body relative to the fixed axis e_z (for
an entry vehicle the velocity direction, θ the total angle of attack), R = μr and G = K·e_z/A
the reduced angular momenta. The perturbation of §9 (the entry capsule) has slow time τ = εt:
a = a0·Q(τ), b = b0·Q(τ) with the dynamic-pressure profile Q, pitch damping εd and roll
damping εν.

The averaged method integrates (2.2)–(2.3) for the slow variables: the energy H (form
``"energy"``, the better-conditioned one of §7) or the turning point θext (form
``"theta_max"``/``"theta_min"``, the paper's (2.2)), together with z = (R, G, a, b). The
averages come from the closed forms of §8 (⟨u⟩, ⟨u²⟩ by K, E, Π) for the built-in
perturbation, and from adaptive quadrature over the nutation period for any perturbation
given as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`).

A model package (:mod:`tumble.models.package`): its names load from ``model`` on first use.
"""

from typing import TYPE_CHECKING

from tumble.models.package import model_exports

if TYPE_CHECKING:
    from tumble.models.nonlinear_moment.model import *  # noqa: F403

__getattr__, __dir__ = model_exports(__name__)
