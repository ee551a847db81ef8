"""Symmetric rigid body under the moment M0(θ) = A(a sinθ + b sin2θ): exact unperturbed motion.

V. M. Serov (1991), eqs. (1.1)–(1.13), with the misprints of the printed paper corrected. A is
the equatorial and C the axial moment of inertia, μ = C/A ∈ (0, 2]; R = μr and G = K·e_z/A are
the reduced angular momenta, constant with E = θ'²/2 + W(θ) (1.6). Time is the paper's t, in
any unit consistent with a, b [1/time²] and R, G [1/time].

Representation
--------------
With u = cosθ, u'² = f(u) = 2b(u − u1)(u − u2)(u − u3)(u − u4) (1.7) and the motion lives
on [u2, u1] (u1 = cos θmin). Every closed form here uses one *chart* of (1.9): a turning point
A_* (the anchor, γ = 0), the other one B_* and the pole root P of §4.1, written as the weighted
mean

    u = (A_* (1 − σ) + B_* ν σ) / ((1 − σ) + ν σ),   ν = (P − A_*)/(P − B_*) > 0,

with σ = sin²γ (case 1, δ = 1) or σ = sin²(γ/2) (case 2, δ = ½, ν = ξ of §4.2). This is (1.9)
with L = P, M = A_* − P, N = ν − 1, rewritten so that nothing is infinite when P is (b = 0,
§4.3) or when ξ = 1 (§4.2): a huge or infinite pole root only makes ν → 1. Case 1 uses the
paper's anchoring (A_* = u2, θmax at γ = 0, σ = −1 in (1.10)) for the motion and, for each pole
ρ = ±1 of (1.12), the anchoring whose anchor is the turning point farther from ρ (the
alternative anchoring of §4.3 is the paper's at βt + τ0 + K). Case 2 anchors at u1 (θmin,
σ = +1, corrections S4).

Partial fractions are taken about the anchor instead of about L (§5):

    1/(u − ρ) = 1/(A_* − ρ) + ν(A_* − B_*)/(A_* − ρ)² · σ/(1 + (r − 1)σ),  r = ν(B_* − ρ)/(A_* − ρ),

and ∫ σ/(1 + wσ) dγ/Δ = S(γ, w) = (1/3) sin³γ R_J(cos²γ, Δ², 1, 1 + w sin²γ), i.e.
(F − Π(γ, w, k))/w without the 0/0 at w = 0. No 1/(1 ± L) appears, so a pole root P close to
±1 (§11) needs no special treatment and the term (G ∓ R)/(1 ∓ u) stays finite for G → ±R.
In case 2 the same algebra gives (1.13) with the corrected χ±, ϰ±, λ± and L±(γ) of corrections
S7–S9 in a form that is finite at ξ = 1 and at 1 ± L = 0.

Roots and conditioning
----------------------
f is expanded about the initial u0 = cosθ0 with its constant term sin²θ0·θ0'² exact, the
turning points are bracketed on monotone pieces of f (between its critical points, so the
physical interval of a double well is the one containing u0, §3) and refined by bisection;
for turning points near ±1, 1 − u1 and 1 + u2 are computed again from the expansion about
u = ±1, where f(±1) = −(G ∓ R)² is exact, and the value with the smaller error bound is kept,
so that they keep their digits for θ near 0 or π. The other two roots
come from deflation (stable quadratic formula; a root at infinity for b = 0 is carried as
2b·root). The root case is 2 when the discriminant of the deflated quadratic is negative
beyond round-off (§14). Both forms agree where the case switches.

For ordinary orbits a fast path finds the same turning points by safeguarded Newton
iterations and certifies them by that deflation (section "Fast path" below); wherever its
checks fail the bracketing above decides. The Jacobi phase data of t = 0, needed by ψ(t)
and φ(t) only, are computed on first use.

Modules: :mod:`~.potential` (W, the energy, f), :mod:`~.quartic` (its roots, both routes),
:mod:`~.carlson` (the integrals), :mod:`~.charts` (turning points, charts, poles),
:mod:`~.build` (from a state or an energy to an orbit), :mod:`~.orbit` (the motion) and
:mod:`~.means` (period averages).

Jacobi functions come from :func:`tumble.unperturbed.elliptic._jacobi` (reduction to a
quarter period with Newton polishing), accurate up to the separatrix; incomplete integrals use
the quasi-periodic reduction of §5.

Limits of the data: see :data:`SEPARATRIX_TOL`, which refuses 1 − k² below 1e-9.
"""

from tumble.kernels.codes import NUTATION_SEPARATRIX_TOL as SEPARATRIX_TOL
from tumble.unperturbed.symmetric_body.orbit import NutationOrbit
from tumble.unperturbed.symmetric_body.potential import (
    effective_potential,
    energy,
    potential_slope,
    quartic_coefficients,
)

__all__ = [
    "SEPARATRIX_TOL",
    "NutationOrbit",
    "effective_potential",
    "energy",
    "potential_slope",
    "quartic_coefficients",
]
