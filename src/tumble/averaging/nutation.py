"""Volosov averaging over the nutation of a symmetric body (spec/serov.md §6–§8), for any
perturbation of (2.1) and for any small torque.

A perturbation is given either directly as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`) or
as a body-axes torque (:func:`torque_perturbation`), converted through (1.3a) and spec §6 and
averaged over the spin φ and the precession ψ (independent fast phases, the non-resonant
case). :func:`numeric_averages` then averages over the nutation period of the frozen orbit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.quadrature import AVERAGE_RTOL, AveragingError, BatchedTorque, torus_mean
from tumble.unperturbed.symmetric_body import NutationOrbit

__all__ = [
    "AVERAGE_RTOL",
    "Perturbation",
    "numeric_averages",
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
    """

    phi_theta: Callable[[float, FloatArray, FloatArray, FloatArray], Any] | None = None
    phi_z: Callable[[float, FloatArray, FloatArray], Any] | None = None
    name: str = "user"
    joint: Callable[[float, FloatArray, FloatArray, FloatArray], Any] | None = None

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
    """W^z = ∂W/∂z = (W_R, W_G, W_a, W_b) of (2.3), spec/serov.md §9, shape (4, n).

    Parameters
    ----------
    u : ndarray
        cos θ at the nodes [1].
    z : ndarray, shape (4,)
        (R, G, a, b) [1/t, 1/t, 1/t², 1/t²].
    """
    R, G = z[0], z[1]
    # (G − Ru)/(1 − u²) = ½[(G + R)/(1 + u) + (G − R)/(1 − u)] (1.12): a pole term whose
    # coefficient vanishes (G = ±R, the axis passing through ±e_z) is dropped, not 0/0.
    h = np.zeros_like(u, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        for c, d in ((G + R, 1.0 + u), (G - R, 1.0 - u)):
            if c != 0.0:
                h = h + 0.5 * c / d
    if not np.all(np.isfinite(h)):
        raise AveragingError(
            f"W_R, W_G = ∓(G − Ru)/(1 − u²) are singular on this orbit (G = {G:.3g}, "
            f"R = {R:.3g}): it passes through θ = 0 or π to round-off, where the numeric "
            "averages cannot be formed"
        )
    return np.array([-u * h, h, u, u * u])


def numeric_averages(
    orbit: NutationOrbit,
    perturbation: Perturbation,
    tau: float,
    *,
    rtol: float = AVERAGE_RTOL,
    n_start: int = 16,
    n_max: int = 1 << 14,
) -> tuple[float, FloatArray]:
    """⟨Φθθ' + Φz·W^z⟩ and ⟨Φz⟩ over one nutation period of ``orbit``, (2.3).

    Periodic trapezoidal rule in time over one period (spectrally accurate; better than the
    rule in γ near a separatrix), doubling the nodes until two results agree to ``rtol``.

    Parameters
    ----------
    orbit : NutationOrbit
        The frozen unperturbed motion.
    perturbation : Perturbation
    tau : float
        Slow time τ = εt (frozen) [1].
    rtol : float
        Relative tolerance of the averages.

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

    def averages(n: int) -> FloatArray:
        _, theta, theta_dot, w = orbit.nodes(n)
        ph, pz = perturbation.evaluate(tau, theta, theta_dot, z)
        g = ph * theta_dot + np.sum(pz * potential_gradient(np.cos(theta), z), axis=0)
        return np.concatenate([[w @ g], pz @ w])

    n = n_start
    old = averages(n)
    while n < n_max:
        n *= 2
        new = averages(n)
        scale = max(float(np.max(np.abs(new))), 1e-300)
        if np.max(np.abs(new - old)) <= rtol * scale:
            return float(new[0]), new[1:]
        old = new
    raise AveragingError(
        f"averages over the nutation period did not converge with {n_max} nodes "
        f"(k² = {orbit.k2:.12g}, 1 − k² = {orbit.mc:.3g}): the motion is too near a separatrix"
    )


def torque_perturbation(
    torque: Callable[[float, FloatArray, FloatArray], Any],
    mu: float,
    *,
    ab_rate: Callable[[float], tuple[float, float]] | None = None,
    rtol: float = AVERAGE_RTOL,
    name: str = "torque",
    vectorized: bool = True,
) -> Perturbation:
    """Φθ, Φz of (2.1) for a small body-axes torque, spec/serov.md §6.

    With δM the torque per unit A (``torque(t, q, omega)`` returns δM/A in body axes, q the
    body → inertial quaternion of the z–x–z angles ψ, θ, φ, omega the body rate):
    Φθ = δM_p cosφ − δM_q sinφ, Φ_R = δM_r, Φ_G = (δM_p sinφ + δM_q cosφ) sinθ + δM_r cosθ.
    These depend on ψ and φ as well; they are averaged over both (uniformly, as independent
    fast phases: the non-resonant case) before the nutation average.

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
        Whether to try batched calls first.

    Returns
    -------
    Perturbation
    """

    call = BatchedTorque(torque, None if vectorized else False, "the nutation (1.9)")

    def joint(tau: float, theta: FloatArray, theta_dot: FloatArray, z: FloatArray) -> FloatArray:
        th, thd = np.broadcast_arrays(np.asarray(theta, float), np.asarray(theta_dot, float))
        shape = th.shape
        th, thd = th.ravel()[:, None, None], thd.ravel()[:, None, None]
        R, G = float(z[0]), float(z[1])
        s, c = np.sin(th), np.cos(th)
        psid = (G - R * c) / (s * s)

        def on_torus(psi: FloatArray, phi: FloatArray) -> FloatArray:
            psi, phi = np.broadcast_arrays(psi, phi)
            sp, cp = np.sin(phi), np.cos(phi)
            w1 = psid * s * sp + thd * cp
            w2 = psid * s * cp - thd * sp
            w1, w2 = np.broadcast_arrays(w1, w2)
            omega = np.stack([w1, w2, np.full(w1.shape, R / mu)], axis=-1)
            # z–x–z angles → quaternion: q = qz(ψ) ⊗ qx(θ) ⊗ qz(φ).
            h, up, um = 0.5 * th, 0.5 * (psi + phi), 0.5 * (psi - phi)
            q = np.stack(
                np.broadcast_arrays(
                    np.cos(h) * np.cos(up),
                    np.sin(h) * np.cos(um),
                    np.sin(h) * np.sin(um),
                    np.cos(h) * np.sin(up),
                ),
                axis=-1,
            )
            m = call(tau, q.reshape(-1, 4), omega.reshape(-1, 3)).reshape(omega.shape)
            m1, m2, m3 = m[..., 0], m[..., 1], m[..., 2]
            return np.stack([m1 * cp - m2 * sp, m3, (m1 * sp + m2 * cp) * s + m3 * c], axis=0)

        mean, _ = torus_mean(on_torus, 2, rtol=rtol, n_start=4, what=f"{name} over ψ and φ")
        out = np.zeros((5, mean.shape[1]))
        out[:3] = mean
        if ab_rate is not None:
            out[3:, :] = np.asarray(ab_rate(tau), dtype=float)[:, None]
        return out.reshape(5, *shape)

    return Perturbation(name=name, joint=joint)
