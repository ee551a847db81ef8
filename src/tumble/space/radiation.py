"""The force and moment of sunlight on a faceted body: absorption, specular and diffuse
reflection, and the thermal re-emission of what is absorbed.

A facet of area A and outward normal n, lit from the unit direction s towards the Sun at
cos θ = n·s > 0, under the radiation pressure P = Φ/c (Φ the solar flux at the body, c the
speed of light), feels

    f = −P A cos θ [(1 − ρs) s + (2 ρs cos θ + ⅔ ρd + ⅔ α κ) n],

with ρs, ρd the specular and diffuse (Lambertian) reflectivities, α = 1 − ρs − ρd the
absorbed fraction and κ = (ε_front − ε_back)/(ε_front + ε_back) the share of the absorbed
light re-emitted, at once and as a Lambertian emitter, to push along −n (1 for a facet of a
closed body, 0 for a thin panel whose faces are alike). The first two terms are the standard
absorption–reflection model (Montenbruck and Gill, *Satellite Orbits*, Springer 2000,
eq. 3.75, with the diffuse part of Milani, Nobili and Farinella, *Non-gravitational
perturbations and satellite geodesy*, 1987); the last is the instantaneous re-emission used for
the YORP effect (Rubincam, *Icarus* 148, 2000; Scheeres, *Icarus* 188, 2007). A facet facing
away from the Sun feels nothing; one facet shading another is ignored. The moment about the
centre of mass is Σ r × f over the facets, r their centres.
"""

from __future__ import annotations

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.space.facets import Facets
from tumble.space.sun import AU, SOLAR_FLUX

__all__ = ["SPEED_OF_LIGHT", "facet_forces", "pressure", "radiation_force_and_moment"]

SPEED_OF_LIGHT = 299_792_458.0
"""[m/s], exact."""


def pressure(sun_distance: ArrayLike = AU) -> FloatArray:
    """The solar radiation pressure P = Φ(1 AU)/c · (1 AU / d)² [N/m²] at ``sun_distance`` [m]
    (4.54e-6 N/m² at 1 AU)."""
    d = np.asarray(sun_distance, dtype=float)
    return np.asarray(SOLAR_FLUX / SPEED_OF_LIGHT * (AU / d) ** 2)


def facet_forces(facets: Facets, sun: ArrayLike, p: float) -> FloatArray:
    """The force on every facet [N], body axes, lit from the unit body direction ``sun``
    under the pressure ``p`` [N/m²] (shape (n, 3); zero for a facet facing away)."""
    s = np.asarray(sun, dtype=float)
    s = s / np.linalg.norm(s)
    cos = facets.normal @ s
    lit = np.where(cos > 0.0, cos, 0.0)
    along_n = (
        2.0 * facets.specular * lit
        + (2.0 / 3.0) * facets.diffuse
        + (2.0 / 3.0) * facets.absorbed * facets.thermal
    )
    scale = -p * facets.area * lit
    along_s = 1.0 - facets.specular
    return scale[:, None] * (along_s[:, None] * s + along_n[:, None] * facets.normal)


def radiation_force_and_moment(
    facets: Facets, sun: ArrayLike, p: float
) -> tuple[FloatArray, FloatArray]:
    """The resultant force [N] and its moment about the centre of mass [N·m], body axes, of
    sunlight from the unit body direction ``sun`` under the pressure ``p`` [N/m²]."""
    f = facet_forces(facets, sun, p)
    return f.sum(axis=0), np.cross(facets.centre, f).sum(axis=0)
