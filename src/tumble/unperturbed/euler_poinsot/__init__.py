"""Euler–Poinsot motion: the torque-free rigid body in Jacobi elliptic functions, eq. (3.1).

Yu. G. Martynenko (1979); docs/theory/rotating-field.md §8, with its correction C7 (§14) for
regime x1. Time is the paper's τ and z the body
angular velocity, in any consistent units: every rate below is in rad per unit of τ.

Conventions
-----------
* Moments sorted I1 ≤ I2 ≤ I3 ("sorted axes"). Bodies given in another order are relabelled
  by a *proper* signed permutation of axes (a cyclic one, or a transposition with the first
  sorted axis reversed), so that attitudes stay rotations; results come back in the user's
  axes.
* With d1 = L² − 2T·I1 ≥ 0, d2 = L² − 2T·I2, d3 = 2T·I3 − L² ≥ 0 the regime is
  ``"x3"`` (d2 > 0, polhode around x3), ``"x1"`` (d2 < 0, around x1) or ``"separatrix"``
  when |d2| ≤ :data:`SEPARATRIX_RTOL`·L²; ``"symmetric"`` when I1 = I2 or I2 = I3 and
  ``"sphere"`` when I1 = I3 (equal to :data:`DEGENERATE_RTOL`); ``"rest"`` when L = 0.
* k2 is the modulus squared of the current regime (x3 formula of §8, or the 1↔3-swapped
  one, correction C7), so 0 ≤ k2 ≤ 1; k2 = 1 on the separatrix and 0 for symmetric bodies.
* Separatrix band. Labels and summary numbers take their separatrix values there
  (k2 = 1, period = inf, ν1 = 0, ν2 = L/I2), but the averages and frequencies of the
  module functions use the actual k'² = 1 − k² (they are continuous, with a logarithmic
  approach), and :class:`EulerPoinsot` follows the state itself: the periodic solution of
  its own k'² when L² ≠ 2T·I2 in floating point, the asymptotic one ((3.1) with m = 1)
  when L² = 2T·I2 exactly. Jacobi functions stay accurate for any k'² > 0 (see
  :func:`tumble.unperturbed.elliptic._jacobi`).
* Orientation (§8, "Frequencies of the fast motion"): 3-1-3 Euler angles of the body
  relative to a frame whose third axis is along L, ``body → L-frame = Rz(ψ) Rx(θ) Rz(φ) · P``
  with P a proper signed permutation that puts the polar axis of the polhode third (x3 in
  regime x3; (x2, x3, x1) in regime x1). Then the body components of L are
  L(sin θ sin φ, sin θ cos φ, cos θ), and ψ̇ = L(2T − I_c z_c²)/(L² − I_c² z_c²).

Modules: :mod:`~.regimes` (the regime, modulus, period averages and fast frequencies of a
pair (L, T): scalars, called at every step of the averaged models) and :mod:`~.motion` (the
motion itself, :class:`EulerPoinsot`).
"""

from tumble.bodies import proper_sorting
from tumble.kernels.codes import DEGENERATE_RTOL, SEPARATRIX_RTOL
from tumble.unperturbed.euler_poinsot.motion import EulerPoinsot
from tumble.unperturbed.euler_poinsot.regimes import (
    ENERGY_RTOL,
    Regime,
    energy_from_modulus,
    fast_frequencies,
    fast_frequencies_of_states,
    mean_square_rate,
    modulus_squared,
    modulus_squared_of_ratio,
    modulus_squared_of_states,
    polhode_point,
    reached_ratio,
    regime,
)

__all__ = [
    "DEGENERATE_RTOL",
    "ENERGY_RTOL",
    "SEPARATRIX_RTOL",
    "EulerPoinsot",
    "Regime",
    "energy_from_modulus",
    "fast_frequencies",
    "fast_frequencies_of_states",
    "mean_square_rate",
    "modulus_squared",
    "modulus_squared_of_ratio",
    "modulus_squared_of_states",
    "polhode_point",
    "proper_sorting",
    "reached_ratio",
    "regime",
]
