"""Volosov averaging over the nutation of a symmetric body (docs/theory/nonlinear-moment.md §6–§8),
for any perturbation of (2.1) and for any small torque.

A perturbation is given either directly as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`) or
as a body-axes torque (:func:`torque_perturbation`), converted through (1.3a) and §6 and
averaged over the spin φ and the precession ψ (independent fast phases, the non-resonant
case). :func:`numeric_averages` then averages over the nutation period of the frozen orbit.

This is the engine for any perturbation; for a moment of the body rate only the compiled twin,
:func:`tumble.kernels.nutation.nutation_engine`, forms the same averages from the same grids
and limits (:mod:`tumble.kernels.limits`), and is tested against this one.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.generator import zero_mean_antiderivative
from tumble.averaging.quadrature import (
    AVERAGE_RTOL,
    AveragingError,
    BatchedTorque,
    rate_only,
    torus_mean,
)
from tumble.averaging.second_order import (
    GRID_MAX,
    SecondOrder,
    generator_drift,
    grid_terms,
    refine_grid,
)
from tumble.kernels.limits import NUTATION_MAX, NUTATION_START, SPIN_MAX, SPIN_START
from tumble.kernels.nutation import orbit_nodes
from tumble.unperturbed.symmetric_body import NutationOrbit

__all__ = [
    "AVERAGE_RTOL",
    "Perturbation",
    "numeric_averages",
    "nutation_generator",
    "potential_gradient",
    "torque_perturbation",
]


@dataclass(frozen=True)
class Perturbation:
    """A perturbation of (2.1): θ'' + F(θ, z) = εΦθ, z' = εΦz, z = (R, G, a, b).

    Given either as ``phi_theta(tau, theta, theta_dot, z)`` and ``phi_z(tau, theta, z)`` (the
    paper's form, Φz independent of θ'), or as one function ``joint(tau, theta, theta_dot, z)``
    returning the rows (Φθ, Φ_R, Φ_G, Φ_a, Φ_b) (e.g. from a torque, whose Φz may depend on
    θ'). All are vectorized over θ, θ'; z is the frozen slow state, τ = εt the slow time.

    Parameters
    ----------
    phi_theta : callable, optional
        Φθ [1/t²].
    phi_z : callable, optional
        Array of shape (4, n): Φ_R, Φ_G [1/t], Φ_a, Φ_b [1/t²].
    name : str
        For messages.
    joint : callable, optional
        All five rows at once, shape (5, n).
    rows : bool
        The functions also take θ, θ' of shape (k, n) with z of shape (4, k, 1), k slow states
        at once (numpy broadcasting), returning (k, n) and (4, k, n): the neighbouring orbits
        of :class:`NutationSystem` are then evaluated in one call.
    """

    phi_theta: Callable[[float, FloatArray, FloatArray, FloatArray], Any] | None = None
    phi_z: Callable[[float, FloatArray, FloatArray], Any] | None = None
    name: str = "user"
    joint: Callable[[float, FloatArray, FloatArray, FloatArray], Any] | None = None
    rows: bool = False

    def evaluate(
        self, tau: float, theta: FloatArray, theta_dot: FloatArray, z: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Φθ (shape (n,)) and Φz (shape (4, n)) at the nodes θ, θ'."""
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        theta_dot = np.atleast_1d(np.asarray(theta_dot, dtype=float))
        if self.joint is not None:
            rows = np.asarray(self.joint(tau, theta, theta_dot, z), dtype=float)
            return rows[0], rows[1:]
        if self.phi_theta is None or self.phi_z is None:
            raise ValueError("a Perturbation needs phi_theta and phi_z, or joint")
        ph = np.asarray(self.phi_theta(tau, theta, theta_dot, z), dtype=float)
        pz = np.asarray(self.phi_z(tau, theta, z), dtype=float)
        return np.broadcast_to(ph, theta.shape), np.broadcast_to(pz, (4, *theta.shape))


def potential_gradient(u: FloatArray, z: FloatArray) -> FloatArray:
    """W^z = ∂W/∂z = (W_R, W_G, W_a, W_b) of (2.3), docs/theory/nonlinear-moment.md §9, shape (4,
    n).

    Parameters
    ----------
    u : ndarray
        cos θ at the nodes [1], shape (n,) (or (k, n) for k states).
    z : ndarray, shape (4,) (or (4, k, 1))
        (R, G, a, b) [1/t, 1/t, 1/t², 1/t²].
    """
    R, G = z[0], z[1]
    # (G − Ru)/(1 − u²) = ½[(G + R)/(1 + u) + (G − R)/(1 − u)] (1.12): a pole term whose
    # coefficient vanishes (G = ±R, the axis passing through ±e_z) is dropped, not 0/0.
    h = np.zeros(np.broadcast_shapes(np.shape(u), np.shape(R)))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for c, d in ((G + R, 1.0 + u), (G - R, 1.0 - u)):
            h = h + np.where(c != 0.0, 0.5 * c / d, 0.0)
    bad = ~np.isfinite(h)
    if np.any(bad):
        at = np.unravel_index(int(np.argmax(bad)), h.shape)  # the first orbit that does
        g_at, r_at = (float(np.broadcast_to(v, h.shape)[at]) for v in (G, R))
        raise AveragingError(
            f"W_R, W_G = ∓(G − Ru)/(1 − u²) are singular on this orbit (G = {g_at:.3g}, "
            f"R = {r_at:.3g}): it passes through θ = 0 or π to round-off, where the numeric "
            "averages cannot be formed"
        )
    return np.array([-u * h, h, u, u * u])


def numeric_averages(
    orbit: NutationOrbit,
    perturbation: Perturbation,
    tau: float,
    *,
    rtol: float = AVERAGE_RTOL,
    n_start: int = NUTATION_START,
    n_max: int = NUTATION_MAX,
) -> tuple[float, FloatArray]:
    """⟨Φθθ' + Φz·W^z⟩ and ⟨Φz⟩ over one nutation period of ``orbit``, (2.3).

    Periodic trapezoidal rule in time over one period (spectrally accurate; better than the
    rule in γ near a separatrix), doubling the nodes until two results agree to ``rtol``
    relative to the size of the integrand (the largest mean |row|, never below the largest
    average): a perturbation whose averages vanish, e.g. a conservative one, converges to
    zero instead of chasing round-off. The first evaluation is on 2·``n_start`` nodes, whose
    even ones give the ``n_start`` mean, and each doubling evaluates the perturbation at the
    new (odd) nodes only.

    Parameters
    ----------
    orbit : NutationOrbit
        The frozen unperturbed motion.
    perturbation : Perturbation
    tau : float
        Slow time τ = εt (frozen) [1].
    rtol : float
        Relative tolerance of the averages.
    n_start, n_max : int
        First and largest number of nodes over the period.

    Returns
    -------
    g : float
        ⟨Φθθ'⟩ + ⟨Φz·W^z⟩ [1/t³].
    phi_z : ndarray, shape (4,)
        ⟨Φz⟩.

    Raises
    ------
    AveragingError
        If the averages do not converge by ``n_max`` nodes (a near-separatrix orbit).
    """
    z = np.array([orbit.R, orbit.G, orbit.a, orbit.b])

    # ufunc reductions rather than np.mean, np.sum, np.max: on these few numbers their
    # wrappers cost more than the arithmetic.
    def integrand(theta: FloatArray, theta_dot: FloatArray) -> FloatArray:
        return _slow_rates(perturbation, tau, z, theta, theta_dot)

    n = 2 * n_start
    if n_start < n_max:
        _, theta, theta_dot, _ = orbit.nodes(n)
        values = integrand(theta, theta_dot)
        old, new = _mean(values, 2), _mean(values)
        size = float(np.maximum.reduce(_mean(np.abs(values))))
        while True:
            if _change(old, new, size) <= rtol:
                return float(new[0]), new[1:]
            if n >= n_max:
                break
            # The nodes of 2n are those of n (the even ones, bit for bit: t_i = i·T/n) and
            # the midpoints.
            _, theta, theta_dot, _ = orbit.nodes(2 * n)
            odd = integrand(theta[1::2], theta_dot[1::2])
            fresh = _mean(odd)
            size = 0.5 * (size + float(np.maximum.reduce(_mean(np.abs(odd)))))
            old, new = new, 0.5 * (new + fresh)
            n *= 2
    raise AveragingError(
        f"averages over the nutation period did not converge with {n_max} nodes "
        f"(k² = {orbit.k2:.12g}, 1 − k² = {orbit.mc:.3g}): the motion is too near a separatrix"
    )


def nutation_generator(
    orbit: NutationOrbit,
    perturbation: Perturbation,
    tau: float,
    *,
    rtol: float = AVERAGE_RTOL,
    n_start: int = 16,
    n_max: int = 1 << 12,
) -> tuple[float, FloatArray]:
    """The first-order generator u₁ of the mean ↔ osculating map of (H, z) at the orbit's
    own state (its t = 0), per unit ε: the general construction of
    :mod:`tumble.averaging.second_order` on the nutation's phase.

    The phase is the time along the orbit in units of the period, w = 2πt/T, uniform in the
    Jacobi argument; ν = 2π/T. u₁ is the zero-mean solution of ν ∂u₁/∂w = f − ⟨f⟩ with
    f = (Φθθ' + Φz·W^z, Φz), by FFT on the nodes of :meth:`NutationOrbit.nodes` (the first at
    t = 0), doubled until u₁(0) changes by less than ``rtol`` of the integrand's size. The
    osculating (H, z) of the orbit's state and the mean ones differ by ε u₁: H̄ = H − ε u₁_H,
    z̄ = z − ε u₁_z. For perturbations with Φθθ' even in θ' and Φz independent of θ' (the
    paper's), f − ⟨f⟩ is even about every turning point, so its zero-mean antiderivative is
    the one that vanishes there: u₁(0) = ∫_{t*}^0 (f − ⟨f⟩) dt, t* the last turning point.

    Returns
    -------
    u_H : float
        u₁ of H per unit ε [1/t²].
    u_z : ndarray, shape (4,)
        u₁ of z = (R, G, a, b) per unit ε [1/t, 1/t, 1/t², 1/t²].

    Raises
    ------
    AveragingError
        Not converged by ``n_max`` nodes (near a separatrix).
    """
    z = np.array([orbit.R, orbit.G, orbit.a, orbit.b])
    if orbit.kind == "steady":  # no oscillation: nothing to remove
        return 0.0, np.zeros(4)
    nu = 2.0 * math.pi / orbit.period
    last: FloatArray | None = None
    n = n_start
    while n <= n_max:
        _, theta, theta_dot, _ = orbit.nodes(n)
        f = _slow_rates(perturbation, tau, z, theta, theta_dot)
        u0 = zero_mean_antiderivative(f, [nu])[:, 0]
        size = float(np.max(np.abs(f))) / nu
        if last is not None and float(np.max(np.abs(u0 - last))) <= rtol * max(size, 1e-300):
            return float(u0[0]), u0[1:]
        last, n = u0, 2 * n
    raise AveragingError(
        f"the generator over the nutation period did not converge with {n_max} nodes "
        f"(k² = {orbit.k2:.12g}, 1 − k² = {orbit.mc:.3g}): the motion is too near a separatrix"
    )


def _slow_rates(
    perturbation: Perturbation,
    tau: float,
    z: FloatArray,
    theta: FloatArray,
    theta_dot: FloatArray,
) -> FloatArray:
    """The integrand of (2.3) at nodes of the orbit: rows g = Φθθ' + Φz·W^z and Φz.

    Parameters
    ----------
    perturbation : Perturbation
    tau : float
        Slow time τ = εt (frozen) [1].
    z : ndarray, shape (4,)
        The orbit's (R, G, a, b) [1/t, 1/t, 1/t², 1/t²].
    theta, theta_dot : ndarray, shape (n,)
        θ [rad] and θ' [rad/t] at the nodes.

    Returns
    -------
    ndarray, shape (5, n)
        g [1/t³] and Φz at the nodes.
    """
    ph, pz = perturbation.evaluate(tau, theta, theta_dot, z)
    out = np.empty((5, theta.size))
    out[0] = ph * theta_dot + np.add.reduce(pz * potential_gradient(np.cos(theta), z))
    out[1:] = pz
    return out


def _mean(values: FloatArray, step: int = 1) -> FloatArray:
    """Mean of each row over every ``step``-th node (a ufunc reduction: on these few numbers
    np.mean's wrapper costs more than the arithmetic)."""
    return np.add.reduce(values[:, ::step], axis=1) * (step / values.shape[1])


def _change(old: FloatArray, new: FloatArray, size: float) -> float:
    """max |new − old| relative to the integrand's size (or max |new| if larger)."""
    top = max(float(np.maximum.reduce(np.abs(new))), size, 1e-300)
    return float(np.maximum.reduce(np.abs(new - old))) / top


def torque_perturbation(
    torque: Callable[[float, FloatArray, FloatArray], Any],
    mu: float,
    *,
    ab_rate: Callable[[float], tuple[float, float]] | None = None,
    rtol: float = AVERAGE_RTOL,
    name: str = "torque",
    vectorized: bool = True,
) -> Perturbation:
    """Φθ, Φz of (2.1) for a small body-axes torque, docs/theory/nonlinear-moment.md §6.

    With δM the torque per unit A (``torque(t, q, omega)`` returns δM/A in body axes, q the
    body → inertial quaternion of the z–x–z angles ψ, θ, φ, omega the body rate):
    Φθ = δM_p cosφ − δM_q sinφ, Φ_R = δM_r, Φ_G = (δM_p sinφ + δM_q cosφ) sinθ + δM_r cosθ.
    These depend on ψ and φ as well; they are averaged over both (uniformly, as independent
    fast phases: the non-resonant case) before the nutation average: by the product
    trapezoidal rule of :func:`~tumble.averaging.quadrature.torus_mean` (4 → 8 → … nodes per
    phase, one call of the torque per level for all the θ nodes). The body rate does not
    involve ψ, so for a torque that is a function of the body rate alone, known from its type
    (:func:`~tumble.averaging.quadrature.rate_only`: the built-in constant body moment, linear
    and quadratic drag), the ψ-mean is exact and only φ is averaged, on the rates alone.

    Parameters
    ----------
    torque : callable
        ``torque(t, q, omega) -> δM/A`` [1/t²]; ``t`` is passed as the slow time τ. Called
        with a batch of states (q of shape (N, 4), omega (N, 3), returning (N, 3)) when
        ``vectorized``; otherwise, or if the result has another shape, one state at a time.
    mu : float
        C/A [1].
    ab_rate : callable, optional
        ``τ -> (da/dτ, db/dτ)``: prescribed slow laws of a and b (Φ_a, Φ_b); zero if omitted.
    rtol : float
        Tolerance of the average over ψ and φ.
    name : str
        For messages.
    vectorized : bool
        Whether to try batched calls first (False: one state at a time, the built-ins too;
        the reference for the fast paths).

    Returns
    -------
    Perturbation
    """
    averages = _TorqueAverages(
        torque,
        mu,
        ab_rate,
        rtol,
        name,
        vectorized and rate_only(torque),
        BatchedTorque(torque, None if vectorized else False, "the nutation (1.9)"),
    )
    return Perturbation(name=name, joint=averages.joint)


class _Nodes(NamedTuple):
    """The θ nodes of one call, shaped (n, 1, 1), and what the body rate needs of them."""

    tau: float
    th: FloatArray
    thd: FloatArray
    s: FloatArray  # sin θ
    c: FloatArray  # cos θ
    ch: FloatArray  # cos θ/2
    sh: FloatArray  # sin θ/2
    rate_sin: FloatArray  # ψ' sin θ
    r: float  # spin r = R/μ


class _Orbits(NamedTuple):
    """Orbits of k slow states at n phase nodes (:meth:`NutationSystem._on_rows`)."""

    theta: FloatArray  # (k, n) [rad]
    theta_dot: FloatArray  # (k, n) [rad/t]
    f: FloatArray  # (k, 5, n): ε(Φθθ' + W^z·Φz, Φz)
    ph: FloatArray  # (k, n): Φθ
    pz: FloatArray  # (k, 4, n): Φz
    nu: FloatArray  # (k,): 2π/T
    hint: FloatArray  # (k,): the middle of each well, ½(u1 + u2)


@dataclass
class _TorqueAverages:
    """Φθ, Φz of a torque averaged over ψ and φ at given θ nodes (:func:`torque_perturbation`)."""

    torque: Callable[[float, FloatArray, FloatArray], Any]
    mu: float
    ab_rate: Callable[[float], tuple[float, float]] | None
    rtol: float
    name: str
    rates_only: bool
    call: BatchedTorque
    trig: dict[tuple[int, int], tuple[FloatArray, ...]] = field(default_factory=dict)

    def angles(self, psi: FloatArray, phi: FloatArray) -> tuple[FloatArray, ...]:
        """sin φ, cos φ, cos (ψ ± φ)/2, sin (ψ ∓ φ)/2 on the torus grid: the same grids come
        back at every call (torus_mean's nodes depend on their number only), so once each."""
        key = (psi.shape[0], phi.shape[1])
        if key not in self.trig:
            up, um = 0.5 * (psi + phi), 0.5 * (psi - phi)
            self.trig[key] = (np.sin(phi), np.cos(phi), np.cos(up), np.cos(um), np.sin(um),
                              np.sin(up))  # fmt: skip
        return self.trig[key]

    def joint(
        self, tau: float, theta: FloatArray, theta_dot: FloatArray, z: FloatArray
    ) -> FloatArray:
        th, thd = np.broadcast_arrays(np.asarray(theta, float), np.asarray(theta_dot, float))
        shape = th.shape
        th, thd = th.ravel()[:, None, None], thd.ravel()[:, None, None]
        R, G = float(z[0]), float(z[1])
        s, c = np.sin(th), np.cos(th)
        psid = (G - R * c) / (s * s)
        nodes = _Nodes(tau, th, thd, s, c, np.cos(0.5 * th), np.sin(0.5 * th), psid * s,
                       R / self.mu)  # fmt: skip
        if self.rates_only:
            # One call on 8 nodes of φ serves the levels 4 and 8.
            circle = functools.partial(self.on_circle, nodes)
            first = circle(np.arange(8, dtype=np.float64) * (2.0 * math.pi / 8))
            mean, _ = torus_mean(
                circle, 1, rtol=self.rtol, n_start=SPIN_START, n_max=SPIN_MAX, known=first,
                what=f"{self.name} over φ",
            )  # fmt: skip
        else:
            torus = functools.partial(self.on_torus, nodes)
            what = f"{self.name} over ψ and φ"
            mean, _ = torus_mean(torus, 2, rtol=self.rtol, n_start=4, what=what)
        out = np.zeros((5, mean.shape[1]))
        out[:3] = mean
        if self.ab_rate is not None:
            out[3:, :] = np.asarray(self.ab_rate(tau), dtype=float)[:, None]
        return out.reshape(5, *shape)

    def on_torus(self, n: _Nodes, psi: FloatArray, phi: FloatArray) -> FloatArray:
        """Φ at psi (m, 1), phi (1, m); the nodes' arrays are (n, m, m). The rates do not
        involve ψ, and the attitude's half-angle functions do not involve θ: each is formed on
        its own axes and broadcast once, into the arrays handed to the torque."""
        sp, cp, cup, cum, sum_, sup = self.angles(psi, phi)
        grid = (n.th.shape[0], psi.shape[0], phi.shape[1])
        omega = np.empty((*grid, 3))
        omega[..., 0] = n.rate_sin * sp + n.thd * cp
        omega[..., 1] = n.rate_sin * cp - n.thd * sp
        omega[..., 2] = n.r
        # z–x–z angles → quaternion: q = qz(ψ) ⊗ qx(θ) ⊗ qz(φ).
        q = np.empty((*grid, 4))
        q[..., 0] = n.ch * cup
        q[..., 1] = n.sh * cum
        q[..., 2] = n.sh * sum_
        q[..., 3] = n.ch * sup
        m = self.call(n.tau, q.reshape(-1, 4), omega.reshape(-1, 3)).reshape(omega.shape)
        return _phis(m, sp, cp, n.s, n.c)

    def on_circle(self, n: _Nodes, phi: FloatArray) -> FloatArray:
        """Φ of a torque of the body rate alone: phi (m,), the nodes' arrays (n, m); no ψ, no
        q (the torque is called with q = None)."""
        sp, cp = np.sin(phi), np.cos(phi)
        omega = np.empty((n.th.shape[0], phi.size, 3))
        omega[..., 0] = n.rate_sin[:, :, 0] * sp + n.thd[:, :, 0] * cp
        omega[..., 1] = n.rate_sin[:, :, 0] * cp - n.thd[:, :, 0] * sp
        omega[..., 2] = n.r
        torque: Any = self.torque
        m = np.asarray(torque(n.tau, None, omega), dtype=float)
        if not np.all(np.isfinite(m)):
            raise AveragingError(
                "the torque returned non-finite values on the nutation (1.9): no average "
                "can be formed"
            )
        return _phis(m, sp, cp, n.s[:, :, 0], n.c[:, :, 0])


def _phis(m: FloatArray, sp: Any, cp: Any, s: FloatArray, c: FloatArray) -> FloatArray:
    """Φθ = M_p cos φ − M_q sin φ, Φ_R = M_r, Φ_G = (M_p sin φ + M_q cos φ) sin θ + M_r cos θ
    of body moments m (..., 3)."""
    m1, m2, m3 = m[..., 0], m[..., 1], m[..., 2]
    out = np.empty((3, *m.shape[:-1]))
    out[0] = m1 * cp - m2 * sp
    out[1] = m3
    out[2] = (m1 * sp + m2 * cp) * s + m3 * c
    return out


# ---------------------------------------------------------------------------------------------
# The nutation as the fast phase of second-order averaging.

NUTATION_NODES = 32
"""First number of phase nodes of :class:`NutationSystem` (doubled until resolved): θ(t) on
an orbit away from a separatrix is analytic, its harmonics fall geometrically."""

_ORBIT_STEP = 1e-5
"""Central differences between neighbouring orbits take steps of this size relative to the
slow variable's scale."""


class NutationSystem:
    """The reduced motion θ'' = −F(θ, z) + εΦθ, z' = εΦz in the standard form of
    :mod:`tumble.averaging.second_order`: slow x = (H, R, G, a, b), one phase w.

    w is the angle variable of the nutation, 2πt/T from the turning point θmax of the orbit of
    energy H (:meth:`NutationOrbit.from_energy`), turning at ν = 2π/T(H, z). The slow rates
    are f = ε(Φθθ' + W^z·Φz, Φz) at the orbit's nodes; the phase's perturbation is

        g = ε(∂w/∂θ' Φθ + ∂w/∂z·Φz),  ∂w/∂θ' = −ν Θ_H,
        ∂w/∂z = −ν(V_H Θ_z|_J − Θ_H V_z|_J),  Θ_z|_J = Θ_z|_H + Θ_H ⟨W_z⟩,

    with θ = Θ(w; H, z), θ' = V(w; H, z) the orbit at fixed phase: the angle's derivatives
    along the perturbation follow from the action–angle variables (J, w) being canonical
    (det ∂(θ, θ')/∂(w, J) = 1, ∂H/∂J = ν) and from ∂H/∂z at fixed action, ⟨W_z⟩ (the mean of
    ∂W/∂z over the orbit). Every derivative in H and z at fixed phase is a central difference
    between neighbouring orbits, their nodes at the same phases; ∂f/∂x comes the same way,
    whole, so that (∂f/∂x)u at the nodes is a contraction.

    Parameters
    ----------
    mu : float
        C/A [1].
    perturbation : Perturbation
        Φθ, Φz (without ε).
    eps : float
        ε [1].
    u_hint : float
        cos θ inside the well of the motion (kept up to date as the orbits move).
    """

    def __init__(self, mu: float, perturbation: Perturbation, eps: float, u_hint: float) -> None:
        self.mu, self.perturbation, self.eps = mu, perturbation, eps
        self.u_hint = u_hint
        self.n = NUTATION_NODES

    def orbit(self, x: FloatArray) -> NutationOrbit:
        """The orbit of energy x[0] in the well of ``u_hint``, z = x[1:]."""
        H, R, G, a, b = (float(v) for v in x)
        return NutationOrbit.from_energy(self.mu, a, b, R, G, H, self.u_hint)

    def _on_rows(self, tau: float, X: FloatArray, n: int) -> _Orbits:
        """The orbits of the rows of X at their n phase nodes: the nodes of all rows in one
        compiled call (:func:`tumble.kernels.nutation.orbit_nodes`), the Python orbit's for a
        row it does not serve (next to a pole, or none: the orbit then says why)."""
        X = np.ascontiguousarray(X, dtype=float)
        thetas, dots, info = orbit_nodes(X, self.u_hint, n)
        for r in np.flatnonzero(np.isnan(info[:, 0])):
            orbit = self.orbit(X[r])
            _, thetas[r], dots[r], _ = orbit.nodes(n)
            info[r] = 2.0 * math.pi / orbit.period, orbit.u1, orbit.u2
        if self.perturbation.rows:
            Z = X[:, 1:].T[:, :, None]
            ph, pz = self.perturbation.evaluate(tau, thetas, dots, Z)
            pz = np.moveaxis(pz, 0, 1)  # (k, 4, n)
            gradient = np.moveaxis(potential_gradient(np.cos(thetas), Z), 0, 1)
        else:
            each = [self.perturbation.evaluate(tau, th, thd, x[1:])
                    for x, th, thd in zip(X, thetas, dots, strict=True)]  # fmt: skip
            ph = np.stack([e[0] for e in each])
            pz = np.stack([e[1] for e in each])
            gradient = np.stack([potential_gradient(np.cos(th), x[1:])
                                 for x, th in zip(X, thetas, strict=True)])  # fmt: skip
        f = np.concatenate([(ph * dots + np.sum(pz * gradient, axis=1))[:, None], pz], axis=1)
        middle = 0.5 * (info[:, 1] + info[:, 2])
        return _Orbits(thetas, dots, self.eps * f, ph, pz, info[:, 0], middle)

    def terms(self, t: float, x: ArrayLike, generator_order: int = 1) -> SecondOrder:
        """:class:`~tumble.averaging.second_order.SecondOrder` at the slow state x (t is the
        fast time; the slow time εt is the perturbation's)."""
        x = np.asarray(x, dtype=float)
        tau = self.eps * t
        scale = np.maximum(np.abs(x), 1.0)
        # The orbit and its neighbours, Θ, V, f and ν at fixed phase to be differentiated in
        # each slow variable, in one call; the grid is resolved on the orbit's f.
        steps = _ORBIT_STEP * scale
        rows = np.concatenate([x[None, :], x + np.diag(steps), x - np.diag(steps)])

        def on(shape: tuple[int, ...]) -> tuple[FloatArray, _Orbits]:
            orbits = self._on_rows(tau, rows, shape[0])
            return orbits.f[0], orbits

        found, (n,) = refine_grid(on, (self.n,))
        self.n = n  # kept also when refused: the next state starts from the finest grid tried
        if found is None:
            raise AveragingError(
                f"the nutation needs more than {GRID_MAX} phase nodes at H = {x[0]:.6g}: "
                "the orbit is too near a separatrix"
            )
        theta, f, ph, pz, nu = found.theta[0], found.f[0], found.ph[0], found.pz[0], found.nu[:1]
        self.u_hint = float(found.hint[0])
        up, down, two_h = slice(1, 6), slice(6, 11), 2.0 * steps
        d_theta = (found.theta[up] - found.theta[down]) / two_h[:, None]
        d_dot = (found.theta_dot[up] - found.theta_dot[down]) / two_h[:, None]
        d_f = np.moveaxis((found.f[up] - found.f[down]) / two_h[:, None, None], 0, 1)
        d_nu = ((found.nu[up] - found.nu[down]) / two_h)[None, :]
        z = x[1:]
        mean_wz = potential_gradient(np.cos(theta), z).mean(axis=1)  # ⟨W_z⟩, (4,)
        theta_z = d_theta[1:] + d_theta[0] * mean_wz[:, None]  # at fixed action
        dot_z = d_dot[1:] + d_dot[0] * mean_wz[:, None]
        w_v = -nu[0] * d_theta[0]
        w_z = -nu[0] * (d_dot[0] * theta_z - d_theta[0] * dot_z)
        g = self.eps * (w_v * ph + np.add.reduce(w_z * pz))[None, :]

        def along(u: FloatArray) -> FloatArray:
            return np.einsum("cin,in->cn", d_f, u)

        def rates_at(y: FloatArray) -> tuple[FloatArray, FloatArray]:
            orbits = self._on_rows(tau, y[None, :], n)
            return orbits.f[0], orbits.nu[:1]

        def drift(first: FloatArray) -> FloatArray:
            size = float(np.max(np.abs(first) / scale))
            h = _ORBIT_STEP / size if size > 0.0 else 0.0
            return generator_drift(rates_at, x, first, h, f)

        return grid_terms(t, x, f, g, nu, d_nu, along, drift if generator_order == 2 else None)

    def frequencies(self, x: FloatArray) -> FloatArray:
        """ν = 2π/T of the orbit of x [rad/t]."""
        return np.array([2.0 * math.pi / self.orbit(x).period])
