"""Earth orbits for the torques on an orbiting body: Keplerian elements with the secular drift
of the node, the perigee and the mean anomaly under J2.

The motion itself is evaluated in compiled code (:mod:`tumble.kernels.space`); this module holds
the elements, their checks, the secular rates and the payload handed to that code. SI units:
metres, seconds, radians. Time t = 0 is the epoch of the elements.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from datetime import UTC, datetime

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_range
from tumble.kernels.astro import EARTH_RADIUS  # a circular orbit's altitude is above it

__all__ = [
    "EARTH_J2",
    "EARTH_MU",
    "EARTH_RADIUS",
    "Orbit",
    "sun_synchronous_inclination",
]

EARTH_MU = 3.986004418e14
"""The Earth's gravitational parameter GM [m³/s²] (WGS 84)."""
EARTH_J2 = 1.08262668e-3
"""The Earth's second zonal harmonic J2 (EGM2008), for the secular drift of the elements."""

_SUN_RATE = 2.0 * math.pi / (365.2421897 * 86400.0)
"""The mean motion of the Sun about the Earth [rad/s]: the node rate of a sun-synchronous
orbit."""


@dataclass(frozen=True)
class Orbit:
    """A Keplerian orbit about the Earth at the epoch t = 0, with secular J2 drift.

    Parameters
    ----------
    a : float
        Semi-major axis [m], with perigee a(1 − e) above the Earth's equatorial radius.
    e : float
        Eccentricity, 0 ≤ e < 1.
    i : float
        Inclination [rad], in [0, π].
    raan : float
        Right ascension of the ascending node at the epoch [rad].
    argp : float
        Argument of perigee at the epoch [rad] (of a circular orbit: the origin of u below).
    mean_anomaly : float
        Mean anomaly at the epoch [rad] (of a circular orbit: the argument of latitude u0
        less ``argp``).
    j2 : bool
        Whether the node, the perigee and the mean anomaly drift under J2 (the secular rates of
        first order in J2, e.g. Vallado, *Fundamentals of Astrodynamics and Applications*,
        on the secular effects of J2); False: a fixed Keplerian ellipse.
    mu : float
        Gravitational parameter [m³/s²].
    """

    a: float
    e: float = 0.0
    i: float = 0.0
    raan: float = 0.0
    argp: float = 0.0
    mean_anomaly: float = 0.0
    j2: bool = True
    mu: float = EARTH_MU

    def __post_init__(self) -> None:
        check_range("orbit.e", self.e, low=0.0, high=1.0, low_open=False)
        check_range("orbit.i [rad]", self.i, low=0.0, high=math.pi, low_open=False, high_open=False)
        check_range("orbit.a [m]", self.a, low=0.0)
        for name in ("raan", "argp", "mean_anomaly"):
            check_range(f"orbit.{name} [rad]", getattr(self, name))
        perigee = self.a * (1.0 - self.e)
        if perigee <= EARTH_RADIUS:
            raise ParameterError(
                f"orbit: perigee altitude {(perigee - EARTH_RADIUS) / 1e3:.6g} km is below the "
                "Earth's surface (allowed: > 0 km)"
            )

    @classmethod
    def circular(
        cls, altitude_km: float, i: float = 0.0, raan: float = 0.0, u0: float = 0.0,
        j2: bool = True,
    ) -> Orbit:  # fmt: skip
        """A circular orbit ``altitude_km`` above the equatorial radius, with the body at the
        argument of latitude ``u0`` [rad] at the epoch."""
        check_range("orbit.altitude [km]", altitude_km, low=0.0)
        return cls(EARTH_RADIUS + 1e3 * altitude_km, 0.0, i, raan, 0.0, u0, j2)

    @classmethod
    def from_tle(cls, line1: str, line2: str, j2: bool = True) -> tuple[Orbit, datetime]:
        """The mean elements of a two-line element set and its epoch (UTC), through the
        ``sgp4`` package (Vallado's SGP4; ``pip install 'tumble[space]'``).

        The elements are SGP4's mean (Brouwer) elements in its TEME frame, the semi-major
        axis from the un-Kozai'd mean motion; tumble then drifts them with its own secular J2
        rates (no drag: over years a low orbit's decay changes the field the body sees). The
        position at the epoch differs from SGP4's osculating one by the short-period J2 terms,
        ~J2 (R/a)² a ≈ 10 km in low orbit.

        Raises
        ------
        ParameterError
            A malformed element set, one SGP4 refuses, or no ``sgp4`` package.
        """
        try:
            from sgp4.api import Satrec
            from sgp4.conveniences import sat_epoch_datetime
        except ImportError:
            raise ParameterError(
                "orbit.tle needs the sgp4 package: pip install 'tumble[space]'"
            ) from None
        lines = (line1.rstrip(), line2.rstrip())
        for k, line in enumerate(lines, start=1):
            _check_tle_line(k, line)
        try:
            sat = Satrec.twoline2rv(*lines)
        except (ValueError, IndexError) as exc:
            raise ParameterError(f"orbit.tle is not a two-line element set: {exc}") from None
        if sat.error != 0:
            raise ParameterError(f"orbit.tle: SGP4 refuses the element set (error {sat.error})")
        a = float(sat.a) * float(sat.radiusearthkm) * 1e3
        orbit = cls(a, float(sat.ecco), float(sat.inclo), float(sat.nodeo), float(sat.argpo),
                    float(sat.mo), j2)  # fmt: skip
        return orbit, sat_epoch_datetime(sat).astimezone(UTC)

    @property
    def mean_motion(self) -> float:
        """Keplerian mean motion n = √(μ/a³) [rad/s]."""
        return math.sqrt(self.mu / self.a**3)

    @property
    def period(self) -> float:
        """Keplerian period 2π/n [s]."""
        return 2.0 * math.pi / self.mean_motion

    def secular_rates(self) -> tuple[float, float, float]:
        """(dΩ/dt, dω/dt, dM/dt) [rad/s]: first order in J2 with p = a(1 − e²),
        dΩ/dt = −(3/2) n J2 (R/p)² cos i, dω/dt = (3/4) n J2 (R/p)² (5 cos² i − 1),
        dM/dt = n [1 + (3/4) J2 (R/p)² √(1 − e²) (3 cos² i − 1)]; (0, 0, n) without J2."""
        n = self.mean_motion
        if not self.j2:
            return 0.0, 0.0, n
        eta2 = 1.0 - self.e**2
        k = EARTH_J2 * (EARTH_RADIUS / (self.a * eta2)) ** 2
        c = math.cos(self.i)
        return (
            -1.5 * n * k * c,
            0.75 * n * k * (5.0 * c * c - 1.0),
            n * (1.0 + 0.75 * k * math.sqrt(eta2) * (3.0 * c * c - 1.0)),
        )

    def payload(self, time_unit: float = 1.0) -> FloatArray:
        """The compiled code's orbit payload (:mod:`tumble.kernels.space`) for times counted
        in units of ``time_unit`` seconds: rates times it, μ times its square."""
        raan_rate, argp_rate, mean_rate = self.secular_rates()
        return np.array(
            [self.a, self.e, self.i, self.raan, self.argp, self.mean_anomaly,
             mean_rate * time_unit, raan_rate * time_unit, argp_rate * time_unit,
             self.mu * time_unit**2],
        )  # fmt: skip

    def states(self, t: ArrayLike) -> FloatArray:
        """Position [m] and velocity [m/s] in inertial axes at times t [s], shape (n, 6)."""
        from tumble.kernels.space import orbit_states  # compiled: loaded on first use

        times = np.atleast_1d(np.asarray(t, dtype=float))
        return orbit_states(self.payload(), times)  # type: ignore[no-any-return]

    def normal(self, t: ArrayLike = 0.0) -> FloatArray:
        """Unit orbit normal ĥ = (sin Ω sin i, −cos Ω sin i, cos i) at times t [s], shape
        (..., 3) for t of shape (...)."""
        raan = self.raan + self.secular_rates()[0] * np.asarray(t, dtype=float)
        si = math.sin(self.i)
        cos_i = np.full_like(raan, math.cos(self.i))
        return np.stack([np.sin(raan) * si, -np.cos(raan) * si, cos_i], axis=-1)


def _check_tle_line(k: int, line: str) -> None:
    """Line k of a two-line element set: 69 characters, starting with its number, with the
    modulo-10 checksum of its digits (a minus sign counting 1) in the last column."""
    if len(line) != 69 or not line.startswith(f"{k} "):
        raise ParameterError(
            f"orbit.tle line {k} is not a line {k} of a two-line element set (69 characters "
            f"starting with '{k} ', got {len(line)})"
        )
    total = sum(int(c) for c in line[:68] if c.isdigit()) + line[:68].count("-")
    if not line[68].isdigit() or total % 10 != int(line[68]):
        raise ParameterError(
            f"orbit.tle line {k}: checksum {line[68]!r} does not match ({total % 10})"
        )


def sun_synchronous_inclination(altitude_km: float) -> float:
    """The inclination [rad] at which a circular orbit's node turns with the mean Sun,
    dΩ/dt = 360° per tropical year, under J2."""
    a = EARTH_RADIUS + 1e3 * altitude_km
    n = math.sqrt(EARTH_MU / a**3)
    c = -_SUN_RATE / (1.5 * n * EARTH_J2 * (EARTH_RADIUS / a) ** 2)
    if not -1.0 <= c <= 1.0:
        # |c| grows as a^(7/2): the highest sun-synchronous circular orbit has |c| = 1.
        highest = (a * abs(c) ** (-1.0 / 3.5) - EARTH_RADIUS) / 1e3
        raise ParameterError(
            f"orbit.altitude = {altitude_km:g} km with sun_synchronous = true: no "
            f"sun-synchronous circular orbit above {highest:.0f} km (the altitude is in km)"
        )
    return math.acos(c)
