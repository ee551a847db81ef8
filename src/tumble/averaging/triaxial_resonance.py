"""The fast frequencies of a triaxial body and its nearest low-order resonance.

The rotating-field setting of Yu. G. Martynenko (1979), docs/theory/rotating-field.md: at
frozen (L, T) the Euler–Poinsot motion is quasi-periodic with the polhode frequency ν1 and
the mean precession rate ν2 about L (§8, "Frequencies of the fast motion"); the averages of
:func:`~tumble.averaging.triaxial.triaxial_average` assume that no relation
m Ω_f = n1 ν1 + n2 ν2 of low order nearly holds (§10 "Assumptions", §12). The functions here
find the nearest one, for one state or for many at once.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from tumble._typing import ArrayLike, FloatArray, IntArray
from tumble.errors import check_range
from tumble.torques import Torque
from tumble.unperturbed._checks import moments
from tumble.unperturbed.euler_poinsot import EulerPoinsot, fast_frequencies

__all__ = [
    "Relations",
    "Resonance",
    "nearest_relations",
    "nearest_resonance",
    "nearest_resonances",
    "precession_harmonic",
]


@dataclass(frozen=True)
class Resonance:
    """The fast frequencies at (L, T) and the nearest low-order resonance, §12.

    Attributes
    ----------
    nu1 : float
        Polhode frequency 2πν/(4K) [rad/τ].
    nu2 : float
        Mean precession rate about L [rad/τ].
    forcing : float
        Forcing frequency Ω_f = 2π/forcing_period [rad/τ]; 0 without forcing.
    m, n1, n2 : int
        The relation m Ω_f = n1 ν1 + n2 ν2 closest to holding (m ≥ 0; m = 0 is a
        commensurability of the free motion itself, which matters for attitude-dependent
        torques). (1, −1, 1) is the co-rotation of the rotating-field paper.
    detuning : float
        n1 ν1 + n2 ν2 − m Ω_f [rad/τ].
    relative : float
        |detuning| / Ω_ref, Ω_ref = Ω_f, or max(ν1, ν2) without forcing [1]. Averaging is
        trustworthy while this is large against √(ε/I) (§12).
    """

    nu1: float
    nu2: float
    forcing: float
    m: int
    n1: int
    n2: int
    detuning: float
    relative: float


def nearest_resonance(
    inertia: ArrayLike,
    L: float,
    T: float,
    forcing_period: float | None = None,
    *,
    max_harmonic: int = 2,
    max_order: int = 2,
) -> Resonance:
    """Fast frequencies ν1, ν2 (§8) and the nearest relation m Ω_f = n1 ν1 + n2 ν2 (§12).

    Searched over 0 ≤ m ≤ ``max_harmonic`` (m = 0 alone without forcing) and
    |n1|, |n2| ≤ ``max_order``, (n1, n2) ≠ (0, 0). Callers warn when ``relative`` is small;
    the averages of :func:`~tumble.averaging.triaxial.triaxial_average` assume it is not.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments, any order [inertia unit].
    L : float
        Angular momentum magnitude [inertia unit · rad/τ].
    T : float
        Kinetic energy [inertia unit · (rad/τ)²].
    forcing_period : float, optional
        Period of the torque's explicit time dependence [τ].
    max_harmonic, max_order : int
        Largest m and |n1|, |n2| (§12 watches m ∈ {1, 2}, |n2| ≤ 2).

    Returns
    -------
    Resonance
    """
    Is = np.sort(moments(inertia))
    nu1, nu2 = fast_frequencies(float(Is[0]), float(Is[1]), float(Is[2]), float(L), float(T))
    found = nearest_resonances(np.array([nu1]), np.array([nu2]), forcing_period,
                               max_harmonic=max_harmonic, max_order=max_order)  # fmt: skip
    return found[0]


def _relations(harmonics: int, max_order: int) -> FloatArray:
    """The relations (m, n1, n2) searched, in a fixed order (the first of equally near ones
    wins): 0 ≤ m < ``harmonics``, |n1|, |n2| ≤ ``max_order``, (n1, n2) ≠ (0, 0), and one of
    ±(n1, n2) for m = 0."""
    orders = range(-max_order, max_order + 1)
    rows = [(m, n1, n2) for m, n1, n2 in itertools.product(range(harmonics), orders, orders)
            if (n1, n2) != (0, 0) and not (m == 0 and (n1, n2) < (0, 0))]  # fmt: skip
    return np.array(rows, dtype=float)


class Relations(NamedTuple):
    """The nearest relation at each of many states, as arrays of one shape (the fields of
    :class:`Resonance`, the forcing a scalar)."""

    m: IntArray
    n1: IntArray
    n2: IntArray
    detuning: FloatArray
    relative: FloatArray
    forcing: float


def nearest_relations(
    nu1: FloatArray,
    nu2: FloatArray,
    forcing_period: float | None = None,
    *,
    max_harmonic: int = 2,
    max_order: int = 2,
) -> Relations:
    """:func:`nearest_resonance` at many states at once, from their fast frequencies ν1, ν2
    (arrays of one shape) [rad/τ]: one vectorised search, the same relation chosen, as
    arrays (the validity checks scan every sample of a run)."""
    nu1, nu2 = np.asarray(nu1, dtype=float).ravel(), np.asarray(nu2, dtype=float).ravel()
    if forcing_period is None:
        forcing, harmonics = 0.0, 1
        ref = np.maximum(nu1, np.abs(nu2))
    else:
        check_range("forcing_period", forcing_period, low=0.0)
        forcing, harmonics = 2.0 * math.pi / forcing_period, max_harmonic + 1
        ref = np.full(nu1.shape, forcing)
    rel = _relations(harmonics, max_order)
    det = rel[:, 1, None] * nu1 + rel[:, 2, None] * nu2 - rel[:, 0, None] * forcing
    # A sphere (ν1 = 0) has no polhode phase to be commensurate: relations with n1 ≠ 0 drop.
    det = np.where((nu1 == 0.0) & (rel[:, 1, None] != 0.0), np.inf, det)
    best = np.argmin(np.abs(det), axis=0)
    d = det[best, np.arange(best.size)]
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = np.where(ref > 0.0, np.abs(d) / ref, math.inf)
    chosen = rel[best].astype(int)
    return Relations(chosen[:, 0], chosen[:, 1], chosen[:, 2], d, relative, forcing)


def nearest_resonances(
    nu1: FloatArray,
    nu2: FloatArray,
    forcing_period: float | None = None,
    *,
    max_harmonic: int = 2,
    max_order: int = 2,
) -> list[Resonance]:
    """:func:`nearest_relations` as one :class:`Resonance` per state."""
    nu1, nu2 = np.asarray(nu1, dtype=float).ravel(), np.asarray(nu2, dtype=float).ravel()
    r = nearest_relations(nu1, nu2, forcing_period, max_harmonic=max_harmonic,
                          max_order=max_order)  # fmt: skip
    fields = zip(r.m.tolist(), r.n1.tolist(), r.n2.tolist(), r.detuning.tolist(),
                 r.relative.tolist(), strict=True)  # fmt: skip
    return [
        Resonance(float(a), float(b), r.forcing, m, n1, n2, d, rel)
        for a, b, (m, n1, n2, d, rel) in zip(nu1, nu2, fields, strict=True)
    ]


HARMONIC_SAMPLES = 512
"""Samples of one polhode period for :func:`precession_harmonic`: the trapezoidal rule on a
periodic analytic integrand, converged to round-off for the harmonics k ≤ 8 up to
|1 − k²| ≈ 1e-3 (the edge of the separatrix band; checked at twice the samples in the
tests)."""


def precession_harmonic(
    torque: Torque, inertia: ArrayLike, omega: ArrayLike, k: int, samples: int = HARMONIC_SAMPLES
) -> complex:
    """The harmonic of a torque of the body rate alone that turns L secularly at the resonance
    ν2 = k ν1 of the free motion through ``omega``.

    Under a torque M(ω) the rates of |L| and T read the polhode phase alone, but the
    direction of L turns at A M, which also reads the precession angle ψ about L. In the frame
    of L (L along its third axis) its part across L is c = e^{iψ} w(polhode phase), and with
    ψ = ν2 t + a periodic part, c e^{−iν2 t} is periodic in the polhode period 2π/ν1:

        c(t) = Σ_m g_m e^{i(ν2 + m ν1) t}.

    Averaging keeps none of these terms. Where ν2 + m ν1 = 0, at m = −k sgn ν2, the term
    g_m stands still: passing that resonance at the rate Ω̇ of the detuning Ω = ν2 + m ν1
    kicks L across itself by |g_m| √(2π/|Ω̇|) (the stationary phase of
    ∫ g_m e^{iΩ̇ s²/2} ds), O(√ε) for a torque of size ε, in a direction set by the phase
    at the passage (Neishtadt's passage through resonance;
    docs/theory/separatrix-crossing.md §5).

    Parameters
    ----------
    torque : Torque
        A torque of the body rate alone (:attr:`~tumble.torques.Torque.rate_only`), with its
        size [moment unit].
    inertia : array_like, shape (3,)
        Principal moments in the user's axes [inertia unit].
    omega : array_like, shape (3,)
        A body rate on the polhode (any point: the harmonic's size does not depend on it)
        [rad/time].
    k : int
        The order of the resonance ν2 = k ν1, k ≥ 1.
    samples : int
        Samples of one polhode period.

    Returns
    -------
    complex
        g_m, m = −k sgn ν2 [moment unit]; 0 for a motion without a polhode phase (a pure
        rotation, a sphere). Its phase is relative to ``omega``'s point of the polhode (and
        to a frame of L fixed by the identity attitude there): only |g_m| is meaningful.

    Raises
    ------
    ValueError
        A torque that reads the attitude or the time, or k < 1.
    """
    from tumble.averaging.triaxial_second import _polhode_frames  # not at start-up

    if not torque.rate_only:
        raise ValueError("precession_harmonic: the torque reads the attitude or the time")
    if k < 1:
        raise ValueError(f"precession_harmonic: k = {k} must be at least 1")
    motion = EulerPoinsot.from_state(inertia, omega)
    if not (motion.nu1 > 0.0 and math.isfinite(motion.nu1)):
        return 0j
    t = np.arange(samples) * (2.0 * math.pi / motion.nu1 / samples)
    # body → L-frame is Rz(ψ) C: the moment across L, less the precession's ν2 t, is
    # e^{i(ψ − ν2 t)} (C M)_{1 + i2}
    omega, C, periodic = _polhode_frames(motion, t)
    w = np.einsum("nij,nj->ni", C, np.asarray(torque(0.0, None, omega), dtype=float))
    m = -k if motion.nu2 >= 0.0 else k
    h = (w[:, 0] + 1j * w[:, 1]) * np.exp(1j * periodic - 1j * m * motion.nu1 * t)
    return complex(np.mean(h))
