"""The physical and astronomical constants the compiled code and :mod:`tumble.space` share,
defined once (this module loads nothing but Python)."""

from __future__ import annotations

__all__ = ["AU", "EARTH_RADIUS", "J2000", "SOLAR_FLUX", "SPEED_OF_LIGHT", "SUN_RADIUS"]

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
