"""The physical and astronomical constants the compiled code and :mod:`tumble.space` share,
defined once (this module loads nothing but Python)."""

from __future__ import annotations

import itertools
import math

__all__ = [
    "ATMOSPHERE_BANDS",
    "AU",
    "EARTH_RADIUS",
    "EXPONENTIAL_ATMOSPHERE",
    "J2000",
    "SOLAR_FLUX",
    "SPEED_OF_LIGHT",
    "SUN_RADIUS",
]

EARTH_RADIUS = 6378137.0
"""The Earth's equatorial radius [m] (WGS-84): the field's reference, the orbit's altitude, the
radius of the Earth's shadow."""
AU = 149_597_870_700.0
"""The astronomical unit [m] (IAU 2012, Resolution B2)."""
SOLAR_FLUX = 1361.0
"""The total solar irradiance at 1 AU [W/m²] (IAU 2015, Resolution B3, nominal value)."""
SUN_RADIUS = 695_700_000.0
"""The nominal solar radius [m] (IAU 2015, Resolution B3)."""
SPEED_OF_LIGHT = 299_792_458.0
"""[m/s], exact."""
J2000 = 2451545.0
"""The Julian date of J2000.0 (2000 January 1, 12 h TT)."""

EXPONENTIAL_ATMOSPHERE: tuple[tuple[float, float, float], ...] = (
    # base altitude [km], nominal density [kg/m³], scale height [km]
    (0.0, 1.225, 7.249), (25.0, 3.899e-2, 6.349), (30.0, 1.774e-2, 6.682),
    (40.0, 3.972e-3, 7.554), (50.0, 1.057e-3, 8.382), (60.0, 3.206e-4, 7.714),
    (70.0, 8.770e-5, 6.549), (80.0, 1.905e-5, 5.799), (90.0, 3.396e-6, 5.382),
    (100.0, 5.297e-7, 5.877), (110.0, 9.661e-8, 7.263), (120.0, 2.438e-8, 9.473),
    (130.0, 8.484e-9, 12.636), (140.0, 3.845e-9, 16.149), (150.0, 2.070e-9, 22.523),
    (180.0, 5.464e-10, 29.740), (200.0, 2.789e-10, 37.105), (250.0, 7.248e-11, 45.546),
    (300.0, 2.418e-11, 53.628), (350.0, 9.518e-12, 53.298), (400.0, 3.725e-12, 58.515),
    (450.0, 1.585e-12, 60.828), (500.0, 6.967e-13, 63.822), (600.0, 1.454e-13, 71.835),
    (700.0, 3.614e-14, 88.667), (800.0, 1.170e-14, 124.64), (900.0, 5.245e-15, 181.05),
    (1000.0, 3.019e-15, 268.00),
)  # fmt: skip
"""The piecewise exponential atmosphere of Vallado (*Fundamentals of Astrodynamics and
Applications*, 4th ed., 2013, table 8-4): from each base altitude up to the next,
ρ = ρ0 exp(−(h − h0)/H)."""


def _continuous(
    table: tuple[tuple[float, float, float], ...],
) -> tuple[tuple[float, float, float], ...]:
    """The bands of ``table`` with each scale height the one that reaches the next band's
    density at its base, H = (h1 − h0)/ln(ρ0/ρ1); the last band's as tabulated."""
    bands = [
        (h0, rho0, (h1 - h0) / math.log(rho0 / rho1))
        for (h0, rho0, _), (h1, rho1, _) in itertools.pairwise(table)
    ]
    return (*bands, table[-1])


ATMOSPHERE_BANDS = _continuous(EXPONENTIAL_ATMOSPHERE)
"""The exponential atmosphere tumble evaluates: Vallado's base altitudes [km] and densities
[kg/m³], each scale height [km] the one that makes ρ continuous at the next base. Vallado's
printed scale heights are these rounded (within 0.05 % at 25 km, 3e-5 above); with them as
printed ρ jumps by up to 1e-4 at a base, which a circular orbit at a round altitude (500 km
is a base) would see as noise in its orbit average."""
