"""Standard atmosphere for the entry descent: ICAO 1993 below 81.02 km, isothermal above.

Below ``H_MAX`` = 81 020 m every quantity comes from :class:`ambiance.Atmosphere` (ICAO
*Manual of the ICAO Standard Atmosphere*, Doc 7488, 3rd ed., 1993). An entry starts at
100–120 km, above that limit, so the table is continued by an **isothermal extension**: the
temperature stays at its value T_top at the limit, and the pressure follows hydrostatic
equilibrium with the inverse-square gravity g(h) = g0 (r0/(r0 + h))² of the standard,

    p(h) = p_top exp(-(g0/(R T_top)) (H(h) - H(H_MAX))),   H(h) = r0 h/(r0 + h),

H the geopotential height, R = 287.05287 J/(kg K), r0 = 6 356 766 m, g0 = 9.80665 m/s² (the
standard's own constants, read from :class:`ambiance.CONST`). Its local pressure scale height
is R T_top / g(h) ≈ 5.9 km at 81 km. Pressure, density and temperature are continuous at the
limit, and so is d(ln p)/dh; the lapse rate jumps from -2 K/km (-0.002 K per geopotential
metre) to 0, so the density scale height jumps by ≈ 6 % there. The extension gives
ρ(100 km) ≈ 6.3e-7 kg/m³ and ρ(120 km) ≈ 2.2e-8 kg/m³ (U.S. Standard Atmosphere 1976:
5.6e-7 and 2.2e-8) — good enough for the onset of the aerodynamic moment, not an upper-
atmosphere model.

:class:`ExponentialAtmosphere` is the isothermal exponential atmosphere ρ = ρ0 exp(-h/H) of
the Allen–Eggers ballistic-entry analysis, for closed-form checks.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Protocol

import ambiance
import numpy as np

from tumble._docstrings import DocSections
from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, check_range

__all__ = [
    "GAMMA_AIR",
    "H_MAX",
    "H_MIN",
    "R_AIR",
    "STANDARD",
    "AtmosphereModel",
    "ExponentialAtmosphere",
    "StandardAtmosphere",
    "density",
    "density_gradient",
    "pressure",
    "speed_of_sound",
    "temperature",
]

_C = ambiance.CONST
H_MIN: float = float(_C.h_min)
"""Lowest geometric altitude of the ICAO table [m] (-5004 m)."""
H_MAX: float = float(_C.h_max)
"""Highest geometric altitude of the ICAO table [m] (81 020 m); isothermal above."""
R_AIR: float = float(_C.R)
"""Specific gas constant of air in the ICAO standard [J/(kg K)]."""
GAMMA_AIR: float = float(_C.kappa)
"""Ratio of specific heats of air in the ICAO standard [1]."""
_G0 = float(_C.g_0)
_R0 = float(_C.r)


_DOC = DocSections(
    h="""
    Parameters
    ----------
    h : array_like
        Geometric altitude [m], ≥ H_MIN.
    """,
    bad_h="""
    Raises
    ------
    ParameterError
        If an altitude is below H_MIN or not finite.
    """,
)


def _geopotential(h: FloatArray | float) -> FloatArray | float:
    """Geopotential height H = r0 h/(r0 + h) [m] of geometric altitude h [m] (ICAO 1993)."""
    return _R0 * h / (_R0 + h)


def _altitudes(h: ArrayLike, field: str = "h") -> FloatArray:
    """Validate altitudes: finite and ≥ H_MIN; return them as a float array."""
    arr = np.asarray(h, dtype=float)
    bad = ~np.isfinite(arr) | (arr < H_MIN)
    if np.any(bad):
        i = int(np.flatnonzero(bad.ravel())[0])
        name = field if arr.ndim == 0 else f"{field}[{i}]"
        raise ParameterError(
            f"{name} = {arr.ravel()[i]:g} m is outside the allowed range [{H_MIN:g}, inf) m"
        )
    return arr


def _check_altitude(h: float) -> None:
    """Refuse one altitude below H_MIN or NaN, the scalar form of :func:`_altitudes`.

    Parameters
    ----------
    h : float
        Geometric altitude [m].

    Raises
    ------
    ParameterError
        If h < H_MIN or h is NaN.
    """
    if not h >= H_MIN:  # also catches NaN
        raise ParameterError(f"h = {h:g} m is outside the allowed range [{H_MIN:g}, inf) m")


def _top() -> tuple[float, float, float]:
    """Temperature [K], pressure [Pa] and geopotential height [m] at H_MAX (ICAO 1993)."""
    atm = ambiance.Atmosphere(H_MAX)
    return float(atm.temperature[0]), float(atm.pressure[0]), float(atm.H[0])


_T_TOP, _P_TOP, _HGP_TOP = _top()

# Layer table of ICAO 1993 (geopotential base height [m], base temperature [K], lapse rate
# [K/m], base pressure [Pa]) for the fast scalar path of ODE right-hand sides.
_LAYERS = [(float(r[0]), float(r[1]), float(r[2]), float(r[3])) for r in _C.LAYER_SPEC_PROP[:-1]]
_BASES = [row[0] for row in _LAYERS]
_KINKS = (
    *(
        float(_R0 * hb / (_R0 - hb))  # geopotential → geometric height
        for (hb, _, beta, _), (_, _, beta_prev, _) in zip(_LAYERS[1:], _LAYERS[:-1], strict=True)
        if beta != beta_prev
    ),
    H_MAX,
)


def _tp(h: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Temperature [K], pressure [Pa] and dT/dh [K/m] at validated altitudes h [m]."""
    low = h <= H_MAX
    t = np.full(h.shape, _T_TOP)
    p = np.empty(h.shape)
    dtdh = np.zeros(h.shape)
    if np.any(low):
        atm = ambiance.Atmosphere(h[low])
        t[low] = atm.temperature
        p[low] = atm.pressure
        beta = np.array([_LAYERS[int(i) - 1][2] for i in np.ravel(atm.layer_nums)])
        dtdh[low] = beta * (_R0 / (_R0 + h[low])) ** 2  # dT/dH · dH/dh
    high = ~low
    if np.any(high):
        hgp = _geopotential(h[high])
        p[high] = _P_TOP * np.exp(-_G0 * (hgp - _HGP_TOP) / (R_AIR * _T_TOP))
    return t, p, dtdh


@_DOC
def temperature(h: ArrayLike) -> FloatArray:
    """Air temperature of the ICAO 1993 standard atmosphere, isothermal above H_MAX.

    Parameters
    ----------
    h : array_like
        Geometric altitude [m], ≥ H_MIN = -5004 m.

    Returns
    -------
    ndarray
        Temperature [K], same shape as ``h``; T(H_MAX) ≈ 196.65 K above H_MAX.

    {{bad_h}}

    References
    ----------
    ICAO Doc 7488 (1993) via ``ambiance``; isothermal extension: module docstring.
    """
    arr = _altitudes(h)
    return _tp(arr)[0]


@_DOC
def pressure(h: ArrayLike) -> FloatArray:
    """Air pressure of the ICAO 1993 standard atmosphere, isothermal hydrostatic above H_MAX.

    {{h}}

    Returns
    -------
    ndarray
        Pressure [Pa], same shape as ``h``.

    {{bad_h}}

    References
    ----------
    ICAO Doc 7488 (1993) via ``ambiance``; above H_MAX
    p = p_top exp(-g0 (H - H_top)/(R T_top)) (hydrostatics of an isothermal layer, the same
    formula the standard uses for its isothermal layers).
    """
    arr = _altitudes(h)
    return _tp(arr)[1]


@_DOC
def density(h: ArrayLike) -> FloatArray:
    """Air density ρ = p/(R T) of the ICAO 1993 atmosphere with its isothermal extension.

    {{h}}

    Returns
    -------
    ndarray
        Density [kg/m³], same shape as ``h``; above H_MAX it decays with the local scale
        height R T_top / g(h) ≈ 5.9 km.

    {{bad_h}}

    References
    ----------
    ICAO Doc 7488 (1993) via ``ambiance``; extension: module docstring.
    """
    arr = _altitudes(h)
    t, p, _ = _tp(arr)
    return p / (R_AIR * t)


@_DOC
def density_gradient(h: ArrayLike) -> FloatArray:
    """Exact derivative dρ/dh of :func:`density` (one-sided at layer boundaries).

    Hydrostatics gives d(ln p)/dh = -g(h)/(R T), so dρ/dh = ρ (-g/(R T) - (dT/dh)/T) with
    dT/dh the layer's lapse rate times dH/dh = (r0/(r0 + h))².

    {{h}}

    Returns
    -------
    ndarray
        dρ/dh [kg/m⁴], same shape as ``h`` (the upper layer's value on a boundary).

    {{bad_h}}

    References
    ----------
    ICAO Doc 7488 (1993): hydrostatic equation and the layer lapse rates.
    """
    arr = _altitudes(h)
    t, p, dtdh = _tp(arr)
    rho = p / (R_AIR * t)
    g = _G0 * (_R0 / (_R0 + arr)) ** 2
    return rho * (-g / (R_AIR * t) - dtdh / t)


@_DOC
def speed_of_sound(h: ArrayLike) -> FloatArray:
    """Speed of sound a = sqrt(γ R T) of the ICAO 1993 atmosphere, isothermal above H_MAX.

    {{h}}

    Returns
    -------
    ndarray
        Speed of sound [m/s], same shape as ``h``.

    {{bad_h}}

    References
    ----------
    ICAO Doc 7488 (1993) via ``ambiance`` (γ = 1.4, R = 287.05287 J/(kg K)).
    """
    return np.sqrt(GAMMA_AIR * R_AIR * temperature(h))


def _density_scalar(h: float) -> float:
    """Density [kg/m³] at one altitude h [m] ≥ H_MIN, in plain floats for ODE right-hand sides.

    The same ICAO 1993 layer formulas as ``ambiance`` (they agree to rounding; the tests
    check it) at ~1 µs instead of ~400 µs per call.
    """
    _check_altitude(h)
    hgp = _R0 * h / (_R0 + h)
    if h > H_MAX:
        t = _T_TOP
        p = _P_TOP * math.exp(-_G0 * (hgp - _HGP_TOP) / (R_AIR * _T_TOP))
    else:
        i = min(max(bisect.bisect_right(_BASES, hgp) - 1, 0), len(_LAYERS) - 1)
        hb, tb, beta, pb = _LAYERS[i]
        t = tb + beta * (hgp - hb)
        if beta == 0.0:
            p = pb * math.exp(-_G0 * (hgp - hb) / (R_AIR * t))
        else:
            p = pb * (1.0 + beta / tb * (hgp - hb)) ** (-_G0 / (R_AIR * beta))
    return p / (R_AIR * t)


class AtmosphereModel(Protocol):
    """What the descent needs from an atmosphere (all SI; ``h`` geometric altitude [m]).

    References
    ----------
    Implemented by :class:`StandardAtmosphere` (ICAO 1993) and :class:`ExponentialAtmosphere`
    (Allen & Eggers, NACA Report 1381, 1958).
    """

    def density(self, h: ArrayLike) -> FloatArray:
        """Density [kg/m³]."""
        ...

    def density_gradient(self, h: ArrayLike) -> FloatArray:
        """dρ/dh [kg/m⁴]."""
        ...

    def speed_of_sound(self, h: ArrayLike) -> FloatArray:
        """Speed of sound [m/s]."""
        ...

    def density_at(self, h: float) -> float:
        """Density [kg/m³] at one altitude, fast (for ODE right-hand sides)."""
        ...

    @property
    def kinks(self) -> tuple[float, ...]:
        """Altitudes [m] where dρ/dh jumps; an ODE solver should restart there."""
        ...


@dataclass(frozen=True, slots=True)
class StandardAtmosphere:
    """The ICAO 1993 standard atmosphere with its isothermal extension (module docstring).

    References
    ----------
    ICAO Doc 7488, *Manual of the ICAO Standard Atmosphere*, 3rd ed. (1993), via ``ambiance``.
    """

    def density(self, h: ArrayLike) -> FloatArray:
        """Density [kg/m³] at geometric altitude h [m]; see :func:`density`."""
        return density(h)

    def density_gradient(self, h: ArrayLike) -> FloatArray:
        """dρ/dh [kg/m⁴] at geometric altitude h [m]; see :func:`density_gradient`."""
        return density_gradient(h)

    def speed_of_sound(self, h: ArrayLike) -> FloatArray:
        """Speed of sound [m/s] at geometric altitude h [m]; see :func:`speed_of_sound`."""
        return speed_of_sound(h)

    def density_at(self, h: float) -> float:
        """Density [kg/m³] at one geometric altitude h [m], fast scalar path."""
        return _density_scalar(h)

    @property
    def kinks(self) -> tuple[float, ...]:
        """Geometric altitudes [m] where the lapse rate changes (ρ is C⁰ with a dρ/dh jump).

        The ICAO layer bases at 11, 20, 32, 47, 51, 71 km geopotential and the start of the
        isothermal extension at H_MAX.
        """
        return _KINKS


STANDARD = StandardAtmosphere()
"""The default atmosphere of :func:`tumble.entry.descend`."""


@dataclass(frozen=True, slots=True)
class ExponentialAtmosphere:
    """Isothermal exponential atmosphere ρ(h) = ρ0 exp(-h/H_s).

    Its temperature is the isothermal one consistent with the scale height,
    T = g0 H_s / R (≈ 246 K for 7.2 km), which fixes the speed of sound. It is the model of the
    Allen–Eggers closed form for ballistic entry, used here for checks.

    Parameters
    ----------
    rho0 : float
        Density at h = 0 [kg/m³] (default: ICAO sea level, 1.225).
    scale_height : float
        Density scale height H_s [m] (default 7200, assumed: a round value between the
        ≈ 6–8 km scale heights of the standard atmosphere).

    References
    ----------
    H. J. Allen, A. J. Eggers, NACA Report 1381 (1958).
    """

    rho0: float = 1.225
    scale_height: float = 7200.0

    def __post_init__(self) -> None:
        check_range("atmosphere.rho0", self.rho0, low=0.0)
        check_range("atmosphere.scale_height", self.scale_height, low=0.0)

    def density(self, h: ArrayLike) -> FloatArray:
        """Density ρ0 exp(-h/H_s) [kg/m³] at altitude h [m] ≥ H_MIN (as the standard)."""
        return self.rho0 * np.exp(-_altitudes(h) / self.scale_height)

    def density_gradient(self, h: ArrayLike) -> FloatArray:
        """dρ/dh = -ρ/H_s [kg/m⁴] at altitude h [m]."""
        return -self.density(h) / self.scale_height

    def speed_of_sound(self, h: ArrayLike) -> FloatArray:
        """Speed of sound sqrt(γ g0 H_s) [m/s] of the isothermal gas, shaped like h [m]."""
        return np.full(np.shape(h), math.sqrt(GAMMA_AIR * _G0 * self.scale_height))

    @property
    def kinks(self) -> tuple[float, ...]:
        """None: the exponential atmosphere is smooth."""
        return ()

    def density_at(self, h: float) -> float:
        """Density [kg/m³] at one altitude h [m] ≥ H_MIN."""
        _check_altitude(h)
        return self.rho0 * math.exp(-h / self.scale_height)
