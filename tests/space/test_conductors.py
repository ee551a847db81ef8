"""Magnetic tensors of conducting shapes against independent evaluations of the Joule power
σ h ∫|E − ∇φ|² of their low-frequency currents (E = ½ x × r)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_bvp

from tumble.errors import ParameterError
from tumble.space import (
    flat_plate,
    solid_sphere,
    thin_cylindrical_shell,
    thin_spherical_shell,
    torsion_constant_rectangle,
)

SIGMA, H = 3.5e7, 2e-3  # aluminium [S/m], a 2 mm wall [m]


def test_the_spherical_shell_and_the_solid_sphere_by_quadrature():
    # On a sphere E = ½ x × r is tangential and divergence-free: no charge, P = σh∫|E|² dA
    # (shell) or σ∫|E|² dV (ball), with |x × r|² = r² sin²θ for x along the pole.
    R = 0.7
    shell = SIGMA * H * quad(lambda th: 0.25 * R**2 * math.sin(th) ** 2 * 2 * math.pi * R**2
                             * math.sin(th), 0.0, math.pi)[0]  # fmt: skip
    ball = SIGMA * quad(lambda r: 0.25 * r**2 * (8 * math.pi / 3) * r**2, 0.0, R)[0]
    assert thin_spherical_shell(SIGMA, R, H) == pytest.approx(shell * np.eye(3), rel=1e-12)
    assert solid_sphere(SIGMA, R) == pytest.approx(ball * np.eye(3), rel=1e-12)


@pytest.mark.parametrize("length", [0.3, 2.0, 10.0])
def test_the_cylinder_across_its_axis_by_the_boundary_value_problem(length):
    # x across the axis: φ = g(z) cos ϕ, and the power per unit σh is
    # πR ∫ [(g/R − z/2)² + (g′ + R/2)²] dz (the ϕ-average ½ of cos², sin²), least when
    # g″ − g/R² = −z/(2R) with g′(±ℓ/2) = −R/2 (no current through the open ends). Solved
    # here by collocation (scipy's solve_bvp, tolerance 1e-10) and integrated numerically.
    R = 1.3

    def rhs(z, y):
        return np.vstack([y[1], y[0] / R**2 - z / (2 * R)])

    def ends(ya, yb):
        return np.array([ya[1] + R / 2, yb[1] + R / 2])

    z = np.linspace(-length / 2, length / 2, 201)
    sol = solve_bvp(rhs, ends, z, np.zeros((2, z.size)), tol=1e-10, max_nodes=100000)
    assert sol.success
    power = math.pi * R * quad(
        lambda s: (sol.sol(s)[0] / R - s / 2) ** 2 + (sol.sol(s)[1] + R / 2) ** 2,
        -length / 2, length / 2, epsabs=0.0, epsrel=1e-12)[0]  # fmt: skip
    M = thin_cylindrical_shell(SIGMA, R, length, H)
    # solve_bvp's residual tolerance 1e-10 bounds the error of g, hence of the power, to ~1e-8.
    assert M[0, 0] == pytest.approx(SIGMA * H * power, rel=1e-6)
    assert M[1, 1] == M[0, 0]
    # Along the axis: the azimuthal field ½R|x| all over the tube, P = σh(R²/4)·2πRℓ.
    assert M[2, 2] == pytest.approx(SIGMA * H * 0.25 * R**2 * 2 * math.pi * R * length, rel=1e-14)


def test_the_cylinders_limits():
    # A long tube: M⊥ → π σ h R³ ℓ (the axial current closes far away); a short ring:
    # M⊥ → π σ h R ℓ³/12. Relative corrections 2R/ℓ and ℓ²/(R²·10) bound the tolerances.
    R = 1.0
    long = thin_cylindrical_shell(SIGMA, R, 1e4, H)[0, 0]
    assert long == pytest.approx(math.pi * SIGMA * H * R**3 * 1e4, rel=3e-4)
    ring = thin_cylindrical_shell(SIGMA, R, 1e-2, H)[0, 0]
    assert ring == pytest.approx(math.pi * SIGMA * H * R * 1e-6 / 12, rel=1e-4)


def test_the_plates_torsion_constant():
    # Saint-Venant's values: 0.1406 a⁴ for a square (Timoshenko and Goodier's table: k = 0.141),
    # and a b³/3 (1 − 0.630 b/a) for a thin strip; the disc's π R⁴/2 gives M33 = π σ h R⁴/8.
    assert torsion_constant_rectangle(1.0, 1.0) == pytest.approx(0.1406, abs=1e-4)
    a, b = 100.0, 1.0
    assert torsion_constant_rectangle(a, b) == pytest.approx(a * b**3 / 3 * (1 - 0.630 * b / a),
                                                             rel=1e-4)  # fmt: skip
    M = flat_plate(SIGMA, 2.0, 1.0, H)
    assert M[0, 0] == M[1, 1] == 0.0
    assert M[2, 2] == pytest.approx(0.25 * SIGMA * H * torsion_constant_rectangle(2.0, 1.0))


def test_a_negative_conductivity_is_refused_in_one_line():
    with pytest.raises(ParameterError, match=r"conductivity = -1 is outside the allowed range"):
        thin_spherical_shell(-1.0, 1.0, 1e-3)
