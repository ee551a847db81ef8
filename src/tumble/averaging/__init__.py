"""Averaging any torque over the unperturbed motion: plain numerics below the models.

* :mod:`~tumble.averaging.quadrature`: adaptive periodic trapezoidal means over fast phases.
* :mod:`~tumble.averaging.spinner`: the fast symmetric spinner of the resisting-medium paper
  (slow k, ρ, σ, ϑ; averaged over ψ and φ).
* :mod:`~tumble.averaging.triaxial`: the triaxial body of the rotating-field paper (slow L_ξ, T;
  averaged over the polhode, the precession about L and a periodic forcing), with
  :mod:`~tumble.averaging.triaxial_grid` (the states of its grid and a torque on them) and
  :mod:`~tumble.averaging.triaxial_resonance` (its fast frequencies and nearest resonance).
* :mod:`~tumble.averaging.nutation`: Volosov averaging over the nutation of the nonlinear-moment
  paper.
* :mod:`~tumble.averaging.generator`: the first-order generator w₁ of the near-identity
  transformation on a torus grid (FFT), with its small divisors reported.
* :mod:`~tumble.averaging.fourier`: Fourier series of values on a uniform torus grid
  (interpolation, spectral derivatives, the resolution test).
* :mod:`~tumble.averaging.second_order`: the averaged equations to second order and the
  mean ↔ osculating map for any fast system, with
  :mod:`~tumble.averaging.resonance_widths` (the distance of its phases from a resonance).
* :mod:`~tumble.averaging.crossing`: a triaxial body crossing the separatrix of the free
  motion: the probability of each rotation it passes into, and where a full or an averaged
  run crosses.
"""

from tumble.averaging.crossing import (
    Crossing,
    averaged_crossing,
    first_crossing,
    separatrix_crossing,
    separatrix_motion,
)
from tumble.averaging.generator import SmallDivisorError, zero_mean_antiderivative
from tumble.averaging.quadrature import AVERAGE_RTOL, AveragingError, torus_mean
from tumble.averaging.spinner import spinner_average
from tumble.averaging.triaxial import (
    branch_kernel,
    nearest_resonance,
    nearest_resonances,
    rotation_sense,
    sense_turn,
    triaxial_average,
    triaxial_average_vector,
    triaxial_kernel,
)
from tumble.averaging.triaxial_resonance import nearest_relations, precession_harmonic

__all__ = [
    "AVERAGE_RTOL",
    "AveragingError",
    "Crossing",
    "SmallDivisorError",
    "averaged_crossing",
    "branch_kernel",
    "first_crossing",
    "nearest_relations",
    "nearest_resonance",
    "nearest_resonances",
    "precession_harmonic",
    "rotation_sense",
    "sense_turn",
    "separatrix_crossing",
    "separatrix_motion",
    "spinner_average",
    "torus_mean",
    "triaxial_average",
    "triaxial_average_vector",
    "triaxial_kernel",
    "zero_mean_antiderivative",
]
