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

**The expanded illumination.** The factor max(0, cos θ) is what makes the moment a kinked
function of the attitude. Expanded in a Fourier series of θ to second order (Benson and
Scheeres, *J. Guid. Control Dyn.* 44(4), 2021),

    max(0, cos θ) ≈ 1/(3π) + ½ cos θ + 4/(3π) cos² θ

(the series 1/π + ½ cos θ + 2/(3π) cos 2θ written in c = cos θ), the moment becomes a cubic
polynomial of the Sun's body direction s,

    M(s) = P (C⁰ + C¹ s + C² s s + C³ s s s),

whose coefficient tensors are sums over the facets (:func:`expanded_coefficients`) formed once:
the moment's averages over any motion are then those of a few monomials of s, whatever the
number of facets. It is exact for a body whose every facet sees the Sun half the time
symmetrically, and otherwise an approximation whose error the theory page measures.
"""

from __future__ import annotations

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.kernels.astro import AU, SOLAR_FLUX, SPEED_OF_LIGHT
from tumble.space.facets import Facets

__all__ = [
    "SPEED_OF_LIGHT",
    "expanded_coefficients",
    "expanded_moment",
    "facet_forces",
    "pressure",
    "radiation_force_and_moment",
]


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
    t = facets.table()
    cos = facets.normal @ s
    lit = np.where(cos > 0.0, cos, 0.0)
    along_n = t[:, 7] * lit + t[:, 8]  # kp ĉ + kd
    return -p * lit[:, None] * (t[:, 6, None] * s + along_n[:, None] * facets.normal)


def radiation_force_and_moment(
    facets: Facets, sun: ArrayLike, p: float
) -> tuple[FloatArray, FloatArray]:
    """The resultant force [N] and its moment about the centre of mass [N·m], body axes, of
    sunlight from the unit body direction ``sun`` under the pressure ``p`` [N/m²]."""
    f = facet_forces(facets, sun, p)
    return f.sum(axis=0), np.cross(facets.centre, f).sum(axis=0)


def expanded_coefficients(
    facets: Facets,
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The tensors C⁰ (3,), C¹ (3, 3), C² (3, 3, 3), C³ (3, 3, 3, 3) of the moment with the
    expanded illumination, M(s) = P (C⁰ + C¹ s + C² s s + C³ s s s) [N·m per N/m² = m³], body
    axes, symmetric in their last indices (module notes): those the orbit-averaged solar term
    evaluates (:func:`tumble.kernels.terms.solar_radiation.expanded_tensors`)."""
    from tumble.kernels.terms.solar_radiation import expanded_tensors  # loads numba

    return expanded_tensors(facets.table())


def expanded_moment(
    coefficients: tuple[FloatArray, FloatArray, FloatArray, FloatArray], sun: ArrayLike, p: float
) -> FloatArray:
    """The moment [N·m], body axes, with the expanded illumination (:func:`expanded_coefficients`)
    for the unit body direction ``sun`` under the pressure ``p`` [N/m²]."""
    c0, c1, c2, c3 = coefficients
    s = np.asarray(sun, dtype=float)
    s = s / np.linalg.norm(s)
    return np.asarray(
        p
        * (
            c0
            + c1 @ s
            + np.einsum("ijk,j,k->i", c2, s, s)
            + np.einsum("ijkl,j,k,l->i", c3, s, s, s)
        )
    )
