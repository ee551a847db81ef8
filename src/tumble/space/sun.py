"""The Sun seen from the Earth, and the Earth's shadow: what sunlight on an orbiting body needs.

* :func:`sun_direction`: the unit vector from the Earth to the Sun and its distance, by the
  low-precision solar coordinates of the *Astronomical Almanac* (section C, "Low precision
  formulas for the Sun"; 0.01° between 1950 and 2050), in the mean equator and equinox of
  date. tumble's inertial axes are those of the epoch (the frame of an SGP4 orbit, theory of
  the orbiting body §12): over a run of years the difference, the precession of the equinox,
  is 0.014° a year, below the formula's own accuracy for a decade.
* :func:`shadow`: the fraction of the Sun's disc seen from a point near the Earth: the
  cylindrical shadow (0 or 1) or the conical one, umbra and penumbra, with the Sun and the
  Earth as spheres (Montenbruck and Gill, *Satellite Orbits*, Springer 2000, §3.4.2);
* :func:`eclipse_fraction`: the fraction of a circular orbit spent in the cylindrical shadow,
  from the Sun's elevation β above the orbit's plane: what sunlight averaged over an orbit
  is weighted by.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.space.orbit import EARTH_RADIUS  # the radius of the shadow's cylinder and cone

__all__ = [
    "AU",
    "J2000",
    "SOLAR_FLUX",
    "SUN_RADIUS",
    "eclipse_fraction",
    "shadow",
    "sun_direction",
]

AU = 149_597_870_700.0
"""The astronomical unit [m] (IAU 2012, Resolution B2)."""
SOLAR_FLUX = 1361.0
"""The total solar irradiance at 1 AU [W/m²] (IAU 2015, Resolution B3, nominal value)."""
SUN_RADIUS = 695_700_000.0
"""The nominal solar radius [m] (IAU 2015, Resolution B3)."""
J2000 = 2451545.0
"""The Julian date of J2000.0 (2000 January 1, 12 h TT)."""

SHADOWS = ("cylindrical", "conical")


def sun_direction(jd: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The unit vector from the Earth to the Sun and the distance, at Julian dates ``jd``.

    Parameters
    ----------
    jd : array_like
        Julian dates (UT or TT: the 69 s between them move the Sun by 0.0008°).

    Returns
    -------
    direction : ndarray, shape (..., 3)
        Unit vectors, mean equator and equinox of date [1].
    distance : ndarray
        The Earth–Sun distance [m].

    Notes
    -----
    With n = jd − 2451545.0 days, the mean longitude L = 280.460° + 0.9856474° n and the mean
    anomaly g = 357.528° + 0.9856003° n, the ecliptic longitude is
    λ = L + 1.915° sin g + 0.020° sin 2g, the obliquity ε = 23.439° − 0.0000004° n and the
    distance R = 1.00014 − 0.01671 cos g − 0.00014 cos 2g [AU]; the direction is
    (cos λ, cos ε sin λ, sin ε sin λ).
    """
    n = np.asarray(jd, dtype=float) - J2000
    mean_longitude = np.radians(280.460 + 0.9856474 * n)
    g = np.radians(357.528 + 0.9856003 * n)
    longitude = mean_longitude + np.radians(1.915 * np.sin(g) + 0.020 * np.sin(2.0 * g))
    obliquity = np.radians(23.439 - 0.0000004 * n)
    direction = np.stack(
        [
            np.cos(longitude),
            np.cos(obliquity) * np.sin(longitude),
            np.sin(obliquity) * np.sin(longitude),
        ],
        axis=-1,
    )
    distance = (1.00014 - 0.01671 * np.cos(g) - 0.00014 * np.cos(2.0 * g)) * AU
    return direction, distance


def shadow(
    position: ArrayLike, sun: ArrayLike, sun_distance: ArrayLike, model: str = "conical"
) -> FloatArray:
    """The fraction of the Sun's disc seen from ``position`` (1 in sunlight, 0 in the umbra).

    Parameters
    ----------
    position : array_like, shape (..., 3)
        The body's place, from the Earth's centre [m], in the axes of ``sun``.
    sun : array_like, shape (..., 3)
        Unit vector from the Earth to the Sun.
    sun_distance : array_like
        The Earth–Sun distance [m].
    model : {"conical", "cylindrical"}
        The conical shadow (umbra and penumbra: the overlap of the two discs, Montenbruck and
        Gill §3.4.2), or the cylinder of the Earth's radius behind it along ``sun``.

    Returns
    -------
    ndarray
        The visible fraction of the Sun, in [0, 1].
    """
    if model not in SHADOWS:
        raise ParameterError(f"shadow = {model!r} must be one of {', '.join(SHADOWS)}")
    r = np.asarray(position, dtype=float)
    s = np.asarray(sun, dtype=float)
    along = np.sum(r * s, axis=-1)
    if model == "cylindrical":
        across = np.linalg.norm(r - along[..., None] * s, axis=-1)
        return np.where((along < 0.0) & (across < EARTH_RADIUS), 0.0, 1.0)
    d = np.asarray(sun_distance, dtype=float)[..., None] * s - r  # body → Sun
    dist_sun = np.linalg.norm(d, axis=-1)
    dist_earth = np.linalg.norm(r, axis=-1)
    a = np.arcsin(np.clip(SUN_RADIUS / dist_sun, -1.0, 1.0))  # apparent radii
    b = np.arcsin(np.clip(EARTH_RADIUS / dist_earth, -1.0, 1.0))
    cos_c = -np.sum(r * d, axis=-1) / (dist_earth * dist_sun)
    c = np.arccos(np.clip(cos_c, -1.0, 1.0))  # apart
    full = c >= a + b
    umbra = c <= b - a
    x = (c * c + a * a - b * b) / (2.0 * c + (c == 0.0))
    y = np.sqrt(np.clip(a * a - x * x, 0.0, None))
    overlap = (
        a * a * np.arccos(np.clip(x / a, -1.0, 1.0))
        + b * b * np.arccos(np.clip((c - x) / b, -1.0, 1.0))
        - c * y
    )
    partial = 1.0 - overlap / (math.pi * a * a)
    annular = 1.0 - (b * b) / (a * a)  # the Earth's disc inside the Sun's
    inside = c <= a - b
    return np.where(full, 1.0, np.where(umbra, 0.0, np.where(inside, annular, partial)))


def eclipse_fraction(radius: ArrayLike, beta: ArrayLike) -> FloatArray:
    """The fraction of a circular orbit of ``radius`` [m] spent in the Earth's cylindrical
    shadow, the Sun at the elevation ``beta`` [rad] above the orbit's plane.

    Notes
    -----
    At the angle u from the Sun's projection on the plane the body is at a cos β cos u along
    the Sun and a (1 − cos²β cos²u)^½ from the shadow's axis: it is in shadow where cos u < 0
    and cos² u > (1 − R²/a²)/cos² β, so that the fraction is arccos(c*)/π with
    c* = (1 − R²/a²)^½ / cos β, and 0 where c* ≥ 1 (the Sun beyond the critical elevation).
    """
    a = np.asarray(radius, dtype=float)
    cos_beta = np.abs(np.cos(np.asarray(beta, dtype=float)))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.sqrt(np.clip(1.0 - (EARTH_RADIUS / a) ** 2, 0.0, None)) / cos_beta
    return np.where(c < 1.0, np.arccos(np.clip(c, -1.0, 1.0)) / math.pi, 0.0)
