"""Averaging over the fast spin of a symmetric body: the resisting-medium setting.

A. V. Medvedev (1987); sections (§) are those of docs/theory/resisting-medium.md. In the
normalized variables of (1.3) (I1 = 1, I3 = 1 + κ, time τ) a fast-spinning symmetric body under
a small body moment ε m has the slow variables k, ρ, σ, ϑ and the fast phases ψ, φ. Along the
unperturbed motion (2.1) at frozen slow variables the phases run uniformly round a 2-torus with
the rates k and −kκ cos ϑ/(1 + κ); when these are not commensurate the time average along
(2.1) is the mean over the torus, which :func:`spinner_average` computes by quadrature for any
torque. For the moment (1.2) of the paper it reproduces (2.2).

Two ways to the mean. A moment that depends on the body rate only (sums and multiples of the
built-in :class:`~tumble.torques.ConstantBodyTorque`, :class:`~tumble.torques.LinearDrag` and
:class:`~tumble.torques.QuadraticDrag`, recognized by their exact types: the law (1.2)) does not
depend on ψ, so its mean over ψ is known exactly (⟨dρ/dτ⟩ = ⟨dσ/dτ⟩ = 0) and only φ is
averaged, on the body rates alone. Any other torque is evaluated on the product grid of ψ and φ
with the attitude: the ψ nodes are chosen first, on 64 values of φ: one node if the moment does
not depend on ψ at 8 nodes (a body-fixed law given as a plain function), else the fewest of 2,
4, 8, … that resolve the ψ-mean. Either way the φ nodes are doubled by
:func:`~tumble.averaging.quadrature.torus_mean` until two results agree to ``rtol`` relative to
the size of the moment on the torus, the trapezoidal means or their Romberg extrapolation,
which the kinks of the quadratic law call for: its third derivative jumps at the nodes φ = 0,
π/2, π, 3π/2, so the plain rule would need 1024–4096 φ nodes and the extrapolated one needs
256–512 (the body-rate path) or 512–1024 (the product grid, which starts at 64). (The 2-D mode
of ``torus_mean`` would refine ψ together with φ, while (1.2) needs one ψ node.)

Measured cost of one :func:`spinner_average` call at the default rtol (2 shared cores): for
``resisting_medium.Params.torque`` about 0.25 ms, with or without the quadratic term; for (1.2)
as a plain batched function about 1 ms (0.5 ms without the quadratic term); called one state at
a time (``batched=False``), about 40 ms.

This is the engine for any torque, and the quadrature oracle of the compiled spinner setting
(:mod:`tumble.kernels.spinner`), which forms the φ-means of a moment of the body rate only in
closed form (no grid, so no limit of its own to share) and is tested against this one.

This module also holds the kinematics of the standard form (1.3), the part that does not depend
on the moment law: :func:`body_momentum` and :func:`standard_form`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.quadrature import (
    AVERAGE_RTOL,
    AveragingError,
    BatchedTorque,
    rate_only,
    torus_mean,
)
from tumble.errors import ParameterError, check_finite, check_range
from tumble.rotations import (
    SINGULAR_SIN,
    attitude_from_kframe_angles,
    matrix_to_quat,
    quat_multiply,
)

__all__ = [
    "TorqueLike",
    "body_momentum",
    "spinner_average",
    "spinner_system",
    "standard_form",
]

TorqueLike = Callable[[float, Any, Any], Any]
"""``torque(t, q, omega) -> body moment``, as in :mod:`tumble.torques` (any callable will do)."""

_PSI_MAX = 256
"""Most nodes in ψ: a torque that needs more varies on a finer angular scale than any smooth
external field (its ψ-dependence comes only through the attitude)."""

_PHI_MAX = 1 << 14
"""Most nodes in φ. The quadratic law w ∘ |w| of (1.2) gives integrands like |sin φ|³, whose
third derivative jumps at φ = 0, π (and |cos φ|³ at π/2, 3π/2): the plain trapezoidal error
falls only like n⁻⁴, a relative 1e-12 would take 1024–4096 nodes. These kinks lie on the nodes
of every grid used here (n a multiple of 4, starting at φ = 0), so the error is a series in
even powers of the step and Romberg extrapolation reaches 1e-12 with 256–1024 nodes (256–512
from the coarse start of the body-rate path). A torque kinked elsewhere falls back to plain
doubling, up to this limit."""

_PHI_START = 64
"""φ nodes on which the ψ nodes are chosen, and the first φ grid of the average over the
product grid (64 resolves any smooth moment law of low degree in φ; a coarser start only adds
doublings)."""

_RATE_PHI_START = 16
"""First φ grid of a moment of the body rate only: the linear part of (1.2) is of degree 2 in
φ, exact from 3 nodes, so 16 → 32 settles it in one doubling, and the Romberg table of the
quadratic part gains a level for each of its cheap coarse grids (a multiple of 4, so the kinks
at multiples of π/2 are nodes)."""

_RATE_PHI_KNOWN = 512
"""φ nodes of the first call for a moment of the body rate only. With Romberg extrapolation the
quadratic law of (1.2) converges to 1e-12 with 256 or 512 nodes, and one call on 512 nodes
costs about what one on 16 does (the cost is Python's, not the arithmetic's): the levels
16 … 512 are subsets of that one call, and the usual law needs no other."""

# ---------------------------------------------------------------------------------------------
# Kinematics of the standard form (1.3), independent of the moment law.


def body_momentum(k: ArrayLike, theta: ArrayLike, phi: ArrayLike) -> FloatArray:
    """k_b = k (sin ϑ sin φ, sin ϑ cos φ, cos ϑ): body components of k, §2.

    Parameters
    ----------
    k : array_like
        Normalized angular momentum |K|/K0 [1].
    theta, phi : array_like
        Nutation angle ϑ and proper rotation φ [rad].

    Returns
    -------
    ndarray, shape (..., 3)
        Body components [1]; the body rate is w = k_b / (1, 1, 1 + κ).
    """
    k, theta, phi = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (k, theta, phi)))
    st = np.sin(theta)
    return np.stack([k * st * np.sin(phi), k * st * np.cos(phi), k * np.cos(theta)], -1)


def _nodal(
    m: FloatArray, ct: ArrayLike, st: ArrayLike, cf: ArrayLike, sf: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """μ = Rx(ϑ) Rz(φ) m from the cosines and sines of ϑ, φ (§3 identity).

    μ is the moment in the frame turned back by ψ: the K-frame components of (1.3) are
    m_K = Rz(ψ) μ (:func:`_kframe`), and μ3 = m3.
    """
    m1, m2, m3 = m[..., 0], m[..., 1], m[..., 2]
    across = sf * m1 + cf * m2
    return cf * m1 - sf * m2, ct * across - st * m3, st * across + ct * m3


def _kframe(
    mu1: FloatArray, mu2: FloatArray, cp: ArrayLike, sp: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """K-frame components m1, m2 = Rz(ψ) (μ1, μ2)."""
    return cp * mu1 - sp * mu2, sp * mu1 + cp * mu2


def standard_form(
    m_body: ArrayLike,
    k: ArrayLike,
    rho: ArrayLike,
    psi: ArrayLike,
    theta: ArrayLike,
    phi: ArrayLike,
    kappa: float,
    eps: float,
) -> FloatArray:
    """Rates of (k, ρ, σ, ψ, ϑ, φ) under the body moment ε m: the standard form (1.3).

    Correction E1 applied (k dρ/dτ = ε m1). Singular where sin ϑ = 0 or sin ρ = 0 (§11).

    Parameters
    ----------
    m_body : array_like, shape (..., 3)
        Normalized moment m in body axes [1] (without the factor ε).
    k : array_like
        |k| [1].
    rho, psi, theta, phi : array_like
        ρ, ψ, ϑ, φ [rad] (σ does not enter the rates).
    kappa : float
        Oblateness κ, I3 = 1 + κ [1].
    eps : float
        Small parameter ε [1].

    Returns
    -------
    ndarray, shape (..., 6)
        dk/dτ [1/τ], dρ/dτ, dσ/dτ, dψ/dτ, dϑ/dτ, dφ/dτ [rad/τ].
    """
    m = np.asarray(m_body, dtype=float)
    k, rho, psi, theta, phi = (np.asarray(v, dtype=float) for v in (k, rho, psi, theta, phi))
    ct, st = np.cos(theta), np.sin(theta)
    mu1, mu2, mu3 = _nodal(m, ct, st, np.cos(phi), np.sin(phi))
    m1, m2 = _kframe(mu1, mu2, np.cos(psi), np.sin(psi))
    e_k = eps / k
    return np.stack(
        np.broadcast_arrays(
            eps * mu3,
            e_k * m1,
            e_k * m2 / np.sin(rho),
            k - e_k * (mu1 * ct / st + m2 / np.tan(rho)),
            e_k * mu2,
            -k * kappa / (1.0 + kappa) * ct + e_k * mu1 / st,
        ),
        -1,
    )


# ---------------------------------------------------------------------------------------------
# The torque at many nodes at once.


class _BodyMoment:
    """The torque at the torus nodes at the frozen slow time t (see :class:`BatchedTorque`)."""

    def __init__(self, torque: TorqueLike, t: float, batched: bool | None) -> None:
        self.t = t
        self.call = BatchedTorque(torque, batched, "the unperturbed motion (2.1)")

    def __call__(self, q: FloatArray, w: FloatArray) -> FloatArray:
        return self.call(self.t, q, w)


# ---------------------------------------------------------------------------------------------
# The averaged system over the torus (ψ, φ).


def _nodes(n: int, offset: float = 0.0) -> FloatArray:
    """The phases (j + offset) 2π/n, j = 0 … n − 1 [rad]: trapezoidal nodes on a circle."""
    return np.asarray((np.arange(n) + offset) * (2.0 * math.pi / n), dtype=np.float64)


class _PsiGrid(NamedTuple):
    """Nodes in ψ with what every φ grid needs from them."""

    psi: FloatArray  # the nodes [rad], shape (n,)
    attitude: FloatArray  # q = (cos φ/2, sin φ/2) @ attitude[i] at ψ_i, shape (n, 2, 4)
    cos: FloatArray  # cos ψ, shape (n, 1)
    sin: FloatArray  # sin ψ, shape (n, 1)


class _Torus:
    """The moment on the torus of (ψ, φ) at frozen slow variables (k, ρ, σ, ϑ)."""

    def __init__(
        self, moment: _BodyMoment, kappa: float, k: float, rho: float, sigma: float, theta: float
    ) -> None:
        self.moment, self.k, self.theta = moment, k, theta
        self.ct, self.st = math.cos(theta), math.sin(theta)
        # Body rate w = k_b / (1, 1, 1 + κ): the last component does not depend on φ.
        self.kst, self.r = k * self.st, k * self.ct / (1.0 + kappa)
        # Ξ(ρ, σ) = Rz(σ) Ry(ρ) (§2), so its quaternion is (cos σ/2, 0, 0, sin σ/2) ⊗
        # (cos ρ/2, 0, sin ρ/2, 0); xi_left[j] = Ξ ⊗ (unit quaternion j), see :meth:`grid`.
        cs, ss, cr, sr = (f(0.5 * x) for x in (sigma, rho) for f in (math.cos, math.sin))
        xi = np.array([cs * cr, -ss * sr, cs * sr, ss * cr])
        self.xi_left = quat_multiply(xi, np.eye(4))

    def grid(self, psi: FloatArray) -> _PsiGrid:
        """The ψ nodes ``psi`` prepared for :meth:`nodal`.

        The attitude Ξ(ρ, σ) Rz(ψ) Rx(ϑ) Rz(φ) is the quaternion Ξ ⊗ e with e the 3-1-3
        quaternion (cos ϑ/2 cos (ψ+φ)/2, sin ϑ/2 cos (ψ−φ)/2, sin ϑ/2 sin (ψ−φ)/2,
        cos ϑ/2 sin (ψ+φ)/2), which is linear in (cos φ/2, sin φ/2); and Ξ ⊗ e = e @ xi_left
        with xi_left[j] = Ξ ⊗ (unit quaternion j). So the whole attitude is one product per
        node and no trigonometry is done on the (ψ, φ) grid.
        """
        ch, sh = math.cos(0.5 * self.theta), math.sin(0.5 * self.theta)
        c, s = np.cos(0.5 * psi), np.sin(0.5 * psi)
        e = np.empty((psi.size, 2, 4))
        e[:, 0, 0], e[:, 0, 1], e[:, 0, 2], e[:, 0, 3] = ch * c, sh * c, sh * s, ch * s  # cos φ/2
        e[:, 1, 0], e[:, 1, 1], e[:, 1, 2], e[:, 1, 3] = -ch * s, sh * s, -sh * c, ch * c  # sin φ/2
        return _PsiGrid(psi, e @ self.xi_left, np.cos(psi)[:, None], np.sin(psi)[:, None])

    def nodal(self, grid: _PsiGrid, phi: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """μ1, μ2, μ3 (§3) of the moment at the nodes ψ × φ, each (len(psi), len(phi))."""
        half = np.stack([np.cos(0.5 * phi), np.sin(0.5 * phi)], -1)
        cf = (half[:, 0] - half[:, 1]) * (half[:, 0] + half[:, 1])
        sf = 2.0 * half[:, 0] * half[:, 1]
        q = half @ grid.attitude  # (n_psi, n_phi, 4)
        q *= np.where(q[..., :1] < 0.0, -1.0, 1.0)  # q0 ≥ 0, as matrix_to_quat returns it
        shape = q.shape[:2]
        w = np.empty((*shape, 3))
        w[..., 0], w[..., 1], w[..., 2] = self.kst * sf, self.kst * cf, self.r
        m = self.moment(q.reshape(-1, 4), w.reshape(-1, 3))
        return _nodal(m.reshape(*shape, 3), self.ct, self.st, cf, sf)

    @staticmethod
    def slow(mu: tuple[FloatArray, FloatArray, FloatArray], grid: _PsiGrid) -> FloatArray:
        """(μ3, m1, m2, μ2), shape (4, n_psi, n_phi): up to the factors ε, ε/k, ε/(k sin ρ),
        ε/k the slow rates of (1.3)."""
        mu1, mu2, mu3 = mu
        m1, m2 = _kframe(mu1, mu2, grid.cos, grid.sin)
        return np.stack([mu3, m1, m2, mu2])

    @staticmethod
    def independent(mu: tuple[FloatArray, FloatArray, FloatArray]) -> FloatArray:
        """(μ3, ⟨m1⟩_ψ, ⟨m2⟩_ψ, μ2) from the first ψ row of a μ that does not depend on ψ.

        Then m_K = Rz(ψ) μ averages to (0, 0, μ3) over ψ exactly.
        """
        zero = np.zeros_like(mu[2][0])
        return np.stack([mu[2][0], zero, zero, mu[1][0]])

    def resolve_psi(self, phi: FloatArray, rtol: float) -> tuple[_PsiGrid, bool, float, FloatArray]:
        """The ψ nodes for the average over φ, chosen on the φ nodes ``phi``.

        If μ does not depend on ψ at 8 nodes (any body-fixed law such as (1.2)), one ψ node
        will do. Otherwise ψ-means R_n of :meth:`slow` with n = 2, 4, 8, … nodes (each level
        adds the midpoints) are compared at every φ of ``phi`` until two successive levels, the
        finer with at least 8 nodes, agree to ``rtol`` times the largest |μ|; the nodes are
        those of the smallest level from which every later one agreed.

        Returns
        -------
        grid : _PsiGrid
            The ψ nodes.
        independent : bool
            Whether μ does not depend on ψ (then ``grid`` has the single node ψ = 0).
        scale : float
            max |μ| on the nodes [moment unit].
        means : ndarray, shape (4, len(phi))
            ψ-means of (μ3, m1, m2, μ2) at ``phi`` on ``grid``.
        """
        n = 8
        grid = self.grid(_nodes(n))
        mu = self.nodal(grid, phi)
        scale = max(float(np.max(np.abs(c))) for c in mu)
        if all(np.all(np.abs(c - c[:1]) <= rtol * scale) for c in mu):
            return self.grid(np.zeros(1)), True, scale, self.independent(mu)
        values = self.slow(mu, grid)
        means = [values[:, ::4].mean(axis=1), values[:, ::2].mean(axis=1), values.mean(axis=1)]
        while True:
            tol = rtol * scale
            agree = [bool(np.all(np.abs(b - a) <= tol)) for a, b in itertools.pairwise(means)]
            if agree[-1]:
                first = len(agree)
                while first > 0 and agree[first - 1]:
                    first -= 1
                n_psi = 2 << first
                return self.grid(_nodes(n_psi)), False, scale, means[first]
            if n >= _PSI_MAX:
                raise AveragingError(
                    f"the average over ψ did not converge with {_PSI_MAX} nodes (k = {self.k:g}, "
                    f"ϑ = {self.theta:g}): the torque varies too fast with the attitude"
                )
            mid = self.grid(_nodes(n, 0.5))
            mu = self.nodal(mid, phi)
            scale = max(scale, *(float(np.max(np.abs(c))) for c in mu))
            means.append(0.5 * (means[-1] + self.slow(mu, mid).mean(axis=1)))
            n *= 2

    def psi_mean(self, grid: _PsiGrid, independent: bool, phi: FloatArray) -> FloatArray:
        """ψ-means of (μ3, m1, m2, μ2) at the φ nodes ``phi``, shape (4, len(phi))."""
        mu = self.nodal(grid, phi)
        if independent:
            return self.independent(mu)
        return self.slow(mu, grid).mean(axis=1)


def _rate_mean(
    torque: Any, kappa: float, k: float, theta: float, t: float, rtol: float
) -> tuple[FloatArray, int]:
    """(⟨μ3⟩, ⟨μ2⟩) over φ for a moment of the body rate only (``rate_only``); φ nodes used.

    The body rate w = (k sin ϑ sin φ, k sin ϑ cos φ, k cos ϑ/(1 + κ)) of (2.1) does not
    involve ψ, so neither does μ = Rx(ϑ) Rz(φ) m (§3): the K-frame components
    m_K = Rz(ψ) μ average over ψ to (0, 0, μ3) exactly, and the slow rates need only the φ
    means of μ3 and μ2. The torque is called on the rates alone (q = None: these torques do
    not read it).
    """
    ct, st = math.cos(theta), math.sin(theta)
    kst, r = k * st, k * ct / (1.0 + kappa)

    def nodal(phi: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        cf, sf = np.cos(phi), np.sin(phi)
        w = np.empty((phi.size, 3))
        w[:, 0], w[:, 1], w[:, 2] = kst * sf, kst * cf, r
        m = np.asarray(torque(t, None, w), dtype=float)
        if not np.all(np.isfinite(m)):
            raise AveragingError(
                "the torque returned non-finite values on the unperturbed motion (2.1): no "
                "average can be formed"
            )
        return _nodal(m, ct, st, cf, sf)

    def mu32(phi: FloatArray) -> FloatArray:
        _, mu2, mu3 = nodal(phi)
        return np.stack([mu3, mu2])

    # One call on the nodes most laws need; the coarser levels are its subsets.
    mu = nodal(_nodes(_RATE_PHI_KNOWN))
    return torus_mean(
        mu32,
        1,
        rtol=rtol,
        atol=rtol * max(float(np.max(np.abs(c))) for c in mu),
        n_start=_RATE_PHI_START,
        n_max=_PHI_MAX,
        what=f"the average over φ (k = {k:g}, ϑ = {theta:g}, κ = {kappa:g})",
        extrapolate=True,
        known=np.stack([mu[2], mu[1]]),
    )


def _check_state(
    kappa: float, eps: float, k: float, rho: float, sigma: float, theta: float
) -> None:
    check_range("kappa", kappa, low=-1.0, high=1.0, high_open=False)
    if kappa == 0.0:
        raise ParameterError(
            "kappa = 0 is outside the allowed range (−1, 0) ∪ (0, 1] of the spinner average: "
            "a spherical inertia ellipsoid has no fast spin φ "
            "(docs/theory/resisting-medium.md §10.5)"
        )
    check_range("eps", eps, low=0.0, low_open=False)
    check_range("k", k, low=0.0)
    check_finite("sigma", sigma)
    for name, value in (("rho", rho), ("theta", theta)):
        check_range(name, value, low=0.0, high=math.pi, low_open=False, high_open=False)
        if abs(math.sin(value)) < SINGULAR_SIN:
            raise ParameterError(
                f"{name} = {value:g} is outside the allowed range (0, π) of the spinner "
                f"average: sin {name} = 0 is a singularity of the standard form (1.3) "
                "(docs/theory/resisting-medium.md §11)"
            )


def _spinner_average(
    torque: TorqueLike,
    kappa: float,
    eps: float,
    y: tuple[float, float, float, float],
    t: float,
    rtol: float,
    batched: bool | None,
) -> tuple[FloatArray, int, int]:
    """:func:`spinner_average` at the slow state ``y = (k, ρ, σ, ϑ)`` [1, rad, rad, rad] (the
    averaged form's state vector), and the nodes used in ψ and in φ."""
    k, rho, sigma, theta = y
    kappa, eps, k, rho, sigma, theta, t = map(float, (kappa, eps, k, rho, sigma, theta, t))
    _check_state(kappa, eps, k, rho, sigma, theta)
    check_finite("t", t)
    check_range("rtol", rtol, low=0.0)
    if batched is not False and rate_only(torque):
        (mu3, mu2), n_phi = _rate_mean(torque, kappa, k, theta, t, rtol)
        # ⟨m1⟩ = ⟨m2⟩ = 0 over ψ exactly: ρ and σ do not drift (see _rate_mean).
        return eps * np.array([mu3, 0.0, 0.0, mu2 / k]), 1, n_phi
    torus = _Torus(_BodyMoment(torque, t, batched), kappa, k, rho, sigma, theta)
    grid, independent, scale, first = torus.resolve_psi(_nodes(_PHI_START), rtol)

    def psi_mean(phi: FloatArray) -> FloatArray:
        return torus.psi_mean(grid, independent, phi)

    mean, n_phi = torus_mean(
        psi_mean,
        1,
        rtol=rtol,
        atol=rtol * scale,
        n_start=_PHI_START,
        n_max=_PHI_MAX,
        what=f"the average over φ (k = {k:g}, ϑ = {theta:g}, κ = {kappa:g})",
        extrapolate=True,
        known=first,  # the ψ-means on the φ grid that chose the ψ nodes
    )
    mu3, m1, m2, mu2 = mean
    rates = eps * np.array([mu3, m1 / k, m2 / (k * math.sin(rho)), mu2 / k])
    return rates, grid.psi.size, n_phi


def spinner_average(
    torque: TorqueLike,
    kappa: float,
    eps: float,
    k: float,
    rho: float,
    sigma: float,
    theta: float,
    t: float = 0.0,
    *,
    rtol: float = AVERAGE_RTOL,
    batched: bool | None = None,
) -> FloatArray:
    """Averaged rates (dk/dτ, dρ/dτ, dσ/dτ, dϑ/dτ) of (1.3) for any torque; (2.2) for (1.2).

    The slow rates of the standard form (1.3) under the body moment ε m, with
    ``m = torque(t, q, w)``, averaged over the fast phases ψ and φ of the unperturbed motion
    (2.1) at frozen k, ρ, σ, ϑ and t: the mean over the 2-torus, i.e. the time average when
    the rates k of ψ and −kκ cos ϑ/(1+κ) of φ are not commensurate (first-order averaging,
    §6; at ϑ = π/2 φ stops and the result is the limit of the average, §10.2).

    How the mean is formed (the exact ψ-mean of a moment of the body rate only, the ψ nodes
    of any other torque, the Romberg extrapolation in φ) and what a call costs: module notes,
    "Two ways to the mean".

    Parameters
    ----------
    torque : callable
        ``torque(t, q, w) -> m``: the normalized moment m of (1.3) in body axes [1], without
        the factor ε (for the model, ``Params.torque`` already includes ε: pass it with
        ``eps=1``). ``q`` is the attitude quaternion (scalar first, body → inertial) of
        Ξ(ρ, σ) C(ψ, ϑ, φ), with q0 ≥ 0 as ``resisting_medium.full_from_slow`` builds it;
        ``w = (k sin ϑ sin φ, k sin ϑ cos φ, k cos ϑ/(1 + κ))`` is the body rate [rad/τ].
        Called batched, with q of shape (n, 4) and w of shape (n, 3), returning shape (n, 3)
        (or (3,) if constant); see ``batched``. Any :class:`~tumble.torques.Torque` will do
        (the built-ins accept batches; those of (1.2) are called with the rates only, q =
        None, which they do not read).
    kappa : float
        Oblateness κ, I3 = I1 (1 + κ) [1], in (−1, 1], κ ≠ 0.
    eps : float
        Small parameter ε ≥ 0 [1].
    k : float
        |k| > 0 [1].
    rho : float
        Angle of K from the inertial axis X3 [rad], sin ρ ≠ 0.
    sigma : float
        Azimuth of K about X3 [rad].
    theta : float
        Nutation angle ϑ [rad], sin ϑ ≠ 0.
    t : float
        Time τ [1], frozen (an explicit time dependence is slow).
    rtol : float
        Tolerance of the quadrature, relative to the largest |m| on the torus.
    batched : bool or None
        True: the torque follows the batched convention (no check). False: call it one state
        at a time (about 10 µs per node; hundreds of nodes for non-smooth laws such as
        (1.2)), the built-ins too (the reference for their fast path). None (default): try
        batched, check two nodes against one-state calls, and fall back if the torque fails
        or disagrees.

    Returns
    -------
    ndarray, shape (4,)
        ⟨dk/dτ⟩ [1/τ], ⟨dρ/dτ⟩, ⟨dσ/dτ⟩, ⟨dϑ/dτ⟩ [rad/τ].

    Raises
    ------
    ParameterError
        κ = 0 (φ is not a fast phase), sin ϑ = 0 or sin ρ = 0 (the standard form (1.3) is
        singular, §11), k ≤ 0, or a torque that returns the wrong shape.
    AveragingError
        The quadrature did not converge, or the torque is not finite on the torus.

    References
    ----------
    A. V. Medvedev (1987), (1.3), (2.1), (2.2); docs/theory/resisting-medium.md §4–§6.
    """
    return _spinner_average(torque, kappa, eps, (k, rho, sigma, theta), t, rtol, batched)[0]


# ---------------------------------------------------------------------------------------------
# The standard form (1.3) as a fast system, for second-order averaging.

SPINNER_GRID = (4, 64)
"""First torus grid (ψ, φ) of :func:`spinner_system`: a body-fixed moment enters the slow
rates through Rz(ψ) only (harmonics 0 and ±1 in ψ, resolved by 4 nodes); the grid is doubled
where the moment needs more (:func:`tumble.averaging.second_order.second_order`)."""


def spinner_system(
    torque: TorqueLike, kappa: float
) -> tuple[
    Callable[[float, FloatArray, Any], tuple[FloatArray, FloatArray]],
    Callable[[FloatArray], FloatArray],
]:
    """The standard form (1.3) split into slow rates and phase rates for the fast system of
    :mod:`tumble.averaging.second_order`.

    Slow x = (k, ρ, σ, ϑ); phases (ψ, φ) with the unperturbed rates ν = (k, −kκ cos ϑ/(1+κ))
    of (2.1). f holds the slow rates of (1.3) and g the phases' rates less ν, both under the
    moment ``torque(t, q, w)`` (which carries ε, as ``resisting_medium.Params.torque`` does).

    Returns
    -------
    rates : callable
        ``rates(t, x, (ψ, φ)) -> (f, g)``, vectorised over the grid and over slow states that
        vary from node to node.
    frequencies : callable
        ``frequencies(x) -> ν`` [rad/τ].
    """
    attitude = not rate_only(torque)
    ratio = kappa / (1.0 + kappa)

    def rates(t: float, x: FloatArray, phases: Any) -> tuple[FloatArray, FloatArray]:
        k, rho, sigma, theta = x
        psi, phi = phases
        shape = np.broadcast_shapes(*(np.shape(v) for v in (k, rho, sigma, theta, psi, phi)))
        if attitude:
            R = attitude_from_kframe_angles(rho, sigma, psi, theta, phi)
            q = matrix_to_quat(np.broadcast_to(R, (*shape, 3, 3))).reshape(-1, 4)
            w = body_momentum(k, theta, phi) / np.array([1.0, 1.0, 1.0 + kappa])
            w = np.broadcast_to(w, (*shape, 3)).reshape(-1, 3)
            m = np.broadcast_to(np.asarray(torque(t, q, w), dtype=float), w.shape)
            m = m.reshape(*shape, 3)
        else:  # the body rate alone: on the φ nodes only when k and ϑ do not vary with ψ
            k_, theta_ = (_along_phi(v) for v in (k, theta))
            w = body_momentum(k_, theta_, phi) / np.array([1.0, 1.0, 1.0 + kappa])
            m = np.asarray(torque(t, None, w.reshape(-1, 3)), dtype=float)
            m = np.broadcast_to(np.broadcast_to(m, (w.size // 3, 3)).reshape(w.shape), (*shape, 3))
        out = standard_form(m, k, rho, psi, theta, phi, kappa, 1.0)
        out = np.moveaxis(out, -1, 0)
        f = out[[0, 1, 2, 4]]
        g = np.stack([out[3] - k, out[5] + k * ratio * np.cos(theta)])
        return f, g

    def frequencies(x: FloatArray) -> FloatArray:
        k, theta = float(x[0]), float(x[3])
        return np.array([k, -k * ratio * math.cos(theta)])

    return rates, frequencies


def _along_phi(values: Any) -> Any:
    """``values`` (on the (ψ, φ) grid) reduced to their first ψ row where they do not vary
    with ψ, so that a moment of the body rate is evaluated on the φ nodes only."""
    v = np.asarray(values)
    if v.ndim == 2 and v.shape[0] > 1 and np.all(v == v[:1]):
        return v[:1]
    return v
