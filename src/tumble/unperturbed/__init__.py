"""Exact unperturbed motions: plain numerics (numpy, scipy) below the models.

* :mod:`~tumble.unperturbed.elliptic`: Legendre elliptic integrals of the third kind for any
  amplitude (Carlson's forms), and the Jacobi functions of the closed forms.
* :mod:`~tumble.unperturbed.euler_poinsot`: the torque-free rigid body (3.1) of
  the rotating-field paper (docs/theory/rotating-field.md §8), its averages and fast
  frequencies.
* :mod:`~tumble.unperturbed.symmetric_body`: the symmetric body under the moment
  A(a·sinθ + b·sin2θ), (1.9)–(1.13) of the nonlinear-moment paper, and its period averages
  (docs/theory/nonlinear-moment.md §8).
"""

from tumble.unperturbed.elliptic import ellippi, ellippi_inc
from tumble.unperturbed.euler_poinsot import (
    ENERGY_RTOL,
    SEPARATRIX_RTOL,
    EulerPoinsot,
    Regime,
    energy_from_modulus,
    fast_frequencies,
    fast_frequencies_of_states,
    mean_square_rate,
    modulus_squared,
    modulus_squared_of_ratio,
    modulus_squared_of_states,
    proper_sorting,
    reached_ratio,
    regime,
)
from tumble.unperturbed.symmetric_body import (
    SEPARATRIX_TOL,
    NutationOrbit,
    effective_potential,
    energy,
    potential_slope,
    quartic_coefficients,
)

__all__ = [
    "ENERGY_RTOL",
    "SEPARATRIX_RTOL",
    "SEPARATRIX_TOL",
    "EulerPoinsot",
    "NutationOrbit",
    "Regime",
    "effective_potential",
    "ellippi",
    "ellippi_inc",
    "energy",
    "energy_from_modulus",
    "fast_frequencies",
    "fast_frequencies_of_states",
    "mean_square_rate",
    "modulus_squared",
    "modulus_squared_of_ratio",
    "modulus_squared_of_states",
    "potential_slope",
    "proper_sorting",
    "quartic_coefficients",
    "reached_ratio",
    "regime",
]
