"""Averaging any torque over the Euler–Poinsot motion of a triaxial body.

The rotating-field setting of Yu. G. Martynenko (1979), docs/theory/rotating-field.md. For a
small body-axes moment ``M = torque(t, q, ω)`` the exact rates of the slow variables are

* ``dL_ξ/dτ = A(q) M`` (Euler's law in inertial axes, the vector form of §10), and
* ``dT/dτ = ω·M`` (the power balance of §4),

with L_ξ the inertial components of the angular momentum and T the kinetic energy. At frozen
(L_ξ, T) the unperturbed motion is the Euler–Poinsot motion (3.1) of §8: quasi-periodic with
the polhode frequency ν1 and the mean precession rate ν2 about L (§8, "Frequencies of the
fast motion"). In the non-resonant case (§10 "Assumptions", §12) the time average is the
average over a 2-torus: the polhode phase (τ over one period 4K/ν of the Jacobi functions)
and an independent precession angle χ about L. The attitude on it is ``F Rz(χ) G(τ)``, G a
rotation taking the body direction of L to the third axis and F one taking that axis to
L_ξ/L; the free motion's own precession angle ψ(τ) only shifts χ, so it drops out and only
the body rates z(τ) of (3.1) over one period are needed. A torque with explicit periodic
time dependence (the rotating field, (1.1)) adds a third independent phase: the time
``t + s`` over one forcing period. That is how (3.5)–(3.7) average the field independently
of the body's phases (§10, "Field-phase average").

This is the engine for any torque (a user's Python function among them); a sum of built-in
torques or a numba function, on a triaxial or a symmetric body, runs the compiled twin,
:mod:`tumble.kernels.triaxial` (:func:`triaxial_kernel`), which refines its quadratures from
the same grids to the same limits (:mod:`tumble.kernels.limits`) and is tested against this
one.

Quadrature. A product periodic trapezoidal rule over the 2 or 3 phases, refined axis by
axis: each axis is doubled (the new nodes are the midpoints, so every value is computed
once) until the mean changes by at most ``rtol`` times the mean magnitude of the integrand,
per group of outputs, or by √(rtol/100) once the changes are seen to square from one
doubling to the next (geometric convergence; see :func:`_product_mean`). This replaces
:func:`~tumble.averaging.quadrature.torus_mean`, which doubles all phases together and
tests all outputs against one scale: the polhode phase needs 32–256 nodes (more near the
separatrix, where K grows like ln(1/k')), while the precession and forcing phases of the
usual torques are trigonometric polynomials of degree ≤ 2, exact with 8 nodes. For the
eddy-current torque an evaluation costs about 1.5–3 ms (k² ≤ 0.9999; 5–8 ms closer to the
separatrix), for the gravity gradient 2–5 ms (benchmarks/averaging_cost.py).

Torques on arrays. The built-in torques of :mod:`tumble.torques` are evaluated here on the
whole grid at once, with arrays that broadcast over the phases (time included); any other
torque is called with the package's batched convention (q of shape (N, 4), omega (N, 3),
one time per call), checked against one-state calls, or one state at a time if it does not
follow it (see :class:`~tumble.averaging.triaxial_grid._Moment` and the ``batched``
argument).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy import special

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.quadrature import AveragingError
from tumble.averaging.triaxial_grid import _Grid, _Moment, _rotate
from tumble.averaging.triaxial_resonance import (
    Resonance,
    nearest_resonance,
    nearest_resonances,
)
from tumble.bodies import proper_sorting
from tumble.errors import ParameterError, TumbleWarning, check_finite, check_range
from tumble.kernels import (
    KIND_TRIAXIAL_AVERAGED,
    KIND_TRIAXIAL_CLOSED,
    KIND_TRIAXIAL_PHASE_MEANS,
    Kernel,
)
from tumble.kernels.codes import DEGENERATE_RTOL
from tumble.kernels.limits import (
    AVERAGE_RTOL,
    MAX_GRID,
    MOMENTUM_FLOOR,
    PHASE_MAX,
    PHASE_START,
    POLHODE_MAX,
    POLHODE_START,
    SQUARING_SAFETY,
)
from tumble.kernels.params import TRIAXIAL_AVERAGED
from tumble.kernels.terms import term_of
from tumble.rotations import matrix_to_quat
from tumble.unperturbed._checks import finite_vector, moments
from tumble.unperturbed.euler_poinsot import (
    SEPARATRIX_RTOL,
    EulerPoinsot,
    polhode_point,
    reached_ratio,
    regime,
)
from tumble.unperturbed.euler_poinsot.motion import _frame_with_third_row

__all__ = [
    "AVERAGE_RTOL",
    "MAX_GRID",
    "MOMENTUM_FLOOR",
    "Resonance",
    "branch_kernel",
    "nearest_resonance",
    "nearest_resonances",
    "rotation_sense",
    "sense_turn",
    "triaxial_average",
    "triaxial_average_stage",
    "triaxial_average_vector",
    "triaxial_kernel",
]

_N_START = {"polhode": POLHODE_START, "precession": PHASE_START, "forcing": PHASE_START}
"""First numbers of nodes (:mod:`tumble.kernels.limits`, shared with the compiled engine)."""

_N_MAX = {"polhode": POLHODE_MAX, "precession": PHASE_MAX, "forcing": PHASE_MAX}


# ---------------------------------------------------------------------------------------------
# Product trapezoidal rule, refined axis by axis.


@dataclass(frozen=True)
class _Axis:
    """One fast phase: ``make(phases) -> node data`` (arrays with the node axis first)."""

    name: str
    make: Callable[[FloatArray], tuple[FloatArray, ...]]
    n_start: int
    n_max: int


def _phases(n: int, offset: float) -> FloatArray:
    return (np.arange(n, dtype=np.float64) + offset) * (2.0 * math.pi / n)


def _product_mean(
    axes: Sequence[_Axis],
    integrand: Callable[..., FloatArray],
    groups: Sequence[tuple[slice, int]],
    rtol: float,
    what: str,
) -> tuple[FloatArray, tuple[int, ...]]:
    """Mean of ``integrand`` over the product torus of ``axes``, refined axis by axis.

    ``integrand(*data)`` (one data tuple per axis) returns an array (channels, n0, n1, …).
    Each group ``(components, magnitude)`` names a slice of channels and the channel that
    holds the size of their integrand (|M| for instance). An axis is accepted when doubling
    its nodes changes every group's mean by at most ``rtol`` times the mean of its
    magnitude channel: relative to the integrand's size, so the test is meaningful where the
    mean vanishes or comes from cancellation. The doubled result is the one returned.

    Squaring shortcut. For an analytic periodic integrand the error of n nodes is ~C ρⁿ,
    so the error of 2n nodes is ~(error of n)²/C: about change², with change = |I_2n − I_n|
    relative to the integrand's size. I_2n is then accepted once
    ``SQUARING_SAFETY·change² ≤ rtol``, provided the last two changes themselves squared
    (``change ≤ SQUARING_SAFETY·previous²``), which algebraic convergence (a torque with a
    kink) never shows; such integrands fall back to the plain test ``change ≤ rtol``.
    """
    n = [ax.n_start for ax in axes]
    data = [ax.make(_phases(ax.n_start, 0.0)) for ax in axes]
    red = tuple(range(1, len(axes) + 1))
    mean = integrand(*data).mean(axis=red)
    shortcut = math.sqrt(rtol / SQUARING_SAFETY)
    for i, ax in enumerate(axes):
        done = n[i] >= ax.n_max  # a frozen phase (one node) is not refined
        previous = math.inf
        while not done:
            if 2 * n[i] > ax.n_max or 2 * math.prod(n) > MAX_GRID:
                raise AveragingError(
                    f"{what} did not converge to rtol = {rtol:g} with "
                    f"{'×'.join(map(str, n))} nodes (the {ax.name} phase at its limit; last "
                    f"change {previous:.1e} of the integrand's size): the integrand is nearly "
                    "singular on the motion (separatrix) or not smooth (a kink in the torque)"
                )
            fresh = ax.make(_phases(n[i], 0.5))
            new = 0.5 * (mean + integrand(*data[:i], fresh, *data[i + 1 :]).mean(axis=red))
            change = max(
                float(np.max(np.abs(new[g] - mean[g]))) / float(new[c]) if new[c] > 0.0 else 0.0
                for g, c in groups
            )
            # Plain test, or the squaring shortcut once the sequence shows it: two changes at
            # least (the first doubling has nothing to square).
            squaring = math.isfinite(previous) and change <= SQUARING_SAFETY * previous**2
            done = change <= rtol or (change <= shortcut and squaring)
            data[i] = tuple(np.concatenate([a, b]) for a, b in zip(data[i], fresh, strict=True))
            n[i] *= 2
            mean, previous = new, change
    return mean, tuple(n)


# ---------------------------------------------------------------------------------------------
# The unperturbed motion at frozen slow variables.


def _check_inputs(
    inertia: ArrayLike, L_xi: ArrayLike, forcing_period: float | None, rtol: float
) -> tuple[FloatArray, FloatArray, float]:
    I_user = moments(inertia)
    Lv = finite_vector("L_xi", L_xi)
    check_range("rtol", rtol, low=0.0, high=1.0)
    if forcing_period is not None:
        check_range("forcing_period", forcing_period, low=0.0)
    omega_ref = 1.0 if forcing_period is None else 2.0 * math.pi / forcing_period
    L = float(np.linalg.norm(Lv))
    floor = MOMENTUM_FLOOR * float(np.max(I_user)) * omega_ref
    if not L > floor:
        raise AveragingError(
            f"|L_xi| = {L:g} is at or below {floor:g} (L → 0): the fast frequencies vanish "
            "and averaging over the Euler–Poinsot motion is undefined "
            "(docs/theory/rotating-field.md §12)"
        )
    return I_user, Lv, L


_SCIPY_MC_FLOOR = 1e-9
"""Below this 1 − k², scipy's ``ellipj`` switches to an expansion in 1 − k² that is good only
to O(1 − k²) near u = K; the body rates then come from :class:`EulerPoinsot`, whose Jacobi
functions are Newton-polished (§8, accurate for any 1 − k² > 0)."""


def _polhode(
    I_user: FloatArray, L: float, T: float, branch: float = 1.0
) -> tuple[Callable[[FloatArray], FloatArray], bool]:
    """Body angular velocity (3.1) over one polhode period, as a function of the phase, in
    the sense of rotation ``branch`` (+1: its component along the encircled sorted axis
    positive; −1: the image with the sn and dn components negated, :func:`sense_turn`).

    Returns ``(rates, periodic)``: ``rates(phases)`` gives z (user axes, shape (n, 3)) at
    τ = phase·period/2π, and ``periodic`` is False for the sphere (z constant; the polhode
    phase is then not averaged over).

    Triaxial bodies with 1 − k² ≥ :data:`_SCIPY_MC_FLOOR`: (3.1) with scipy's Jacobi
    functions in sorted axes, u uniform over [0, 4K) (regime x3: z = (a_cn cn u, a_sn sn u,
    a_dn dn u); regime x1: indices 1 and 3 exchanged, every root of a product of positive
    factors, correction C7), K of the same floating-point parameter as ``ellipj`` so that the
    nodes span exactly its period. This skips building an :class:`EulerPoinsot` (1.3 ms, a
    third of an evaluation), whose attitude the average does not need. Otherwise (symmetric
    bodies, the sphere, 1 − k² < floor): :class:`EulerPoinsot` from a state on the polhode
    where it crosses z2 = 0 (sorted axes; every polhode of either regime does): there
    z1² = (2T·I3 − L²)/(I1(I3 − I1)) and z3² = (L² − 2T·I1)/(I3(I3 − I1)).

    Raises
    ------
    AveragingError
        In the separatrix band |L² − 2T·I2| ≤ SEPARATRIX_RTOL·L² (§8, §12).
    ParameterError
        2T/L² outside [1/I3, 1/I1] (beyond ENERGY_RTOL).
    """
    Is = np.sort(I_user)
    I1, I2, I3 = (float(x) for x in Is)
    reg = regime(Is, L, T)
    if reg == "separatrix":
        d2 = (L * L - 2.0 * T * I2) / (L * L)
        raise AveragingError(
            f"(L² − 2T·I2)/L² = {d2:.3g} is within ±{SEPARATRIX_RTOL:g} (separatrix, 1 − k² → "
            "0): the polhode period is infinite and averaging is undefined (§12)"
        )
    Q = proper_sorting(I_user)  # v_sorted = Q v_user, so a row z_user = z_sorted @ Q
    r = 2.0 * T / (L * L)
    d1, d2, d3 = max(1.0 - r * I1, 0.0), 1.0 - r * I2, max(r * I3 - 1.0, 0.0)  # over L²
    if reg == "x3":
        m, mc = (I2 - I1) * d3 / ((I3 - I2) * d1), (I3 - I1) * d2 / ((I3 - I2) * d1)
        a_cn = math.sqrt(d3 / (I1 * (I3 - I1)))
        a_sn = math.sqrt(d3 / (I2 * (I3 - I2)))
        a_dn = math.sqrt(d1 / (I3 * (I3 - I1)))
        cols = (0, 1, 2)  # sorted components of (cn, sn, dn)
    elif reg == "x1":
        m, mc = (I3 - I2) * d1 / ((I2 - I1) * d3), -(I3 - I1) * d2 / ((I2 - I1) * d3)
        a_cn = math.sqrt(d1 / (I3 * (I3 - I1)))
        a_sn = math.sqrt(d1 / (I2 * (I2 - I1)))
        a_dn = math.sqrt(d3 / (I1 * (I3 - I1)))
        cols = (2, 1, 0)
    if reg in ("x3", "x1") and mc >= _SCIPY_MC_FLOOR:
        m = min(max(m, 0.0), 1.0 - _SCIPY_MC_FLOOR)
        to_u = 4.0 * float(special.ellipk(m)) / (2.0 * math.pi)
        amp = np.zeros((3, 3))  # rows: cn, sn, dn → sorted components, times L
        for row, (col, a) in enumerate(zip(cols, (a_cn, a_sn, a_dn), strict=True)):
            amp[row, col] = L * a

        if branch < 0.0:
            amp[1:] *= -1.0  # the rows of sn and dn

        def jacobi(phases: FloatArray) -> FloatArray:
            sn, cn, dn, _ = special.ellipj(phases * to_u, m)
            return np.asarray(np.stack([cn, sn, dn], -1) @ amp @ Q, dtype=float)

        return jacobi, True

    with warnings.catch_warnings():
        # The band test above is on (L, T); the state rounds L² − 2T·I2 anew.
        warnings.simplefilter("error", TumbleWarning)
        try:
            ep = EulerPoinsot.from_state(I_user, polhode_point(I_user, L, T))
        except TumbleWarning as w:
            raise AveragingError(f"{w} (state L = {L:g}, T = {T:g})") from None
    if not math.isfinite(ep.period):  # the sphere: uniform rotation about L
        return (lambda phases: np.broadcast_to(ep.z0, (len(phases), 3)).copy()), False
    to_tau = ep.period / (2.0 * math.pi)
    flip = sense_turn(I_user, L, T, branch)
    return (lambda phases: ep.omega(phases * to_tau) @ flip), True


def sense_turn(inertia: ArrayLike, L: float, T: float, branch: float) -> FloatArray:
    """The rotation (user axes; symmetric, so it acts on rows as on columns) that takes a
    motion of the sense +1 at momentum L and energy T (such as that through
    :func:`~tumble.unperturbed.euler_poinsot.polhode_point`) to the one of sense ``branch``
    (:func:`rotation_sense`): the identity, or the turn by π about the sorted axis across
    the encircled one and the sn component (the third in regime x1, the first in x3; a
    symmetric body encircles its symmetry axis).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments in the user's order [inertia unit].
    L, T : float
        ‖L‖ [inertia unit · rad/τ] and the kinetic energy [inertia unit · (rad/τ)²].
    branch : {1.0, -1.0}

    Returns
    -------
    ndarray, shape (3, 3)
    """
    if _sense(branch) > 0.0:
        return np.eye(3)
    I_user = np.asarray(inertia, dtype=float).reshape(3)
    Q = proper_sorting(I_user)
    signs = [1.0, -1.0, -1.0] if _encircles_third(I_user, L * L, 2.0 * T) else [-1.0, -1.0, 1.0]
    return np.asarray(Q.T @ np.diag(signs) @ Q, dtype=float)


def _encircles_third(I_user: FloatArray, L2: float, T2: float) -> bool:
    """Whether the polhode of L² = ``L2``, 2T = ``T2`` encircles the third sorted axis (regime
    x3, or a body with I1 = I2) rather than the first, as :func:`tumble.kernels.triaxial.
    _polhode` decides it (the sphere: the third)."""
    I1, I2, I3 = sorted(I_user.tolist())
    tol = DEGENERATE_RTOL * I3
    low, high = I2 - I1 <= tol, I3 - I2 <= tol
    return low or (L2 - T2 * I2 > 0.0 and not high)


def _frame_with_third_column(v: FloatArray) -> FloatArray:
    """A rotation matrix whose third column is v/|v|: the transpose of the Euler–Poinsot
    motion's frame with that third row (C-ordered, as the products on the grid expect)."""
    return np.ascontiguousarray(_frame_with_third_row(v).T)


class _Prefetched:
    """An axis' ``make`` that evaluates ``n`` nodes in one call and serves the nested grids
    of 16, 32, … nodes from them (one kernel call instead of one per doubling)."""

    def __init__(self, make: Callable[[FloatArray], tuple[FloatArray, ...]], n: int) -> None:
        self._make, self._n = make, n
        self._data: tuple[FloatArray, ...] | None = None

    def __call__(self, phases: FloatArray) -> tuple[FloatArray, ...]:
        idx = phases * (self._n / (2.0 * math.pi))
        k = np.rint(idx)
        if np.max(np.abs(idx - k), initial=0.0) > 1e-9:
            return self._make(phases)
        if self._data is None:
            self._data = self._make(_phases(self._n, 0.0))
        return tuple(a[k.astype(int)] for a in self._data)


def _means(
    torque: Any,
    I_user: FloatArray,
    Lv: FloatArray,
    L: float,
    T: float,
    t: float,
    forcing_period: float | None,
    rtol: float,
    groups: Sequence[tuple[slice, int]],
    batched: bool | None,
    branch: float = 1.0,
) -> tuple[FloatArray, tuple[int, ...]]:
    """Means of [A M (3), ω·M, (ω − r Iω)·M] over the fast phases; nodes per phase.

    Attitude on the torus: ``A(τ, χ) = F Rz(χ) G(τ)``. G(τ) is a rotation whose third row is
    the body direction of L, ℓ_b = I z(τ)/L (body → a frame with L third), Rz(χ) the
    precession about L, F a fixed rotation with F e3 = L_ξ/L. The free motion's own
    precession angle ψ(τ) only shifts χ, which is averaged uniformly over the circle, so it
    drops out: the torus needs z(τ) over one polhode period and nothing else. G = Rx(θ) Rz(φ)
    with ℓ_b = (sin θ sin φ, sin θ cos φ, cos θ) (the 3-1-3 angles of §8, in user axes).
    In inertial axes ω − r Iω is Ω_ξ − r L_ξ (A Iω = L_ξ), so inertial-form torques need no A.
    """
    check_finite("t", t)
    rates, periodic = _polhode(I_user, L, T, branch)
    r = 2.0 * T / (L * L)
    forced = forcing_period is not None
    F = _frame_with_third_column(Lv)
    q_F_cache: list[FloatArray] = []

    def q_F() -> FloatArray:
        if not q_F_cache:
            q_F_cache.append(matrix_to_quat(F))
        return q_F_cache[0]

    polhode = _polhode_attitudes(rates, I_user)
    precession = _precessions(F)

    n_pre = 4 * _N_START["polhode"]
    axes = [
        _Axis("polhode", _Prefetched(polhode, n_pre), _N_START["polhode"], _N_MAX["polhode"])
        if periodic
        else _Axis("polhode", polhode, 1, 1),
        _Axis("precession", precession, _N_START["precession"], _N_MAX["precession"]),
    ]
    if forcing_period is not None:
        P = float(forcing_period)

        def forcing(phases: FloatArray) -> tuple[FloatArray, ...]:
            return (t + phases * (P / (2.0 * math.pi)),)

        axes.append(_Axis("forcing", forcing, _N_START["forcing"], _N_MAX["forcing"]))

    rL = r * Lv
    moment = _Moment(torque, batched)

    def integrand(pol: tuple[FloatArray, ...], pre: tuple[FloatArray, ...], *rest: Any) -> Any:
        w, G, Gw, q_G = pol
        FRz, q_z = pre
        Omega = np.matmul(FRz[None], Gw[:, None, :, None])[..., 0]  # (n0, n1, 3) = A ω
        w = w[:, None, :]
        if forced:
            w, Omega = w[:, :, None], Omega[:, :, None]
            tt = rest[0][0][None, None, :]
        else:
            tt = np.asarray(t)
        grid = _Grid(FRz, G, w, Omega, (q_F, q_z, q_G), forced)
        shape = np.broadcast_shapes(tt.shape, Omega.shape[:-1])
        M = np.broadcast_to(moment.inertial(tt, grid), (*shape, 3))
        out = np.empty((7, *shape))
        out[:3] = np.moveaxis(M, -1, 0)
        out[3] = np.sum(Omega * M, axis=-1)  # ω·M_body = Ω_ξ·M_ξ
        out[4] = np.sum((Omega - rL) * M, axis=-1)  # (ω − r Iω)·M
        # Magnitudes for the convergence test: |M|, and |Ω||M|, the size of the products
        # ω·M and (ω − r Iω)·M before their cancellations (their round-off level).
        out[5] = np.sqrt(np.sum(M * M, axis=-1))
        out[6] = out[5] * np.sqrt(np.sum(Omega * Omega, axis=-1))
        return out

    return _product_mean(axes, integrand, groups, rtol, "the average over the Euler–Poinsot motion")


def _polhode_attitudes(
    rates: Callable[[FloatArray], FloatArray], I_user: FloatArray
) -> Callable[[FloatArray], tuple[FloatArray, ...]]:
    """At polhode phases: the body rate ω, G = Rx(θ) Rz(φ) taking the body direction of L to
    the third axis, G ω, and the quaternion of G."""

    def polhode(phases: FloatArray) -> tuple[FloatArray, ...]:
        w = rates(phases)  # (n, 3) body rate
        Lb = I_user * w
        theta = np.arctan2(np.hypot(Lb[:, 0], Lb[:, 1]), Lb[:, 2])
        phi = np.arctan2(Lb[:, 0], Lb[:, 1])
        ct, st, cp, sp = np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
        zero = np.zeros_like(theta)
        G = np.stack(
            [
                np.stack([cp, -sp, zero], -1),
                np.stack([ct * sp, ct * cp, -st], -1),
                np.stack([st * sp, st * cp, ct], -1),
            ],
            -2,
        )
        ch, sh = np.cos(0.5 * theta), np.sin(0.5 * theta)
        cf, sf = np.cos(0.5 * phi), np.sin(0.5 * phi)
        q_G = np.stack([ch * cf, sh * cf, -sh * sf, ch * sf], -1)  # q_x(θ) ⊗ q_z(φ)
        return w, G, _rotate(G, w), q_G

    return polhode


def _precessions(F: FloatArray) -> Callable[[FloatArray], tuple[FloatArray, ...]]:
    """At precession angles χ about L: F Rz(χ) and the quaternion of Rz(χ)."""

    def precession(phases: FloatArray) -> tuple[FloatArray, ...]:
        c, s = np.cos(phases), np.sin(phases)
        zero, one = np.zeros_like(c), np.ones_like(c)
        Rz = np.stack(
            [
                np.stack([c, -s, zero], -1),
                np.stack([s, c, zero], -1),
                np.stack([zero, zero, one], -1),
            ],
            -2,
        )
        q_z = np.stack([np.cos(0.5 * phases), zero, zero, np.sin(0.5 * phases)], -1)
        return F @ Rz, q_z

    return precession


# ---------------------------------------------------------------------------------------------
# Public entry points.

# Channels of the integrand of _means: A M (0–2), ω·M (3), (ω − r Iω)·M (4), |M| (5), |Ω||M| (6).
_GROUPS_T = ((slice(0, 3), 5), (slice(3, 4), 6))
_GROUPS_R = ((slice(0, 3), 5), (slice(4, 5), 6))


def triaxial_average(
    torque: Any,
    inertia: ArrayLike,
    L_xi: ArrayLike,
    T: float,
    t: float = 0.0,
    *,
    forcing_period: float | None = None,
    rtol: float = AVERAGE_RTOL,
    batched: bool | None = None,
    branch: float = 1.0,
) -> FloatArray:
    """Averaged rates (dL_ξ/dτ, dT/dτ) of a triaxial body under any small torque, §10.

    Averages ``dL_ξ/dτ = A(q) M`` and ``dT/dτ = ω·M`` (§4) over the Euler–Poinsot motion
    (3.1) with angular momentum L_ξ and energy T: the polhode phase (one period 4K/ν of the
    Jacobi functions) and the precession angle about L, independently (non-resonant, §10,
    §12), and, when ``forcing_period`` is given, the time t + s over one forcing period as a
    third independent phase. For the eddy-current torque (1.3) this is (3.5) and the
    corrected (3.6) (correction C5), in inertial components.

    Parameters
    ----------
    torque : Torque or callable
        ``torque(t, q, omega)`` → body moment [moment unit], q the attitude quaternion (scalar
        first, body → inertial), omega the body angular velocity [rad/τ]; see ``batched``.
        The quaternion's sign is not continuous over the grid: the torque must depend on the
        attitude only.
    inertia : array_like, shape (3,)
        Principal moments in the user's axis order [inertia unit] (any order; triangle
        inequality).
    L_xi : array_like, shape (3,)
        Inertial components of the angular momentum [inertia unit · rad/τ].
    T : float
        Kinetic energy ½ ω·Iω [inertia unit · (rad/τ)²], with 2T·I1 ≤ L² ≤ 2T·I3.
    t : float
        Time τ [1]: the frozen (slow) time without ``forcing_period``; with it, the start of
        the forcing period averaged over (immaterial for a purely periodic forcing).
    forcing_period : float, optional
        Period of the torque's explicit time dependence [τ] (2π/ω_field for the rotating
        field, 2π in the units of (1.5)); None: the time is frozen at ``t``.
    rtol : float
        Estimated error of the averages relative to the mean magnitude of their integrands,
        |M| for dL_ξ and |ω||M| for dT (a phase is accepted when doubling its nodes changes
        the mean by less; see :func:`_product_mean`) [1].
    batched : bool or None
        How a torque that is not a built-in of :mod:`tumble.torques` is called: True, with
        q of shape (N, 4) and omega of shape (N, 3) for N attitudes at one time, returning
        (N, 3) or (3,) (no check); None (default), the same checked against one-state calls at
        two nodes, else one state at a time; False, one state at a time, the built-ins too.
    branch : {1.0, -1.0}
        The sense of rotation about the axis the polhode encircles: +1, the body rate's
        component along it positive in the sorted axes of :func:`tumble.bodies.proper_sorting`
        (eq. (3.1) as written); −1, the other sense (:mod:`tumble.kernels.triaxial`, "the
        sense of rotation"). The state (L_ξ, T) is the same for both; a torque fixed in the
        body is not.

    Returns
    -------
    ndarray, shape (4,)
        ``[dL_ξ1, dL_ξ2, dL_ξ3]/dτ`` [moment unit] and ``dT/dτ`` [moment unit · rad/τ].

    Raises
    ------
    AveragingError
        L → 0 (|L_ξ| ≤ :data:`MOMENTUM_FLOOR`·max I·Ω_ref), the separatrix band
        |L² − 2T·I2| ≤ SEPARATRIX_RTOL·L², or no convergence within :data:`MAX_GRID` nodes.
    ParameterError
        Bad inertia, non-finite input, or 2T/L² outside [1/I3, 1/I1].

    Notes
    -----
    Near a resonance m Ω_f = n1 ν1 + n2 ν2 the true time average differs from this torus
    average; see :func:`nearest_resonance`.
    """
    I_user, Lv, L = _check_inputs(inertia, L_xi, forcing_period, rtol)
    check_finite("T", float(T))
    mean, _ = _means(torque, I_user, Lv, L, float(T), float(t), forcing_period, rtol, _GROUPS_T,
                     batched, _sense(branch))  # fmt: skip
    return np.asarray(mean[:4], dtype=float)


def rotation_sense(inertia: ArrayLike, omega: ArrayLike) -> float:
    """The sense of rotation (``branch``) of the body rate ``omega`` about the axis its
    polhode encircles: the sign of its component along that axis in the sorted axes of
    :func:`tumble.bodies.proper_sorting` (the largest moment's in regime x3, the smallest's in
    x1; the symmetry axis of a symmetric body), +1 where it is zero or undefined (the
    separatrix, the sphere, rest).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments in the user's order [inertia unit].
    omega : array_like, shape (3,)
        Body angular velocity in the same axes [rad/τ].

    Returns
    -------
    float
        +1.0 or −1.0.
    """
    I_user = np.asarray(inertia, dtype=float).reshape(3)
    w = proper_sorting(I_user) @ np.asarray(omega, dtype=float).reshape(3)
    Is = np.sort(I_user)
    tol = DEGENERATE_RTOL * Is[2]
    if Is[1] - Is[0] <= tol and Is[2] - Is[1] <= tol:
        return 1.0  # the sphere (as the kernel tells it): no axis to turn about
    L2, T2 = float(np.sum((Is * w) ** 2)), float(np.sum(Is * w * w))
    component = float(w[2] if _encircles_third(I_user, L2, T2) else w[0])
    return -1.0 if component < 0.0 else 1.0


def branch_kernel(kernel: Kernel | None, branch: float) -> Kernel | None:
    """``kernel`` (of :func:`triaxial_kernel`) with its sense of rotation set to ``branch``:
    the same program, one parameter changed (no packing)."""
    sense = _sense(branch)
    if kernel is None or kernel.params[_BRANCH] == sense:
        return kernel
    params = kernel.params.copy()
    params[_BRANCH] = sense
    return replace(kernel, params=params)


_BRANCH = TRIAXIAL_AVERAGED.at.branch


def _sense(branch: float) -> float:
    """``branch`` checked: +1 or −1."""
    if branch not in (1.0, -1.0):
        raise ParameterError(f"branch = {branch!r} is not a sense of rotation (allowed: 1, -1)")
    return float(branch)


def triaxial_average_vector(
    torque: Any,
    inertia: ArrayLike,
    y: ArrayLike,
    t: float = 0.0,
    *,
    forcing_period: float | None = None,
    rtol: float = AVERAGE_RTOL,
    batched: bool | None = None,
    branch: float = 1.0,
) -> FloatArray:
    """:func:`triaxial_average` in the state ``[L_ξ, r = 2T/L²]`` of the vector form, §10.

    ``dr/dτ = 2 ⟨(ω − r Iω)·M⟩ / L²`` (from r′ = 2(T′ − r L_ξ·L_ξ′)/L² and Iω·M = L_ξ·A M),
    averaged as one integrand: ω − r Iω vanishes on a pure rotation, so there is no
    cancellation between T′ and L′ near k² = 0. For the eddy-current torque this is
    ``rotating_field.averaged_rhs_vector``.

    Parameters
    ----------
    torque : Torque or callable
        As in :func:`triaxial_average`.
    inertia : array_like, shape (3,)
        Principal moments, any order [inertia unit].
    y : array_like, shape (4,)
        ``[L_ξ1, L_ξ2, L_ξ3, r]`` [inertia unit · rad/τ, 1/inertia unit], 1/I3 ≤ r ≤ 1/I1.
    t : float
        Time τ [1], as in :func:`triaxial_average`.
    forcing_period : float, optional
        Period of the explicit time dependence [τ].
    rtol : float
        As in :func:`triaxial_average`; the magnitude for dr/dτ is |ω||M| [1].
    batched : bool or None
        As in :func:`triaxial_average`.
    branch : {1.0, -1.0}
        As in :func:`triaxial_average`.

    Returns
    -------
    ndarray, shape (4,)
        ``[dL_ξ/dτ (3), dr/dτ]`` [moment unit, 1/(inertia unit · τ)].

    Raises
    ------
    AveragingError, ParameterError
        As :func:`triaxial_average`.
    """
    yv = np.asarray(y, dtype=float).reshape(-1)
    if yv.shape != (4,):
        raise ParameterError(f"y must be [L_xi1, L_xi2, L_xi3, r], got {yv.size} values")
    I_user, Lv, L = _check_inputs(inertia, yv[:3], forcing_period, rtol)
    r = float(yv[3])
    check_finite("r", r)
    T = 0.5 * r * L * L
    mean, _ = _means(torque, I_user, Lv, L, T, float(t), forcing_period, rtol, _GROUPS_R, batched,
                     _sense(branch))  # fmt: skip
    return np.array([*mean[:3], 2.0 * mean[4] / (L * L)])


def triaxial_average_stage(
    torque: Any,
    inertia: ArrayLike,
    y: FloatArray,
    t: float,
    forcing_period: float | None,
    branch: float = 1.0,
) -> FloatArray:
    """:func:`triaxial_average_vector` at a stage of an integrator, ``y = [L_ξ, r]``: an r past
    the range [1/I3, 1/I1] a rigid body reaches by no more than the solver's local error is
    moved into it (:func:`~tumble.unperturbed.euler_poinsot.reached_ratio`), one further
    beyond gives NaN rates, so that the solver rejects the step.

    The parameters and the rates returned are those of :func:`triaxial_average_vector`
    (``forcing_period`` None: no explicit time dependence; ``branch`` the sense of
    rotation), or NaN.
    """
    I1, I2, I3 = sorted(float(v) for v in np.asarray(inertia, dtype=float).reshape(3))
    r = reached_ratio(I1, I2, I3, float(y[3]))
    if math.isnan(r):
        return np.full(4, math.nan)  # past a pure rotation: the solver rejects the step
    state = np.array([y[0], y[1], y[2], r])
    return triaxial_average_vector(torque, inertia, state, t, forcing_period=forcing_period,
                                   branch=branch)  # fmt: skip


_PERIOD_RTOL = 1e-9
"""How close to a whole number the forcing period must be in periods of each time-dependent
term for the compiled engine (which averages each term over its own period)."""


def triaxial_kernel(
    torque: Any,
    inertia: ArrayLike,
    forcing_period: float | None = None,
    *,
    factor: float = 1.0,
    rtol: float = AVERAGE_RTOL,
    branch: float = 1.0,
) -> Kernel | None:
    """:func:`triaxial_average_vector` compiled (:mod:`tumble.kernels.triaxial`), times
    ``factor``; None where only the Python engine applies. Its separatrix r = 1/I2 is the
    compiled event ``EVENT_TRIAXIAL_SEPARATRIX``.

    A program of constant moments, linear drag, the gravity gradient and the orbit-averaged
    field and gravity moments is averaged in closed form (:mod:`tumble.kernels.
    triaxial_closed`, exact to round-off). For other built-in terms the compiled engine
    averages each time-dependent term over its own phase in closed form and the precession
    on four nodes, which is exact for them, and refines the polhode phase with the Python
    engine's test; a user's numba function
    (:mod:`tumble.kernels.user`), or a term of higher degree in the precession
    (:attr:`~tumble.kernels.terms.base.Term.precession_degree`) without its closed form, gets
    the Python engine's product rule on all phases.

    Parameters
    ----------
    torque : Torque or callable
        The moment; compiled when every term is built in or a numba function
        (:attr:`Torque.program`).
    inertia : array_like, shape (3,)
        Principal moments, any order [inertia unit].
    forcing_period : float, optional
        Period of the explicit time dependence [τ]; every time-dependent term's period must
        divide it.
    factor : float
        Multiplies the rates (the ε of a model whose torque is given without it) [1].
    rtol : float
        As in :func:`triaxial_average` [1].
    branch : {1.0, -1.0}
        The sense of rotation, as in :func:`triaxial_average`.

    Returns
    -------
    Kernel or None
        None for a Python torque, a time-dependent term without a forcing period, or one
        whose period does not divide it. Symmetric bodies and the sphere are compiled too
        (:func:`tumble.kernels.triaxial._polhode`: the polhode at m = 0).
    """
    terms = torque.compiled_terms() if hasattr(torque, "compiled_terms") else None
    program = getattr(torque, "program", None)
    if terms is None or program is None:
        return None
    I_user = np.asarray(inertia, dtype=float).reshape(3)
    I1, I2, I3 = sorted(I_user.tolist())
    exact = True  # terms averaged at t or over their own phase: the kernel's reductions apply
    four = True  # every term's precession on four nodes (phase means) exactly
    for code, _, payload in terms:
        term = term_of(code)
        if term.quadrature_only:
            exact = False  # a user's numba function: the general product rule
            continue
        four = four and term.precession_degree <= 3
        rate = 0.0 if term.forcing_rate is None else term.forcing_rate(term.values(payload))
        if rate == 0.0:
            continue
        if forcing_period is None:
            return None
        cycles = float(forcing_period) * abs(float(rate)) / (2.0 * math.pi)
        if round(cycles) < 1 or abs(cycles - round(cycles)) > _PERIOD_RTOL * cycles:
            return None
    omega_ref = 1.0 if forcing_period is None else 2.0 * math.pi / float(forcing_period)
    closed = exact and all(term_of(code).has_closed_form(payload) for code, _, payload in terms)
    head = TRIAXIAL_AVERAGED.pack(
        {
            "eps": factor,
            "rtol": rtol,
            "floor": MOMENTUM_FLOOR * I3 * omega_ref,
            "inertia": (I1, I2, I3),
            "sorting": proper_sorting(I_user),
            "user_inertia": I_user,
            "period": 0.0 if forcing_period is None else float(forcing_period),
            "branch": _sense(branch),
        }
    )
    kind = KIND_TRIAXIAL_CLOSED if closed else (KIND_TRIAXIAL_PHASE_MEANS if exact and four else
                                                KIND_TRIAXIAL_AVERAGED)  # fmt: skip
    return Kernel(kind, np.concatenate([head, program]))
