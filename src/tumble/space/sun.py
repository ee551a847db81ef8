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
* :func:`eclipse_fraction`: the fraction of an orbit's time spent in the cylindrical shadow,
  from the Sun's place relative to the orbit's plane and perigee: what sunlight averaged over
  an orbit is weighted by.

Each calls the compiled definition the torque terms evaluate (:mod:`tumble.kernels.sun`),
loaded on first use.
"""

from __future__ import annotations

from datetime import UTC, datetime

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.astro import AU, J2000, SOLAR_FLUX, SUN_RADIUS

__all__ = [
    "AU",
    "J2000",
    "SHADOWS",
    "SOLAR_FLUX",
    "SUN_RADIUS",
    "eclipse_fraction",
    "julian_date",
    "shadow",
    "sun_direction",
]

SHADOWS = ("cylindrical", "conical")
"""The Earth's shadow models: a cylinder of the Earth's radius, or the cones of umbra and
penumbra."""


_J2000_UTC = datetime(2000, 1, 1, 12, tzinfo=UTC)


def julian_date(when: datetime) -> float:
    """The Julian date of ``when`` (UTC, taken for the time scale of the solar formulas: the
    minute between UTC and TT moves the Sun by 0.0008°; a naive time is UTC)."""
    utc = when.replace(tzinfo=UTC) if when.tzinfo is None else when.astimezone(UTC)
    return J2000 + (utc - _J2000_UTC).total_seconds() / 86400.0


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
    The compiled :func:`tumble.kernels.sun.sun_at`, which states the formulas.
    """
    from tumble.kernels.sun import sun_samples  # compiled: loaded on first use

    n = np.asarray(jd, dtype=float)
    out = sun_samples(np.ascontiguousarray(n.ravel()))
    return out[:, :3].reshape(*n.shape, 3), out[:, 3].reshape(n.shape)


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
        Gill §3.4.2), or the cylinder of the Earth's radius behind it along ``sun``
        (:func:`tumble.kernels.sun.conical_shadow`, :func:`~tumble.kernels.sun.
        cylindrical_shadow`).

    Returns
    -------
    ndarray
        The visible fraction of the Sun, in [0, 1].
    """
    if model not in SHADOWS:
        raise ParameterError(f"shadow = {model!r} must be one of {', '.join(SHADOWS)}")
    from tumble.kernels.sun import shadow_samples

    r = np.asarray(position, dtype=float)
    s = np.asarray(sun, dtype=float)
    shape = np.broadcast_shapes(r.shape, s.shape)[:-1]
    d = np.broadcast_to(np.asarray(sun_distance, dtype=float), shape)
    flat = [np.ascontiguousarray(np.broadcast_to(x, (*shape, 3)).reshape(-1, 3)) for x in (r, s)]
    out = shadow_samples(flat[0], flat[1], np.ascontiguousarray(d.ravel()), model == "conical")
    return out.reshape(shape)


def eclipse_fraction(
    radius: ArrayLike, beta: ArrayLike, eccentricity: ArrayLike = 0.0, sun_perigee: ArrayLike = 0.0
) -> FloatArray:
    """The fraction of an orbit's time spent in the Earth's cylindrical shadow.

    Parameters
    ----------
    radius : array_like
        The semi-major axis [m] (a circular orbit's radius).
    beta : array_like
        The Sun's elevation above the orbit's plane [rad].
    eccentricity : array_like
        The orbit's eccentricity.
    sun_perigee : array_like
        The angle in the orbit's plane from the perigee to the Sun's projection [rad] (an
        eccentric orbit only).

    Returns
    -------
    ndarray

    Notes
    -----
    The compiled :func:`tumble.kernels.sun.eclipse_fraction`: for a circular orbit the fraction
    is arccos(c*)/π with c* = (1 − R²/a²)^½/cos β, and 0 where c* ≥ 1 (the Sun beyond the
    critical elevation); for an eccentric one the shadow's arc is located on the orbit.
    """
    from tumble.kernels.sun import eclipse_samples

    given = (radius, beta, eccentricity, sun_perigee)
    a, b, e, w = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in given))
    cb = np.cos(b)
    s = np.stack([cb * np.cos(w), cb * np.sin(w), np.sin(b)], axis=-1).reshape(-1, 3)
    out = eclipse_samples(np.ascontiguousarray(a.ravel()), np.ascontiguousarray(e.ravel()), s)
    return out.reshape(a.shape)
