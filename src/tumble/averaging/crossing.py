"""Crossing the separatrix of the Euler–Poinsot motion under a small torque: into which rotation
a triaxial body passes.

On the sphere ‖L‖ = const the free motion circulates about the axis of least inertia (x1,
regions "x1+" and "x1−" by the sign of its component) when h = T − L²/(2 I2) > 0, and about
the axis of largest inertia (x3, "x3+" and "x3−") when h < 0 (I1 < I2 < I3, sorted axes).
The four regions are bounded by four separatrix arcs joining the saddles ±L x̂2/I2 (the
intermediate axis); the arc (s1, s3) lies where sign ω1 = s1 and sign ω3 = s3 and separates
"x1 s1" from "x3 s3". On it (2T I2 = L²)

    ω1 = s1 a sech λt,  ω3 = s3 b sech λt,  ω2 = s1 s3 (L/I2) tanh λt,
    a² = L² (I3 − I2) / (I1 I2 (I3 − I1)),  b² = L² (I2 − I1) / (I3 I2 (I3 − I1)),
    λ = (I3 − I1) a b / L.

A small torque M(ω) changes h at ḣ = Σᵢ ωᵢ Mᵢ (1 − Iᵢ/I2) (h is a first integral of the free
motion, zero on the separatrix). The body leaves its region through one of the region's two
arcs; which one depends on its phase when it reaches the separatrix, and over phases spread
uniformly (what any slight uncertainty of the initial state or of the torque makes them after
a slow evolution of 1/ε) the probability of each arc is its share of the flux out of the
region (Neishtadt, *Prikl. Mat. Mekh.* 51(5), 1987; Cary, Escande and Tennyson, *Phys. Rev. A*
34, 1986): with Θ = −∫ ḣ dt along the arc's whole motion (for a region with h > 0; +∫ ḣ dt for
h < 0), P = max(Θ, 0) / (Θ_first + Θ_second) over the region's arcs with Θ > 0.

A torque of the body rate alone (a damper, drag, a body-fixed moment) gives ḣ along the arc
directly; ḣ vanishes at the saddles and the integrand decays like sech λt, which the
trapezoidal rule in λt integrates to round-off (the integrand is analytic in a strip of
half-width π/2). A torque that reads the attitude (or the time) also depends on the
precession angle χ about L, a third phase spread as uniformly as the polhode's: the fluxes are
then those of the phase volume, averaged over χ (and over the forcing phase of an explicit
periodic time dependence), at the direction of L and the time of the crossing. In inertial
axes ḣ = (Ω − L_ξ/I2)·M_ξ, the integrand of the triaxial engine's dr/dτ at r = 1/I2, on the
engine's grid A = F Rz(χ) G(t) (:mod:`tumble.averaging.triaxial`), refined in χ and the
forcing phase until the fluxes settle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.bodies import proper_sorting
from tumble.errors import ParameterError
from tumble.torques import Torque

__all__ = [
    "REGIONS",
    "Crossing",
    "averaged_crossing",
    "first_crossing",
    "separatrix_crossing",
    "separatrix_motion",
]

REGIONS = ("x1+", "x1-", "x3+", "x3-")
"""The regions of the Euler–Poinsot motion on the sphere ‖L‖ = const (sorted axes): rotation
about the axis of least inertia with ω1 of either sign, about the axis of largest with ω3 of
either sign."""

_SPAN = 40.0  # λt from −40 to 40: sech 40 = 8.5e-18
_STEP = 0.125  # the trapezoidal rule's error ~ exp(−π²/step) for a pole at iπ/2


def _sorted(inertia: ArrayLike) -> tuple[FloatArray, FloatArray]:
    moments = np.asarray(inertia, dtype=float)
    if moments.shape != (3,) or not np.all(moments > 0.0):
        raise ParameterError(f"inertia = {moments.tolist()} must be three positive moments")
    Q = proper_sorting(moments)
    i1, i2, i3 = np.abs(Q) @ moments  # Q diag(I) Qᵀ: the reversed axis keeps its moment
    if not (i1 < i2 < i3) or min(i2 - i1, i3 - i2) <= 1e-12 * i3:
        raise ParameterError(
            f"inertia = {moments.tolist()}: a separatrix needs three different moments"
        )
    return Q, np.array([i1, i2, i3])


def separatrix_motion(inertia: ArrayLike, L: float, s1: int, s3: int, t: ArrayLike) -> FloatArray:
    """The body rate ω(t) [rad/time, the user's body axes] on the separatrix arc (s1, s3) of
    the free motion with ‖L‖ = ``L``, t = 0 midway between the saddles (module notes).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments, three different ones, in the user's body axes [inertia unit].
    L : float
        ‖L‖ > 0 [inertia unit · rad/time].
    s1, s3 : {1, -1}
        The signs of ω1 and ω3 (sorted axes) on the arc.
    t : array_like
        Times [time].

    Returns
    -------
    ndarray, shape (n, 3)
    """
    Q, (i1, i2, i3) = _sorted(inertia)
    u = np.atleast_1d(np.asarray(t, dtype=float)) * _rate(i1, i2, i3, L)
    return _arc(i1, i2, i3, L, s1, s3, u) @ Q


def _amplitudes(i1: float, i2: float, i3: float, L: float) -> tuple[float, float]:
    a = L * math.sqrt((i3 - i2) / (i1 * i2 * (i3 - i1)))
    b = L * math.sqrt((i2 - i1) / (i3 * i2 * (i3 - i1)))
    return a, b


def _rate(i1: float, i2: float, i3: float, L: float) -> float:
    a, b = _amplitudes(i1, i2, i3, L)
    return (i3 - i1) * a * b / L


def _arc(i1: float, i2: float, i3: float, L: float, s1: int, s3: int, u: FloatArray) -> FloatArray:
    """ω in the sorted axes on the arc (s1, s3) at λt = u."""
    a, b = _amplitudes(i1, i2, i3, L)
    sech = 1.0 / np.cosh(u)
    return np.stack([s1 * a * sech, s1 * s3 * (L / i2) * np.tanh(u), s3 * b * sech], axis=1)


@dataclass(frozen=True)
class Crossing:
    """Where a body that reaches the separatrix from one region goes.

    Attributes
    ----------
    start : str
        The region it leaves (:data:`REGIONS`).
    probabilities : dict
        Each region it may enter → its probability (summing to 1).
    fluxes : dict
        Each of the two arcs out of ``start``, by the region beyond it → Θ, how much the motion
        along the arc changes h = T − L²/(2 I2), counted positive where the torque drives the
        body across it [energy unit].
    """

    start: str
    probabilities: dict[str, float]
    fluxes: dict[str, float]


def separatrix_crossing(
    torque: Torque,
    inertia: ArrayLike,
    L: float,
    start: str,
    *,
    direction: ArrayLike | None = None,
    t: float = 0.0,
    forcing_period: float | None = None,
) -> Crossing:
    """The probability of each rotation a body leaving region ``start`` passes into, under a
    small ``torque`` (module notes).

    Parameters
    ----------
    torque : Torque
        The moment in body axes (the user's), evaluated at the separatrix motion; its size
        sets the fluxes, not the probabilities.
    inertia : array_like, shape (3,)
        Principal moments in the user's body axes, three different ones [inertia unit].
    L : float
        ‖L‖ at the crossing [inertia unit · rad/time].
    start : str
        The region the body leaves, one of :data:`REGIONS` (sorted axes: x1 is the axis of
        least inertia).
    direction : array_like, shape (3,), optional
        The inertial direction of L at the crossing (any length), for a torque that reads the
        attitude or the time; unused for one of the body rate alone.
    t : float
        The time of the crossing [time]: the one at which a slowly varying torque (an
        orbiting body's orbit-averaged terms) is evaluated, and the origin of the forcing
        phase.
    forcing_period : float, optional
        The period of the torque's explicit time dependence [time], averaged over.

    Returns
    -------
    Crossing

    Raises
    ------
    ParameterError
        An unknown region, two equal moments, a torque that reads the attitude or the time
        without ``direction``, or a torque that does not drive the body out of ``start`` (both
        fluxes ≤ 0).
    """
    if start not in REGIONS:
        raise ParameterError(f"start = {start!r} must be one of " + ", ".join(REGIONS))
    if not (L > 0.0 and math.isfinite(L)):
        raise ParameterError(f"L = {L!r} must be a positive number")
    if not torque.rate_only and direction is None:
        raise ParameterError(
            "separatrix_crossing: the torque reads the attitude or the time: give the "
            "direction of L at the crossing (direction = L_xi)"
        )
    Q, (i1, i2, i3) = _sorted(inertia)
    sign = 1 if start.endswith("+") else -1
    # The two arcs out of the region, each by the region beyond it.
    if start.startswith("x1"):
        arcs = {"x3+": (sign, 1), "x3-": (sign, -1)}
        out_of = -1.0  # h > 0 in x1: leaving means h falls
    else:
        arcs = {"x1+": (1, sign), "x1-": (-1, sign)}
        out_of = 1.0
    u = np.arange(-_SPAN, _SPAN + 0.5 * _STEP, _STEP)
    factors = 1.0 - np.array([i1, i2, i3]) / i2
    fluxes = {}
    for beyond, (s1, s3) in arcs.items():
        omega = _arc(i1, i2, i3, L, s1, s3, u)  # sorted axes
        if torque.rate_only:
            moment = np.asarray(torque(0.0, None, omega @ Q), dtype=float) @ Q.T  # sorted axes
            h_rate = np.sum(omega * moment * factors, axis=1)
        else:
            assert direction is not None  # required above
            h_rate = _attitude_h_rate(torque, np.asarray(inertia, dtype=float), omega @ Q,
                                      i2, L, direction, t, forcing_period)  # fmt: skip
        fluxes[beyond] = out_of * float(np.sum(h_rate)) * _STEP / _rate(i1, i2, i3, L)
    driving = {k: max(v, 0.0) for k, v in fluxes.items()}
    total = sum(driving.values())
    if not total > 0.0:
        raise ParameterError(
            f"separatrix_crossing: the torque does not drive the body out of {start} (its "
            f"fluxes through the two arcs are {fluxes['x3+' if 'x3+' in fluxes else 'x1+']:.3g} "
            f"and {fluxes['x3-' if 'x3-' in fluxes else 'x1-']:.3g})"
        )
    return Crossing(start, {k: v / total for k, v in driving.items()}, fluxes)


_CHI_START, _CHI_MAX = 8, 4096  # precession nodes: doubled until the flux settles
_SETTLED = 1e-5  # … to this part of ∫|⟨ḣ⟩| dt along the arc (a torque with kinks in the
# attitude, sunlight's lit facets, converges algebraically; the probabilities need far less)


def _attitude_h_rate(
    torque: Torque,
    I_user: FloatArray,
    omega: FloatArray,
    i2: float,
    L: float,
    direction: ArrayLike,
    t: float,
    forcing_period: float | None,
) -> FloatArray:
    """⟨ḣ⟩ over the precession angle χ (and the forcing phase) at each body rate ``omega``
    (user axes, shape (n, 3)) of an arc: ḣ = (Ω − L_ξ/I2)·M_ξ on the triaxial engine's grid
    A = F Rz(χ) G, F the frame of L_ξ = L·direction, G taking the body direction of L to the
    third axis (module notes). The nodes of χ (and of the forcing phase, as many) are doubled
    from :data:`_CHI_START` until the flux (their sum along the arc) settles to
    :data:`_SETTLED` of the sum of their sizes."""
    from tumble.averaging.triaxial import (
        _frame_with_third_column,
        _polhode_attitudes,
        _precessions,
    )
    from tumble.averaging.triaxial_grid import _Grid, _Moment
    from tumble.rotations import matrix_to_quat

    d = np.asarray(direction, dtype=float).reshape(3)
    size = float(np.linalg.norm(d))
    if not (size > 0.0 and math.isfinite(size)):
        raise ParameterError(f"direction = {d.tolist()} must be a finite nonzero vector")
    L_xi = L * d / size
    F = _frame_with_third_column(L_xi)
    q_F = matrix_to_quat(F)
    w, G, Gw, q_G = _polhode_attitudes(lambda _: omega, I_user)(np.zeros(len(omega)))
    moment = _Moment(torque, None)
    forced = forcing_period is not None

    def means(n: int) -> FloatArray:
        FRz, q_z = _precessions(F)(2.0 * math.pi * np.arange(n) / n)
        Omega = np.matmul(FRz[None], Gw[:, None, :, None])[..., 0]  # (n0, n, 3)
        rates = w[:, None, :]
        if forced:
            assert forcing_period is not None
            tt = (t + forcing_period * np.arange(n) / n)[None, None, :]
            Omega, rates = Omega[:, :, None], rates[:, :, None]
        else:
            tt = np.asarray(t)
        grid = _Grid(FRz, G, rates, Omega, (lambda: q_F, q_z, q_G), forced)
        shape = np.broadcast_shapes(np.shape(tt), Omega.shape[:-1])
        M = np.broadcast_to(moment.inertial(tt, grid), (*shape, 3))
        h = np.sum((Omega - L_xi / i2) * M, axis=-1)
        return np.asarray(h.reshape(len(omega), -1).mean(axis=1), dtype=float)

    n = _CHI_START
    h = means(n)
    while n < _CHI_MAX:
        n *= 2
        finer = means(n)
        size = max(float(np.sum(np.abs(finer))), 1e-300)
        settled = abs(float(np.sum(finer - h))) <= _SETTLED * size
        h = finer
        if settled:
            return h
    raise ParameterError(
        f"separatrix_crossing: the torque's average over the precession does not settle on "
        f"{_CHI_MAX} nodes"
    )


def first_crossing(
    inertia: ArrayLike, t: ArrayLike, omega: ArrayLike, depth: float = 0.0
) -> tuple[float, float, str, str] | None:
    """The first crossing of the separatrix in samples of a motion: its time, ‖L‖ there, the
    region left and the region entered (:data:`REGIONS`); None if the samples never cross.

    Under a torque h = T − L²/(2 I2) oscillates about its slow course by about the flux Θ of a
    passage (:func:`separatrix_crossing`), so a motion near the separatrix may cross it and
    come back within a lap. A region counts as entered once h is past the separatrix by
    ``depth``; the crossing's time and ‖L‖ are those of the last change of sign of h before.
    The region entered is told by the sign of its axis's rate there (fixed within a region).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments, the user's body axes, three different ones [inertia unit].
    t : array_like, shape (n,)
        Sample times [time].
    omega : array_like, shape (n, 3)
        The body rate at those times, the user's body axes [rad/time].
    depth : float
        How far past the separatrix, in h [energy unit], the motion must go: above the
        oscillation of h (the flux Θ of a passage, of the torque's size), below the depth the
        motion reaches within the samples.
    """
    Q, (i1, i2, i3) = _sorted(inertia)
    times = np.asarray(t, dtype=float)
    w = np.asarray(omega, dtype=float) @ Q.T  # sorted axes
    moments = np.array([i1, i2, i3])
    L = np.linalg.norm(w * moments, axis=1)
    h = 0.5 * np.sum(moments * w * w, axis=1) - L * L / (2.0 * i2)
    side = math.copysign(1.0, float(h[0]))
    past = np.flatnonzero(side * h < -depth) if h[0] != 0.0 else np.empty(0, dtype=int)
    if not past.size:
        return None
    k = int(past[0])
    before = np.flatnonzero(side * h[:k] > 0.0)
    at = int(before[-1]) + 1 if before.size else 0  # the last change of sign before k
    left_axis, entered_axis = (0, 2) if side > 0.0 else (2, 0)
    left = ("x1" if left_axis == 0 else "x3") + ("+" if np.median(w[:at, left_axis]) > 0 else "-")
    entered = ("x3" if entered_axis == 2 else "x1") + ("+" if w[k, entered_axis] > 0 else "-")
    return float(times[at]), float(L[at]), left, entered


def averaged_crossing(
    inertia: ArrayLike, t: ArrayLike, L_xi: ArrayLike, T: ArrayLike
) -> tuple[float, FloatArray] | None:
    """Where samples of an averaged run first cross the separatrix: the time and the inertial
    L there, from the first change of sign of r − 1/I2 (r = 2T/‖L‖²), interpolated linearly
    between its two samples; None if they never cross.

    An averaged run crosses once, on its slow course, and cannot say into which rotation: that
    is :func:`separatrix_crossing`'s probability at this L (its norm, and its direction for a
    torque of the attitude), the averaged counterpart of :func:`first_crossing`.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments, three different ones [inertia unit].
    t : array_like, shape (n,)
        Sample times [time].
    L_xi : array_like, shape (n, 3)
        The inertial angular momentum at those times [inertia unit · rad/time].
    T : array_like, shape (n,)
        The kinetic energy at those times [inertia unit · rad²/time²].

    Returns
    -------
    (float, ndarray of shape (3,)) or None
        The time [time] and L there [inertia unit · rad/time].
    """
    _, (_, i2, _) = _sorted(inertia)
    times = np.asarray(t, dtype=float)
    L = np.asarray(L_xi, dtype=float)
    s = 2.0 * np.asarray(T, dtype=float) * i2 - np.sum(L * L, axis=1)  # ∝ r − 1/I2
    changed = np.flatnonzero(np.sign(s[1:]) != np.sign(s[:-1]))
    if not changed.size:
        return None
    k = int(changed[0])
    w = s[k] / (s[k] - s[k + 1])
    return float(times[k] + w * (times[k + 1] - times[k])), (1.0 - w) * L[k] + w * L[k + 1]
