"""The force and moment of the upper atmosphere on a faceted body in free-molecular flow, and the
air it meets: an exponential density model and the atmosphere turning with the Earth.

Above ~150 km the mean free path of the air far exceeds a satellite's size: molecules strike
the surface one by one and leave it (free-molecular flow). At orbital speeds (7–8 km/s, far
above the molecules' thermal speed, the hypersonic limit) a facet of area A and outward normal
n, moving through air of density ρ at the velocity v relative to it (s = v/|v|), struck at
cos θ = n·s > 0, feels

    f = −ρ v² A cos θ [σt s + (σn vw/v + (2 − σn − σt) cos θ) n],

with σn and σt the accommodation coefficients of the normal and tangential momentum (0: the
molecules bounce specularly; 1: they leave diffusely, in equilibrium with the wall) and vw/v
the ratio of the mean speed of the molecules re-emitted by the wall to the flow's
(Schaaf and Chambré, *Flow of rarefied gases*, Princeton 1961; the panel form of Hughes,
*Spacecraft attitude dynamics*, Wiley 1986, §8.5, and Wertz (ed.), *Spacecraft attitude
determination and control*, §17.2). A facet facing away from the flow feels nothing; one facet
shielding another is ignored. The moment about the centre of mass is Σ r × f.

The force has the form of sunlight's (:mod:`tumble.space.radiation`) with the flow direction
for the Sun's, ρ v² for the pressure and, per facet, ks = A σt, kp = A (2 − σn − σt),
kd = A σn vw/v for A (1 − ρs), 2 A ρs and ⅔ A (ρd + α κ): :func:`air_table` writes a surface
in that form, which the compiled sunlight code reads.

The air: :func:`exponential_density`, the piecewise exponential model of Vallado (*Fundamentals
of Astrodynamics and Applications*, 4th ed., 2013, table 8-4), from the CIRA-72 atmosphere at
mean solar activity — a fallback that knows neither the solar cycle nor the day–night bulge
(NRLMSIS, which does, needs the space weather of the dates); :func:`air_velocity`, the body's
velocity relative to an atmosphere turning with the Earth, v − ω⊕ × r.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.astro import ATMOSPHERE_BANDS
from tumble.space.facets import Facets
from tumble.space.geomagnetic import EARTH_ROTATION  # the atmosphere turns with the Earth

__all__ = [
    "EXPONENTIAL_ATMOSPHERE",
    "Accommodation",
    "aerodynamic_force_and_moment",
    "air_table",
    "air_velocity",
    "exponential_density",
]

EXPONENTIAL_ATMOSPHERE = np.array(ATMOSPHERE_BANDS)
"""The bands of Vallado's table 8-4 made continuous (:data:`tumble.kernels.astro.
ATMOSPHERE_BANDS`): base altitude [km], nominal density [kg/m³], scale height [km]."""


@dataclass(frozen=True)
class Accommodation:
    """How a surface returns the molecules that strike it.

    Attributes
    ----------
    normal, tangential : float
        The accommodation coefficients σn and σt of the normal and the tangential momentum, in
        [0, 1] (0: specular reflection; 1: diffuse re-emission; satellite surfaces in LEO are
        close to diffuse, σ ≈ 0.8–1).
    wall_speed_ratio : float
        vw/v, the mean speed of the re-emitted molecules over the flow's, in [0, 1) (about
        0.05 for a wall near 300 K at 7.5 km/s).
    """

    normal: float = 1.0
    tangential: float = 1.0
    wall_speed_ratio: float = 0.05

    def __post_init__(self) -> None:
        for name in ("normal", "tangential"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ParameterError(f"accommodation {name} = {value:g} must be in [0, 1]")
        if not 0.0 <= self.wall_speed_ratio < 1.0:
            raise ParameterError(f"wall_speed_ratio = {self.wall_speed_ratio:g} must be in [0, 1)")


def air_table(facets: Facets, accommodation: Accommodation) -> FloatArray:
    """The facets in the form of :meth:`Facets.table` with the air's areas: ks = A σt,
    kp = A (2 − σn − σt), kd = A σn vw/v [m²] (module notes)."""
    table = facets.table()
    a = accommodation
    table[:, 6] = facets.area * a.tangential
    table[:, 7] = facets.area * (2.0 - a.normal - a.tangential)
    table[:, 8] = facets.area * a.normal * a.wall_speed_ratio
    return table


def aerodynamic_force_and_moment(
    facets: Facets, accommodation: Accommodation, velocity: ArrayLike, density: float
) -> tuple[FloatArray, FloatArray]:
    """The resultant force [N] and its moment about the centre of mass [N·m], body axes, of the
    air of ``density`` [kg/m³] on a body moving at ``velocity`` [m/s, body axes] relative to it.
    """
    v = np.asarray(velocity, dtype=float)
    speed = float(np.linalg.norm(v))
    if speed == 0.0:
        return np.zeros(3), np.zeros(3)
    s = v / speed
    table = air_table(facets, accommodation)
    cos = facets.normal @ s
    struck = np.where(cos > 0.0, cos, 0.0)
    along_n = table[:, 7] * struck + table[:, 8]
    f = -density * speed**2 * struck[:, None] * (table[:, 6, None] * s
                                                 + along_n[:, None] * facets.normal)  # fmt: skip
    return f.sum(axis=0), np.cross(facets.centre, f).sum(axis=0)


def exponential_density(altitude: ArrayLike) -> FloatArray:
    """The density [kg/m³] at ``altitude`` [m above the equatorial radius] of the piecewise
    exponential model (:data:`EXPONENTIAL_ATMOSPHERE`); above 1000 km its last band goes on.

    Raises
    ------
    ParameterError
        For an altitude below 0.
    """
    h = np.asarray(altitude, dtype=float) / 1e3
    if np.any(h < 0.0):
        raise ParameterError("exponential_density: altitude must be at least 0 m")
    band = np.clip(np.searchsorted(EXPONENTIAL_ATMOSPHERE[:, 0], h, side="right") - 1, 0, None)
    h0, rho0, scale = (EXPONENTIAL_ATMOSPHERE[band, k] for k in range(3))
    return np.asarray(rho0 * np.exp(-(h - h0) / scale))


def air_velocity(position: ArrayLike, velocity: ArrayLike) -> FloatArray:
    """The velocity [m/s] of a body at ``position`` [m] moving at ``velocity`` [m/s] (inertial
    axes, ξ3 the Earth's axis) relative to the atmosphere turning with the Earth:
    v − ω⊕ ξ3 × r."""
    r = np.asarray(position, dtype=float)
    v = np.asarray(velocity, dtype=float)
    turning = EARTH_ROTATION * np.stack([-r[..., 1], r[..., 0], np.zeros_like(r[..., 0])], axis=-1)
    return np.asarray(v - turning)
