"""The geomagnetic field turning with the Earth: a tilted dipole, or the IGRF to any degree.

The degree-1 part of the geomagnetic potential, V = a³ (g·r)/r³ with the Gauss vector
g = (g11, h11, g10) in Earth-fixed axes and the reference radius a = 6371.2 km, gives the
field B = −∇V = a³ [3 (g·r) r − r² g]/r⁵. Earth-fixed axes turn about the inertial ξ3 axis by
the Greenwich mean sidereal angle θ(t) = θ0 + ω_E t (precession, nutation and polar motion are
left out: their effect on the field seen by a body is far below the dipole's own error). The
field and its rate along an orbit are evaluated in compiled code (:mod:`tumble.kernels.space`).

Coefficients: IGRF-13 (Alken et al., "International Geomagnetic Reference Field: the
thirteenth generation", *Earth, Planets and Space* 73, 49 (2021)), the 2020.0 main field and
its 2020–2025 secular variation, evaluated at the epoch.

:class:`Igrf` is the whole International Geomagnetic Reference Field to degree N ≤ 13, its
coefficients those of the maintained package ``ppigrf`` (the IGRF-14 table, 1900–2030,
interpolated linearly in time as the IGRF prescribes), held fixed at the epoch (the secular
variation changes the field by ~0.1 % a year).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from datetime import UTC, datetime

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_range
from tumble.space.orbit import Orbit

__all__ = [
    "DIPOLE_EPOCHS",
    "EARTH_ROTATION",
    "IGRF13_DIPOLE",
    "REFERENCE_RADIUS",
    "Dipole",
    "Igrf",
    "greenwich_sidereal_angle",
]

REFERENCE_RADIUS = 6371.2e3
"""The geomagnetic reference radius a of the IGRF [m]."""
EARTH_ROTATION = 360.98564736629 * math.pi / 180.0 / 86400.0
"""The Earth's sidereal rotation rate [rad/s], that of :func:`greenwich_sidereal_angle`."""

IGRF13_DIPOLE = {
    "epoch": 2020.0,
    "g10": -29404.8,
    "g11": -1450.9,
    "h11": 4652.5,
    "g10_rate": 5.7,
    "g11_rate": 7.4,
    "h11_rate": -25.9,
}
"""IGRF-13 degree-1 coefficients at 2020.0 [nT] and their secular variation [nT/yr]."""

_J2000 = datetime(2000, 1, 1, 12, 0, 0, tzinfo=UTC)

DIPOLE_EPOCHS = (datetime(1900, 1, 1, tzinfo=UTC), datetime(2030, 1, 1, tzinfo=UTC))
"""The epochs :meth:`Dipole.igrf` accepts, those of the IGRF's own table (:class:`Igrf`):
beyond them the coefficients would be extrapolated by centuries (at year 1 the secular
variation alone changes g10 by 40 %), so an epoch outside is refused, not clamped."""


def _utc(epoch: datetime) -> datetime:
    return epoch.replace(tzinfo=UTC) if epoch.tzinfo is None else epoch.astimezone(UTC)


def greenwich_sidereal_angle(epoch: datetime) -> float:
    """Greenwich mean sidereal angle [rad] at ``epoch`` (UTC taken for UT1; naive times are
    UTC): θ = 280.46061837° + 360.98564736629° d + 0.000387933° T² − T³/38710000°, d the days
    from J2000.0 and T = d/36525 (Meeus, *Astronomical Algorithms*, eq. 12.4)."""
    d = (_utc(epoch) - _J2000).total_seconds() / 86400.0
    T = d / 36525.0
    deg = 280.46061837 + 360.98564736629 * d + 0.000387933 * T * T - T**3 / 38710000.0
    return math.radians(deg % 360.0)


def _decimal_year(epoch: datetime) -> float:
    e = _utc(epoch)
    start = datetime(e.year, 1, 1, tzinfo=UTC)
    length = (datetime(e.year + 1, 1, 1, tzinfo=UTC) - start).total_seconds()
    return e.year + (e - start).total_seconds() / length


def _along(orbit: Orbit, payload: FloatArray, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """B [T] and dB/dt [T/s] of a field payload at the body's place at times t [s]."""
    from tumble.kernels.space import fields_along  # compiled: loaded on first use

    times = np.atleast_1d(np.asarray(t, dtype=float))
    out = fields_along(orbit.payload(), payload, times)
    return out[:, :3], out[:, 3:]


@dataclass(frozen=True)
class Dipole:
    """A tilted geomagnetic dipole turning with the Earth.

    Parameters
    ----------
    g10, g11, h11 : float
        Degree-1 Gauss coefficients [nT] (IGRF sign convention: g10 < 0 for today's field).
    theta0 : float
        The Earth's rotation angle (Greenwich sidereal) at t = 0 [rad].
    rotation : float
        The Earth's rotation rate [rad/s]; 0 freezes the field in inertial space.
    """

    g10: float
    g11: float = 0.0
    h11: float = 0.0
    theta0: float = 0.0
    rotation: float = EARTH_ROTATION

    def __post_init__(self) -> None:
        for name in ("g10", "g11", "h11", "theta0", "rotation"):
            check_range(f"field.{name}", getattr(self, name))
        if self.strength == 0.0:
            raise ParameterError("field: g10, g11, h11 are all 0 (no field)")

    @classmethod
    def igrf(cls, epoch: datetime) -> Dipole:
        """The IGRF-13 dipole at ``epoch`` (its 2020–2025 secular variation carried on beyond
        2025: the dipole changes by ~0.1 % a year), with θ0 the sidereal angle of the epoch.

        Raises
        ------
        ParameterError
            For an epoch outside :data:`DIPOLE_EPOCHS` (1900–2030).
        """
        first, last = DIPOLE_EPOCHS
        if not first <= _utc(epoch) <= last:
            raise ParameterError(
                f"orbit.epoch = {_utc(epoch).date()} is outside the field's table "
                f"{first.year}–{last.year} (the IGRF-13 dipole); give [field] g10, g11 and h11 "
                'for another epoch, or model = "none"'
            )
        years = _decimal_year(epoch) - IGRF13_DIPOLE["epoch"]
        c = {
            k: IGRF13_DIPOLE[k] + years * IGRF13_DIPOLE[f"{k}_rate"] for k in ("g10", "g11", "h11")
        }
        return cls(c["g10"], c["g11"], c["h11"], greenwich_sidereal_angle(epoch))

    @property
    def strength(self) -> float:
        """√(g10² + g11² + h11²) [nT]: the field at the reference radius on the dipole's
        equator."""
        return math.sqrt(self.g10**2 + self.g11**2 + self.h11**2)

    @property
    def tilt(self) -> float:
        """Angle between the dipole axis and the Earth's rotation axis [rad]."""
        return math.acos(abs(self.g10) / self.strength)

    def payload(self, time_unit: float = 1.0) -> FloatArray:
        """The compiled code's field payload (:mod:`tumble.kernels.space`): a³ g [T m³], θ0
        and ω_E times ``time_unit`` [s]."""
        scale = 1e-9 * REFERENCE_RADIUS**3
        return np.array(
            [scale * self.g11, scale * self.h11, scale * self.g10, self.theta0,
             self.rotation * time_unit],
        )  # fmt: skip

    def along(self, orbit: Orbit, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """B [T] and dB/dt [T/s] in inertial axes at the body's place at times t [s], each of
        shape (n, 3)."""
        return _along(orbit, self.payload(), t)


@functools.lru_cache(maxsize=1)
def _igrf_table() -> tuple[FloatArray, list[tuple[int, int]], FloatArray, FloatArray]:
    """ppigrf's IGRF table, read once: its epochs (POSIX seconds), its (n, m) columns and the
    g and h values [nT] (epochs × columns)."""
    from ppigrf.ppigrf import read_shc  # the space extra's dependency

    g_table, h_table = read_shc()
    years = np.array([_utc(d.to_pydatetime()).timestamp() for d in g_table.index])
    columns = [(int(n), int(m)) for n, m in g_table.columns]
    return years, columns, g_table.to_numpy(dtype=float), h_table.to_numpy(dtype=float)


@dataclass(frozen=True)
class Igrf:
    """The IGRF to degree ``degree``, turning with the Earth.

    Parameters
    ----------
    degree : int
        Highest degree N, 1–13 (1: the IGRF's own tilted dipole).
    g, h : tuple of float
        Schmidt semi-normalised Gauss coefficients [nT], (n, m) in the order n = 1 … N,
        m = 0 … n (h_n0 = 0).
    theta0 : float
        The Earth's rotation angle (Greenwich sidereal) at t = 0 [rad].
    rotation : float
        The Earth's rotation rate [rad/s]; 0 freezes the field in inertial space.
    """

    degree: int
    g: tuple[float, ...]
    h: tuple[float, ...]
    theta0: float = 0.0
    rotation: float = EARTH_ROTATION

    def __post_init__(self) -> None:
        if not (isinstance(self.degree, int) and 1 <= self.degree <= 13):
            raise ParameterError(f"field.degree must be an integer in 1–13, got {self.degree!r}")
        size = (self.degree + 1) * (self.degree + 2) // 2 - 1
        if len(self.g) != size or len(self.h) != size:
            raise ParameterError(f"field: degree {self.degree} needs {size} g and h coefficients")
        for name in ("theta0", "rotation"):
            check_range(f"field.{name}", getattr(self, name))

    @classmethod
    def at(cls, epoch: datetime, degree: int = 13, rotation: bool = True) -> Igrf:
        """The IGRF at ``epoch`` (1900–2030) to ``degree``, θ0 the sidereal angle of the
        epoch; ``rotation`` False freezes it in inertial space."""
        years, columns, g_table, h_table = _igrf_table()
        when = _utc(epoch).timestamp()
        if not years[0] <= when <= years[-1]:
            first, last = (datetime.fromtimestamp(y, UTC).year for y in (years[0], years[-1]))
            raise ParameterError(
                f"orbit.epoch must be within {first}–{last} for the IGRF, got {epoch.date()}"
            )
        index = [columns.index((n, m)) for n in range(1, degree + 1) for m in range(n + 1)]
        # Linear in time between the table's epochs, as ppigrf's own field is.
        g, h = (tuple(float(np.interp(when, years, table[:, k])) for k in index)
                for table in (g_table, h_table))  # fmt: skip
        return cls(degree, g, h, greenwich_sidereal_angle(epoch),
                   EARTH_ROTATION if rotation else 0.0)  # fmt: skip

    def payload(self, time_unit: float = 1.0) -> FloatArray:
        """The compiled code's field payload (:func:`tumble.kernels.space.harmonic_size`): N,
        θ0, ω_E times ``time_unit`` [s], the reference radius [m], then C_nm and S_nm [T], the
        coefficients times the Schmidt factors √(2 (n − m)!/(n + m)!) (m > 0) of the
        unnormalised Legendre functions."""
        factors = [1.0 if m == 0 else math.sqrt(2.0 * math.factorial(n - m) / math.factorial(n + m))
                   for n in range(1, self.degree + 1) for m in range(n + 1)]  # fmt: skip
        scale = 1e-9 * np.array(factors)
        return np.concatenate([
            [float(self.degree), self.theta0, self.rotation * time_unit, REFERENCE_RADIUS],
            scale * np.array(self.g), scale * np.array(self.h),
        ])  # fmt: skip

    def along(self, orbit: Orbit, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """B [T] and dB/dt [T/s] in inertial axes at the body's place at times t [s], each of
        shape (n, 3)."""
        return _along(orbit, self.payload(), t)
