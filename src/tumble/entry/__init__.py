"""Uncontrolled entry capsules: atmosphere, Newtonian aerodynamics and ballistic descent.

The application of docs/theory/nonlinear-moment.md §9–§10: a segmental-conical capsule whose
restoring moment M0(θ) = A(a sinθ + b sin2θ) (1.5) is fitted from modified-Newtonian aerodynamics,
with a and b following the dynamic pressure q(t) of a ballistic descent through the standard
atmosphere. Plain numerics (numpy, scipy, ambiance); from tumble it imports only its errors and type
aliases.

Typical use::

    import math
    from tumble.entry import SOYUZ_CLASS, descend, fit_moment, restoring_coefficients

    fit = fit_moment(SOYUZ_CLASS)                       # Cm ≈ c1 sinα + c2 sin2α
    d = descend(SOYUZ_CLASS, 7600.0, math.radians(-2.0), 100e3)
    a, b = restoring_coefficients(SOYUZ_CLASS, d.q_peak, fit)   # [1/s²] at peak q
"""

from tumble.entry.aerodynamics import (
    CP_MAX_HYPERSONIC,
    SOYUZ_CLASS,
    AeroCoefficients,
    Capsule,
    MomentFit,
    Trim,
    coefficients,
    cp_max,
    fit_moment,
    restoring_coefficients,
    trim_angles,
)
from tumble.entry.atmosphere import (
    STANDARD,
    AtmosphereModel,
    ExponentialAtmosphere,
    StandardAtmosphere,
    density,
    density_gradient,
    pressure,
    speed_of_sound,
    temperature,
)
from tumble.entry.descent import MU_EARTH, R_EARTH, Descent, descend

__all__ = [
    "CP_MAX_HYPERSONIC",
    "MU_EARTH",
    "R_EARTH",
    "SOYUZ_CLASS",
    "STANDARD",
    "AeroCoefficients",
    "AtmosphereModel",
    "Capsule",
    "Descent",
    "ExponentialAtmosphere",
    "MomentFit",
    "StandardAtmosphere",
    "Trim",
    "coefficients",
    "cp_max",
    "density",
    "density_gradient",
    "descend",
    "fit_moment",
    "pressure",
    "restoring_coefficients",
    "speed_of_sound",
    "temperature",
    "trim_angles",
]
