"""The Euler–Poinsot motion as a function of its invariants (L, T): regime, modulus k²,
period averages and fast frequencies, §8 of docs/theory/rotating-field.md (scalars, called at
every step of the averaged models). Conventions: :mod:`tumble.unperturbed.euler_poinsot`."""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from scipy import special

from tumble._docstrings import DocSections
from tumble._typing import ArrayLike, FloatArray
from tumble.bodies import proper_sorting
from tumble.errors import ParameterError, check_finite
from tumble.kernels.codes import DEGENERATE_RTOL, REACHED_MARGIN, SEPARATRIX_RTOL
from tumble.kernels.codes import MC_FLOOR as _MC_FLOOR

Regime = Literal["x3", "x1", "separatrix", "symmetric", "sphere", "rest"]

ENERGY_RTOL = 1e-9
"""(L, T) pairs may violate 2T·I1 ≤ L² ≤ 2T·I3 by this fraction of L² (round-off or an
integrator's step error at the pure rotations k2 = 0); they are clipped onto the range.
Larger violations describe no motion and raise :class:`~tumble.errors.ParameterError`."""

_DOC = DocSections(
    moments="""
    I1, I2, I3 : float
        Principal moments, I1 ≤ I2 ≤ I3 [inertia unit].
    """,
    state="""
    I1, I2, I3 : float
        Principal moments, I1 ≤ I2 ≤ I3 [inertia unit].
    L : float
        Angular momentum magnitude [inertia unit · rad/τ].
    T : float
        Kinetic energy [inertia unit · (rad/τ)²].
    """,
    states="""
    L, T : array_like
        Angular momentum magnitudes [inertia unit · rad/τ] and kinetic energies
        [inertia unit · (rad/τ)²], broadcasting.
    """,
)


def _check_sorted(I1: float, I2: float, I3: float) -> None:
    for name, value in (("I1", I1), ("I2", I2), ("I3", I3)):
        check_finite(f"inertia.{name}", value)
        if value <= 0.0:
            raise ParameterError(
                f"inertia.{name} = {value:g} is outside the allowed range (0, inf)"
            )
    if not I1 <= I2 <= I3:
        raise ParameterError(
            f"inertia = ({I1:g}, {I2:g}, {I3:g}) must be sorted, I1 ≤ I2 ≤ I3 (sorted axes)"
        )


def _symmetry(I1: float, I2: float, I3: float) -> str:
    """Degeneracy: "sphere", "x3" (I1 = I2, axis x3), "x1" (I2 = I3) or "" (triaxial)."""
    tol = DEGENERATE_RTOL * I3
    if I3 - I1 <= 2.0 * tol:
        return "sphere"
    if I2 - I1 <= tol:
        return "x3"
    if I3 - I2 <= tol:
        return "x1"
    return ""


def reached_ratio(I1: float, I2: float, I3: float, r: float) -> float:
    """A value of 2T/L² that an integration reached, brought back onto [1/I3, 1/I1].

    The ends of the range are the pure rotations about the axes of the largest and smallest
    moment, where the averaged solutions come to rest; an integrator's stage steps a little
    past them (by about its local error). Within :data:`REACHED_MARGIN` of the range the value
    is clipped onto it (the averaged rates there are those of the pure rotation: the solution
    rests at the end); farther it describes no motion and NaN is returned, so that the solver
    rejects the step rather than stopping the run with an input error.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments, ascending [inertia unit].
    r : float
        2T/L² [1/inertia unit].
    """
    lo, hi = 1.0 / I3, 1.0 / I1
    margin = REACHED_MARGIN * hi
    if not lo - margin <= r <= hi + margin:
        return math.nan
    return min(max(r, lo), hi)


def _classify(
    I1: float, I2: float, I3: float, L: float, T: float
) -> tuple[Regime, float, float, float]:
    """Regime and d1 = 1 − r·I1, d2 = 1 − r·I2, d3 = r·I3 − 1 with r = 2T/L², i.e. the
    differences L² − 2T·I1, L² − 2T·I2, 2T·I3 − L² over L² (scale-free: no underflow of
    L² for tiny states); d1, d3 clipped at 0."""
    _check_sorted(I1, I2, I3)
    check_finite("L", L)
    check_finite("T", T)
    if L < 0.0 or T < 0.0:
        raise ParameterError(f"L = {L:g}, T = {T:g}: both must be ≥ 0")
    if L == 0.0:
        if T != 0.0:
            raise ParameterError(f"T = {T:g} must be 0 when L = 0 (a body at rest)")
        return "rest", 0.0, 0.0, 0.0
    r = 2.0 * T / L / L
    d1, d2, d3 = 1.0 - r * I1, 1.0 - r * I2, r * I3 - 1.0
    if d1 < -ENERGY_RTOL or d3 < -ENERGY_RTOL:
        raise ParameterError(
            f"2T/L² = {r:g} is outside the allowed range [1/I3, 1/I1] = "
            f"[{1 / I3:g}, {1 / I1:g}] of a rigid body (L = {L:g}, T = {T:g})"
        )
    d1, d3 = max(d1, 0.0), max(d3, 0.0)
    sym = _symmetry(I1, I2, I3)
    if sym == "sphere":
        return "sphere", d1, d2, d3
    if sym:
        return "symmetric", d1, d2, d3
    if abs(d2) <= SEPARATRIX_RTOL:
        return "separatrix", d1, d2, d3
    return ("x3" if d2 > 0.0 else "x1"), d1, d2, d3


def _side_modulus(
    side: str, I1: float, I2: float, I3: float, d1: float, d2: float, d3: float
) -> tuple[float, float]:
    """(m, mc = 1 − m) of regime ``side`` ("x3": d2 ≥ 0, "x1": d2 ≤ 0), each from its own
    formula so that mc keeps its digits near the separatrix (§8 and correction C7). mc below
    _MC_FLOOR counts as 0 (K = R_F(0, mc, 1) overflows for subnormal mc)."""
    if side == "x3":
        den = (I3 - I2) * d1
        m, mc = (I2 - I1) * d3 / den, (I3 - I1) * d2 / den
    else:
        den = (I2 - I1) * d3
        m, mc = (I3 - I2) * d1 / den, -(I3 - I1) * d2 / den
    if mc < _MC_FLOOR:
        return 1.0, 0.0
    return min(max(m, 0.0), 1.0), min(mc, 1.0)


def _side(reg: Regime, I1: float, I2: float, I3: float, d2: float) -> str:
    """Which set of formulas applies: x3 (polar axis x3) or x1 (polar axis x1)."""
    if reg == "symmetric":
        return _symmetry(I1, I2, I3)
    if reg == "separatrix":
        return "x3" if d2 >= 0.0 else "x1"
    return reg


def _jacobi_means(m: float, mc: float) -> tuple[float, float]:
    """Period averages (⟨cn²⟩, ⟨dn²⟩) = ((E − mc K)/(m K), E/K), §8 "Period averages".

    Carlson forms K = R_F(0, mc, 1), E = 2 R_G(0, mc, 1), K − E = (m/3) R_D(0, mc, 1): no
    0/0 at m = 0 and no overflow at m = 1, where both averages vanish (E/K → 0).
    """
    if mc == 0.0:
        return 0.0, 0.0
    rf = float(special.elliprf(0.0, mc, 1.0))
    dn2 = 2.0 * float(special.elliprg(0.0, mc, 1.0)) / rf
    if m <= 0.5:
        cn2 = 1.0 - float(special.elliprd(0.0, mc, 1.0)) / (3.0 * rf)
    else:
        cn2 = (dn2 - mc) / m  # E/K ≫ mc near m = 1: no cancellation
    return cn2, dn2


def _pi_over_k(n: float, mc: float) -> float:
    """Π(n | m)/K(m) for n ≤ 0; its limit 1/(1 − n) at m = 1 (both integrals diverge)."""
    if mc == 0.0:
        return 1.0 / (1.0 - n)
    rf = float(special.elliprf(0.0, mc, 1.0))
    return 1.0 + n / 3.0 * float(special.elliprj(0.0, mc, 1.0, 1.0 - n)) / rf


def _characteristic(side: str, I1: float, I2: float, I3: float) -> float:
    """n of ψ̇ = L/I_c ± L(I3 − I1)/(I1 I3) / (1 − n sn²u); independent of k (§8)."""
    if side == "x3":
        return -I3 * (I2 - I1) / (I1 * (I3 - I2)) if I2 != I1 else 0.0
    return -I1 * (I3 - I2) / (I3 * (I2 - I1)) if I2 != I3 else 0.0


def _u_rate(side: str, I1: float, I2: float, I3: float, d1: float, d3: float) -> float:
    """ν of (3.1): sqrt(d1 (I3 − I2)/(I1 I2 I3)), or with 1 ↔ 3 swapped (correction C7)."""
    if side == "x3":
        return math.sqrt(d1 * (I3 - I2) / (I1 * I2 * I3)) if I2 != I3 else 0.0
    return math.sqrt(d3 * (I2 - I1) / (I1 * I2 * I3)) if I2 != I1 else 0.0


def _mean_precession(side: str, I1: float, I2: float, I3: float, L: float, mc: float) -> float:
    """ν2 = ⟨ψ̇⟩ = L/I3 + L(I3 − I1)/(I1 I3) Π(n|m)/K (x3); 1 ↔ 3 with a minus sign (x1)."""
    n = _characteristic(side, I1, I2, I3)
    ratio = _pi_over_k(n, mc)
    if side == "x3":
        return L / I3 + L * (I3 - I1) / (I1 * I3) * ratio
    return L / I1 - L * (I3 - I1) / (I1 * I3) * ratio


def regime(inertia_sorted: ArrayLike, L: float, T: float) -> Regime:
    """Regime of the Euler–Poinsot motion with given L and T (docs/theory/rotating-field.md §8,
    §16).

    Parameters
    ----------
    inertia_sorted : array_like, shape (3,)
        Principal moments I1 ≤ I2 ≤ I3 [inertia unit].
    L : float
        Angular momentum magnitude [inertia unit · rad/τ].
    T : float
        Kinetic energy ½ z·Iz [inertia unit · (rad/τ)²].

    Returns
    -------
    {"x3", "x1", "separatrix", "symmetric", "sphere", "rest"}
        See the module docstring; separatrix means |L² − 2T·I2| ≤ SEPARATRIX_RTOL·L².

    Raises
    ------
    ParameterError
        Moments not positive and sorted, or L² outside [2T·I1, 2T·I3] by more than
        ENERGY_RTOL·L².
    """
    I1, I2, I3 = (float(x) for x in np.asarray(inertia_sorted, dtype=float).reshape(3))
    return _classify(I1, I2, I3, float(L), float(T))[0]


@_DOC
def modulus_squared(I1: float, I2: float, I3: float, L: float, T: float) -> tuple[float, Regime]:
    """Modulus squared k² of (3.1) for the current regime, and the regime, §8 and correction C7.

    Regime x3 (L² > 2T·I2): k² = (I2 − I1)(2T·I3 − L²) / ((I3 − I2)(L² − 2T·I1)); regime x1:
    the same with indices 1 and 3 exchanged, k̃² = (I3 − I2)(L² − 2T·I1) /
    ((I2 − I1)(2T·I3 − L²)) = 1/k²_x3. Either way 0 ≤ k2 ≤ 1.

    Parameters
    ----------
    {{state}}

    Returns
    -------
    k2 : float
        k² [1]: 1 on the separatrix; 0 for symmetric bodies, the sphere and rest (where
        k² carries no information).
    regime : str
        As :func:`regime`.
    """
    reg, d1, d2, d3 = _classify(I1, I2, I3, L, T)
    if reg in ("rest", "sphere", "symmetric"):
        return 0.0, reg
    if reg == "separatrix":
        return 1.0, reg
    return _side_modulus(reg, I1, I2, I3, d1, d2, d3)[0], reg


@_DOC
def modulus_squared_of_ratio(I1: float, I2: float, I3: float, r: ArrayLike) -> FloatArray:
    """:func:`modulus_squared` for many states at once, given by r = 2T/L² (k² depends on r
    only): the same regimes and formulas, vectorized, for r on [1/I3, 1/I1] (an averaged
    run's values; outside it the ends are taken).

    Parameters
    ----------
    {{moments}}
    r : array_like
        2T/L² [1/inertia unit].
    """
    _check_sorted(I1, I2, I3)
    r = np.asarray(r, dtype=float)
    if _symmetry(I1, I2, I3):
        return np.zeros_like(r)
    d1 = np.maximum(1.0 - r * I1, 0.0)
    d2 = 1.0 - r * I2
    d3 = np.maximum(r * I3 - 1.0, 0.0)
    x3 = d2 > 0.0
    # Each regime's m and mc over one denominator, positive on its side of the separatrix
    # (d1 > 0 where d2 > 0, d3 > 0 where d2 ≤ 0): no division by zero, one division each.
    den = np.where(x3, (I3 - I2) * d1, (I2 - I1) * d3)
    m = np.where(x3, (I2 - I1) * d3, (I3 - I2) * d1) / den
    mc = (I3 - I1) * np.abs(d2) / den
    k2 = np.clip(m, 0.0, 1.0)
    return np.where((np.abs(d2) <= SEPARATRIX_RTOL) | ~(mc >= _MC_FLOOR), 1.0, k2)


@_DOC
def modulus_squared_of_states(
    I1: float, I2: float, I3: float, L: ArrayLike, T: ArrayLike
) -> FloatArray:
    """:func:`modulus_squared` (k² alone) for many states (L, T) at once: by
    :func:`modulus_squared_of_ratio` of r = 2T/L², and 0 at rest (L = 0).

    Parameters
    ----------
    {{moments}}
    {{states}}
    """
    L, T = np.broadcast_arrays(np.asarray(L, dtype=float), np.asarray(T, dtype=float))
    moving = L > 0.0
    r = np.divide(2.0 * T, L * L, out=np.full(L.shape, 1.0 / I2), where=moving)
    return np.where(moving, modulus_squared_of_ratio(I1, I2, I3, r), 0.0)


@_DOC
def energy_from_modulus(
    I1: float, I2: float, I3: float, L: float, k2: float, regime: Regime
) -> float:
    """Kinetic energy from L and k², the "T substitution" of §8 (inverse of modulus_squared).

    Regime x3: 2T = L² [(I2 − I1) + k²(I3 − I2)] / I0, I0 = I3(I2 − I1) + I1(I3 − I2)k²;
    regime x1: the same with indices 1 and 3 exchanged; separatrix: 2T = L²/I2.

    Parameters
    ----------
    {{moments}}
    L : float
        Angular momentum magnitude [inertia unit · rad/τ].
    k2 : float
        Modulus squared of ``regime`` [1], 0 ≤ k2 ≤ 1 (ignored on the separatrix).
    regime : {"x3", "x1", "separatrix", "sphere", "rest"}
        Regime k2 belongs to.

    Returns
    -------
    float
        T [inertia unit · (rad/τ)²].

    Raises
    ------
    ParameterError
        k2 outside [0, 1]; ``regime`` "symmetric", or "x3"/"x1" for a body with two equal
        moments (k² ≡ 0 there and does not determine T); "sphere" for a non-spherical
        body; "rest" with L ≠ 0.
    """
    _check_sorted(I1, I2, I3)
    check_finite("L", L)
    if L < 0.0:
        raise ParameterError(f"L = {L:g} is outside the allowed range [0, inf)")
    check_finite("k2", k2)
    if not 0.0 <= k2 <= 1.0:
        raise ParameterError(f"k2 = {k2:g} is outside the allowed range [0, 1]")
    L2 = L * L
    if regime == "rest":
        if L != 0.0:
            raise ParameterError(f"regime = 'rest' needs L = 0, got L = {L:g}")
        return 0.0
    sym = _symmetry(I1, I2, I3)
    if regime == "sphere":
        if sym != "sphere":
            raise ParameterError(f"regime = 'sphere' needs I1 = I3, got ({I1:g}, {I2:g}, {I3:g})")
        return 0.5 * L2 / I1
    if regime == "separatrix":
        return 0.5 * L2 / I2
    if regime not in ("x3", "x1"):
        raise ParameterError(
            f"regime = {regime!r} is not one of 'x3', 'x1', 'separatrix', 'sphere', 'rest' "
            "(k² does not determine T for a symmetric body)"
        )
    if sym:
        raise ParameterError(
            f"inertia = ({I1:g}, {I2:g}, {I3:g}) has two equal moments: k² ≡ 0 and does not "
            "determine T (use the T-form of §10)"
        )
    if regime == "x3":
        return 0.5 * L2 * ((I2 - I1) + k2 * (I3 - I2)) / (I3 * (I2 - I1) + I1 * (I3 - I2) * k2)
    return 0.5 * L2 * ((I3 - I2) + k2 * (I2 - I1)) / (I1 * (I3 - I2) + I3 * (I2 - I1) * k2)


@_DOC
def mean_square_rate(I1: float, I2: float, I3: float, L: float, T: float) -> float:
    """Period average ⟨|z|²⟩ over the Euler–Poinsot motion, (3.6) with §8 "Degenerate inertia".

    Evaluated as ⟨z²⟩ = 2T/I2 + [(I2 − I1) ⟨z1²⟩ − (I3 − I2) ⟨z3²⟩]/I2 (from 2T = Σ I_i z_i²),
    which equals (3.6) in regime x3 and its 1 ↔ 3 swap in regime x1, stays well conditioned
    near the symmetric and spherical limits, and reduces to the symmetric-body formula
    z⊥² + z_c² for I1 = I2 or I2 = I3. Inside the separatrix band the formula of the side of
    L² − 2T·I2 is used with the actual modulus, so the value is continuous; at k = 1 it is
    2T/I2 (E/K = 0 there, evaluated without overflow). The approach to that value is only
    logarithmic, ∝ E/K ≈ 1/ln(4/k') (k' = sqrt(1 − k²)).

    Parameters
    ----------
    {{state}}

    Returns
    -------
    float
        ⟨z1² + z2² + z3²⟩ [(rad/τ)²]; L²/I² for a sphere, 0 at rest.
    """
    reg, d1, d2, d3 = _classify(I1, I2, I3, L, T)
    if reg == "rest":
        return 0.0
    if reg == "sphere":
        return L * L / (I2 * I2)
    side = _side(reg, I1, I2, I3, d2)
    m, mc = (0.0, 1.0) if reg == "symmetric" else _side_modulus(side, I1, I2, I3, d1, d2, d3)
    cn2, dn2 = _jacobi_means(m, mc)
    w1 = (I2 - I1) * d3 / (I1 * (I3 - I1))  # (I2 − I1) · max z1² / L²
    w3 = (I3 - I2) * d1 / (I3 * (I3 - I1))  # (I3 − I2) · max z3² / L²
    if side == "x3":  # z1 ∝ cn u, z3 ∝ dn u
        return 2.0 * T / I2 + L * (L * (w1 * cn2 - w3 * dn2)) / I2
    return 2.0 * T / I2 + L * (L * (w1 * dn2 - w3 * cn2)) / I2  # x1: z1 ∝ dn u, z3 ∝ cn u


@_DOC
def fast_frequencies(I1: float, I2: float, I3: float, L: float, T: float) -> tuple[float, float]:
    """Frequencies of the fast motion, §8 "Frequencies of the fast motion" (and §12).

    ν1 = 2πν/(4K) is the polhode frequency (angular frequency of z in body axes) and
    ν2 = ⟨ψ̇⟩ the mean precession rate of the body about L, in closed form
    ν2 = L/I3 + L(I3 − I1)/(I1 I3) · Π(n | k²)/K(k²), n = −I3(I2 − I1)/(I1(I3 − I2)) in
    regime x3, and ν2 = L/I1 − L(I3 − I1)/(I1 I3) · Π(ñ | k̃²)/K(k̃²),
    ñ = −I1(I3 − I2)/(I3(I2 − I1)) in regime x1.

    Parameters
    ----------
    {{state}}

    Returns
    -------
    nu1, nu2 : float
        [rad/τ]. Continuous across the separatrix, where ν1 → 0 (logarithmically) and
        ν2 → L/I2. At k = 0 they are the limits k → 0: ν1 = z3 ω0 with ω0 of (2.6) and
        ν2 = z3 (1 + ω0) in regime x3. Symmetric bodies: ν1 = |z_c (I_a − I_c)/I_a|,
        ν2 = L/I_a (regular precession). Sphere: (0, L/I); rest: (0, 0).
    """
    reg, d1, d2, d3 = _classify(I1, I2, I3, L, T)
    if reg == "rest":
        return 0.0, 0.0
    if reg == "sphere":
        return 0.0, L / I2
    side = _side(reg, I1, I2, I3, d2)
    nu = L * _u_rate(side, I1, I2, I3, d1, d3)  # d's are over L²
    if reg == "symmetric":
        return nu, _mean_precession(side, I1, I2, I3, L, 1.0)
    _, mc = _side_modulus(side, I1, I2, I3, d1, d2, d3)
    nu1 = 0.0 if mc == 0.0 else 0.5 * math.pi * nu / float(special.elliprf(0.0, mc, 1.0))
    return nu1, _mean_precession(side, I1, I2, I3, L, mc)


@_DOC
def fast_frequencies_of_states(
    I1: float, I2: float, I3: float, L: ArrayLike, T: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """:func:`fast_frequencies` for many states (L, T) at once, with the same operations in
    the same order on arrays (the validity checks evaluate it at every sample of a run).

    Parameters
    ----------
    {{moments}}
    {{states}}

    Returns
    -------
    nu1, nu2 : ndarray
        [rad/τ], of the broadcast shape: the values of :func:`fast_frequencies`.

    Raises
    ------
    ParameterError
        As :func:`fast_frequencies`, for the first state it refuses.
    """
    _check_sorted(I1, I2, I3)
    L, T = np.broadcast_arrays(np.asarray(L, dtype=float), np.asarray(T, dtype=float))
    rest = L == 0.0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        r = 2.0 * T / L / L
        d1, d2, d3 = 1.0 - r * I1, 1.0 - r * I2, r * I3 - 1.0
        refused = ~(np.isfinite(L) & np.isfinite(T)) | (L < 0.0) | (T < 0.0)
        refused |= np.where(rest, T != 0.0, (d1 < -ENERGY_RTOL) | (d3 < -ENERGY_RTOL))
        if np.any(refused):  # the scalar function's message for the first one
            i = np.unravel_index(int(np.argmax(refused)), L.shape)
            _classify(I1, I2, I3, float(L[i]), float(T[i]))
        d1, d3 = np.maximum(d1, 0.0), np.maximum(d3, 0.0)
        sym = _symmetry(I1, I2, I3)
        if sym == "sphere":
            return np.zeros(L.shape), np.where(rest, 0.0, L / I2)
        if sym:  # one side for every state, m = 0
            nu = L * (np.sqrt(d1 * (I3 - I2) / (I1 * I2 * I3)) if sym == "x3" else
                      np.sqrt(d3 * (I2 - I1) / (I1 * I2 * I3)))  # fmt: skip
            ratio = np.full(L.shape, _pi_over_k(_characteristic(sym, I1, I2, I3), 1.0))
            nu1, x3 = nu, np.full(L.shape, sym == "x3")
        else:
            x3 = d2 >= 0.0  # the side of a separatrix state too
            nu = L * np.where(x3, np.sqrt(d1 * (I3 - I2) / (I1 * I2 * I3)),
                              np.sqrt(d3 * (I2 - I1) / (I1 * I2 * I3)))  # fmt: skip
            den = np.where(x3, (I3 - I2) * d1, (I2 - I1) * d3)
            mc = np.where(x3, (I3 - I1) * d2 / den, -(I3 - I1) * d2 / den)
            mc = np.where(mc < _MC_FLOOR, 0.0, np.minimum(mc, 1.0))
            positive = np.where(mc > 0.0, mc, 1.0)  # R_F and R_J where mc > 0 only
            rf = special.elliprf(0.0, positive, 1.0)
            nu1 = np.where(mc == 0.0, 0.0, 0.5 * math.pi * nu / rf)
            n = np.where(x3, _characteristic("x3", I1, I2, I3), _characteristic("x1", I1, I2, I3))
            rj = special.elliprj(0.0, positive, 1.0, 1.0 - n)
            ratio = np.where(mc == 0.0, 1.0 / (1.0 - n), 1.0 + n / 3.0 * rj / rf)
        span = L * (I3 - I1) / (I1 * I3) * ratio
        nu2 = np.where(x3, L / I3 + span, L / I1 - span)
        return np.where(rest, 0.0, nu1), np.where(rest, 0.0, nu2)


def polhode_point(inertia: ArrayLike, L: float, T: float) -> FloatArray:
    """The body rate, in the axes of ``inertia``, where the Euler–Poinsot polhode of momentum
    L and energy T crosses the plane of the smallest and the largest moments (z2 = 0 in
    sorted axes, which every polhode of either regime does; Martynenko (1979), eq. (3.1) at
    sn = 0): z1² = (2T·I3 − L²)/(I1(I3 − I1)), z3² = (L² − 2T·I1)/(I3(I3 − I1)), both ≥ 0.
    For the sphere, L/I along the third sorted axis.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments, any order [inertia unit].
    L : float
        |L| > 0 [inertia unit · rad/τ].
    T : float
        Kinetic energy, 2T/L² within [1/I3, 1/I1] [inertia unit · (rad/τ)²].

    Returns
    -------
    ndarray, shape (3,)
        The body rate [rad/τ].
    """
    moments = np.asarray(inertia, dtype=float).reshape(3)
    I1, _, I3 = (float(v) for v in np.sort(moments))
    if I3 - I1 <= 2.0 * DEGENERATE_RTOL * I3:
        sorted_rate = np.array([0.0, 0.0, L / I3])
    else:
        sorted_rate = np.array([
            math.sqrt(max(2.0 * T * I3 - L * L, 0.0) / (I1 * (I3 - I1))),
            0.0,
            math.sqrt(max(L * L - 2.0 * T * I1, 0.0) / (I3 * (I3 - I1))),
        ])  # fmt: skip
    return np.asarray(proper_sorting(moments).T @ sorted_rate, dtype=float)
