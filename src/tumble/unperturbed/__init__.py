"""Exact unperturbed motions: plain numerics (numpy, scipy) below the models.

* :mod:`~tumble.unperturbed.elliptic`: Legendre elliptic integrals of the third kind for any
  amplitude (Carlson's forms).
* :mod:`~tumble.unperturbed.euler_poinsot`: the torque-free rigid body (3.1) of
  spec/martynenko.md §8, its averages and fast frequencies.
"""

from tumble.unperturbed.elliptic import ellippi, ellippi_inc
from tumble.unperturbed.euler_poinsot import (
    ENERGY_RTOL,
    SEPARATRIX_RTOL,
    EulerPoinsot,
    Regime,
    energy_from_modulus,
    fast_frequencies,
    mean_square_rate,
    modulus_squared,
    proper_sorting,
    regime,
)

__all__ = [
    "ENERGY_RTOL",
    "SEPARATRIX_RTOL",
    "EulerPoinsot",
    "Regime",
    "ellippi",
    "ellippi_inc",
    "energy_from_modulus",
    "fast_frequencies",
    "mean_square_rate",
    "modulus_squared",
    "proper_sorting",
    "regime",
]
