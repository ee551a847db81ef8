"""Magnetic (eddy-current) tensors of simple conducting shapes.

A conductor turning at ω in a field B (both in body axes) carries the induced dipole m = M x
with x = −dB/dt seen in the body, = ω × B for a steady field, and feels the moment m × B; M is
its magnetic tensor [S·m⁴]. For a sphere M = m·1 and the moment is −m B² ω⊥, ω⊥ the part of ω
across B.

The tensors below hold in the limit of low frequency, where the currents do not shield the body
from the field: skin depth √(2/(μ0 σ ω)) much larger than the wall (thin shells, plates) or the
radius (solid sphere), i.e. μ0 σ h R ω ≪ 1 and μ0 σ R² ω ≪ 1 (for aluminium, σ ≈ 3.5e7 S/m, a
2 mm wall of radius 1 m gives 0.09 at ω = 1 rad/s). In that limit the current density is
j = σ(E − ∇φ), where E = ½ x × r after the conservative part of the motional field
(ω × r) × B is removed, and the charge potential φ makes the current tangential at every
surface and edge; the Joule power σ∫|E − ∇φ|² = xᵀ M x defines M. The derivations, for each
shape, are on the documentation's page on the orbiting body; the sphere's are those of Smythe
(*Static and Dynamic Electricity*, 3rd ed., 1968), and the comparisons of Ortiz Gómez and
Walker ("Eddy currents applied to de-tumbling of space debris", *Acta Astronautica* 114 (2015)
34–53) with finite-element results bound their accuracy for real shells.
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.errors import check_range

__all__ = [
    "flat_plate",
    "solid_sphere",
    "thin_cylindrical_shell",
    "thin_spherical_shell",
    "torsion_constant_rectangle",
]


def _positive(**values: float) -> None:
    for name, value in values.items():
        check_range(name, value, low=0.0)


def thin_spherical_shell(conductivity: float, radius: float, thickness: float) -> FloatArray:
    """M = (2π/3) σ h R⁴ 1 [S·m⁴] of a thin spherical shell (conductivity σ [S/m], radius R
    [m], wall h [m] ≪ R)."""
    _positive(conductivity=conductivity, radius=radius, thickness=thickness)
    return (2.0 * math.pi / 3.0) * conductivity * thickness * radius**4 * np.eye(3)


def solid_sphere(conductivity: float, radius: float) -> FloatArray:
    """M = (2π/15) σ R⁵ 1 [S·m⁴] of a solid conducting sphere of radius R [m]."""
    _positive(conductivity=conductivity, radius=radius)
    return (2.0 * math.pi / 15.0) * conductivity * radius**5 * np.eye(3)


def thin_cylindrical_shell(
    conductivity: float, radius: float, length: float, thickness: float
) -> FloatArray:
    """M of a thin open cylindrical shell with its axis along body axis 3 [S·m⁴].

    Along the axis, M33 = (π/2) σ h R³ ℓ: x along the axis drives an azimuthal current, exact
    for any length. Across it, M11 = M22 = 2π σ h R⁴ (λ − tanh λ), λ = ℓ/(2R): the axial
    current closes around the open ends (the surface problem solved exactly in φ and z), which
    tends to π σ h R³ ℓ for a long tube and to π σ h R ℓ³/12 for a short ring.

    Parameters
    ----------
    conductivity : float
        σ [S/m].
    radius, length, thickness : float
        R, ℓ and the wall h ≪ R [m].
    """
    _positive(conductivity=conductivity, radius=radius, length=length, thickness=thickness)
    lam = 0.5 * length / radius
    across = 2.0 * math.pi * conductivity * thickness * radius**4 * (lam - math.tanh(lam))
    along = 0.5 * math.pi * conductivity * thickness * radius**3 * length
    return np.diag([across, across, along])


def torsion_constant_rectangle(a: float, b: float, terms: int = 50) -> float:
    r"""Saint-Venant's torsion constant J of an a × b rectangle [m⁴]:
    :math:`J = a b^3 \left[\tfrac13 - \tfrac{64}{\pi^5}\tfrac{b}{a}\sum_{n\ \mathrm{odd}}
    \tanh(n\pi a/2b)/n^5\right]` for a ≥ b (Timoshenko and
    Goodier, *Theory of Elasticity*, torsion of rectangular bars); 0.1406 a⁴ for a square."""
    a, b = max(a, b), min(a, b)
    n = np.arange(1, 2 * terms, 2, dtype=float)
    series = float(np.sum(np.tanh(n * math.pi * a / (2.0 * b)) / n**5))
    return a * b**3 * (1.0 / 3.0 - 64.0 / math.pi**5 * (b / a) * series)


def flat_plate(conductivity: float, a: float, b: float, thickness: float) -> FloatArray:
    """M = diag(0, 0, σ h J/4) of a thin flat a × b rectangular plate normal to body axis 3
    [S·m⁴], J its planform's torsion constant (:func:`torsion_constant_rectangle`).

    Only x along the normal drives current in the plate; the current's stream function ψ obeys
    ∇²ψ = −x3 inside with ψ = 0 on the edge, Prandtl's torsion problem, so that the power is
    σ h x3² J/4 (for a disc of radius R, J = πR⁴/2 and M33 = π σ h R⁴/8).
    """
    _positive(conductivity=conductivity, a=a, b=b, thickness=thickness)
    return np.diag([0.0, 0.0, 0.25 * conductivity * thickness * torsion_constant_rectangle(a, b)])
