"""The effective potential W(θ), its slope, the energy (1.6) and the quartic f(u) (1.7) of the
symmetric body under M0(θ) = A(a sinθ + b sin2θ) (Serov 1991)."""

from __future__ import annotations

import math

import numpy as np

from tumble._docstrings import DocSections
from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_finite
from tumble.unperturbed._checks import finite_array

__all__ = ["effective_potential", "energy", "potential_slope", "quartic_coefficients"]

_DOC = DocSections(
    theta="""
    theta : array_like
        Nutation angle [rad], strictly inside (0, π).
    """,
    constants="""
    R, G : float
        Reduced angular momenta [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].
    """,
)


def _theta_array(theta: ArrayLike, name: str = "theta") -> FloatArray:
    th = np.asarray(theta, dtype=float)
    ok = np.isfinite(th) & (th > 0.0) & (th < math.pi)
    if not np.all(ok):
        bad = float(th[~ok].flat[0]) if th.ndim else float(th)
        raise ParameterError(f"{name} = {bad:g} is outside the allowed range (0, π)")
    return th


def _finite(**values: float) -> None:
    for name, value in values.items():
        check_finite(name, float(value))


@_DOC
def effective_potential(theta: ArrayLike, R: float, G: float, a: float, b: float) -> FloatArray:
    """Effective potential W(θ) of the nutation, Serov (1991), eq. (1.6).

    W(θ) = (G − R cosθ)²/(2 sin²θ) + a cosθ + b cos²θ.

    Parameters
    ----------
    {{theta}}
    R, G : float
        Reduced angular momenta μr and K·e_z/A [1/time].
    a, b : float
        Moment coefficients of (1.5) [1/time²].

    Returns
    -------
    ndarray
        W [1/time²], shape of ``theta`` (0-d for a scalar).

    Raises
    ------
    ParameterError
        θ outside (0, π) or an input not finite (W is infinite at θ = 0, π unless G = ±R).
    """
    _finite(R=R, G=G, a=a, b=b)
    th = _theta_array(theta)
    u, s = np.cos(th), np.sin(th)
    return np.asarray((G - R * u) ** 2 / (2.0 * s * s) + a * u + b * u * u, dtype=float)


@_DOC
def potential_slope(theta: ArrayLike, R: float, G: float, a: float, b: float) -> FloatArray:
    """Slope F(θ) = ∂W/∂θ of the effective potential, Serov (1991), eq. (2.1).

    F(θ) = (G − R cosθ)(R − G cosθ)/sin³θ − a sinθ − b sin2θ; θ'' + F = 0 is the nutation.

    Parameters
    ----------
    {{theta}}
    {{constants}}

    Returns
    -------
    ndarray
        F [1/time²], shape of ``theta``.

    Raises
    ------
    ParameterError
        θ outside (0, π) or an input not finite.
    """
    _finite(R=R, G=G, a=a, b=b)
    th = _theta_array(theta)
    u, s = np.cos(th), np.sin(th)
    return np.asarray((G - R * u) * (R - G * u) / s**3 - a * s - b * np.sin(2.0 * th), dtype=float)


@_DOC
def energy(
    theta: ArrayLike, theta_dot: ArrayLike, R: float, G: float, a: float, b: float
) -> FloatArray:
    """Energy integral E = θ'²/2 + W(θ), Serov (1991), eq. (1.6).

    Parameters
    ----------
    {{theta}}
    theta_dot : array_like
        Nutation rate θ' [rad/time].
    {{constants}}

    Returns
    -------
    ndarray
        E [1/time²], broadcast shape of ``theta`` and ``theta_dot``.
    """
    td = finite_array("theta_dot", theta_dot)
    return np.asarray(0.5 * td * td + effective_potential(theta, R, G, a, b), dtype=float)


@_DOC
def quartic_coefficients(R: float, G: float, a: float, b: float, E: float) -> FloatArray:
    """Coefficients g0 … g4 of f(u) = u'² = Σ g_i u^i, Serov (1991), eq. (1.7).

    g0 = 2E − G², g1 = 2(GR − a), g2 = −2b − R² − 2E, g3 = 2a, g4 = 2b.

    Parameters
    ----------
    {{constants}}
    E : float
        Energy (1.6) [1/time²].

    Returns
    -------
    ndarray, shape (5,)
        (g0, g1, g2, g3, g4), ascending powers of u [1/time²].
    """
    _finite(R=R, G=G, a=a, b=b, E=E)
    return np.array(
        [2.0 * E - G * G, 2.0 * (G * R - a), -2.0 * b - R * R - 2.0 * E, 2.0 * a, 2.0 * b]
    )
