"""The triaxial body as a fast system of second-order averaging: slow (L_ξ, T), the angle
variables of the Euler–Poinsot motion, and a forcing phase.

Slow x = (L_ξ1, L_ξ2, L_ξ3, T): the inertial angular momentum and the kinetic energy. Phases:
w1, the polhode phase (2πτ/T_p from a reference point of the polhode), w2, the precession
angle variable about L (uniform, at the mean precession rate ν2), and, for a torque with a
periodic time dependence, w3 = 2πt/T_f. On the torus the attitude is

    A(w) = F(L̂) Rz(w2 + P(w1)) C(τ),   τ = w1 T_p/2π,

with C(τ) = Rx(θ(τ)) Rz(φ(τ)) P_polar the free motion's body → L-frame rotation without its
precession ψ(τ), P(w1) = ψ(τ) − ν2 τ the periodic part of ψ, and F(L̂) a frame whose third
column is L̂ (its first axis from a fixed auxiliary direction, so that F is smooth in L̂). Along
the free motion w1 and w2 turn uniformly and A(w(t)) is the Euler–Poinsot attitude.

The slow rates are exact: dL_ξ/dt = A εM, dT/dt = ω·εM. The phases' perturbation follows from
the forward map Y(x, w) = (attitude, body momentum L_b = Iω): the perturbation of the full
equations is δL_b = εM at a fixed attitude, and (ẋ, ẇ) solve ∂Y/∂(x, w) · (ẋ, ẇ) = (0, εM)
at each node, the attitude's part as an inertial rotation vector. Its columns are central
differences between neighbouring motions in x at fixed phases, spectral derivatives in w1, and
the rotation about L̂ for w2. (The slow rows reproduce the exact rates, a check of the map.)

The polhode of given (|L|, T) is one of two tori, mirror images through the body, told apart
by the sign of the body momentum along the polar axis (axis 3 in regime x3, axis 1 in regime
x1): the ``sign`` of a system, constant away from the separatrix. A hybrid run, whose full
legs may take the body across the separatrix onto either torus, tells the system which one it
is on from its return on (:meth:`TriaxialSystem.reorient`); the terms at a time are those of
the torus the body was on then.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.quadrature import AveragingError, BatchedTorque
from tumble.averaging.second_order import (
    GRID_MAX,
    SecondOrder,
    generator_drift,
    grid_terms,
    refine_grid,
    resonance_table,
)
from tumble.bodies import proper_sorting
from tumble.rotations import matrix_to_quat, rot_x, rot_z
from tumble.unperturbed.euler_poinsot import EulerPoinsot, fast_frequencies

__all__ = ["TriaxialSystem"]


def _polhode_frames(ep: EulerPoinsot, tau: ArrayLike) -> tuple[FloatArray, ...]:
    """Along the free motion ``ep`` at times τ: the body rate ω (shape (n, 3)), the rotation
    C(τ) = Rx(θ) Rz(φ) P_polar without the precession (shape (n, 3, 3)) and the periodic part
    P = ψ − ν2 τ of the precession (shape (n,)) (module notes)."""
    tau = np.asarray(tau, dtype=float)
    psi, theta, phi = ep.euler_angles(tau)
    C = rot_x(theta) @ rot_z(phi) @ ep.polar_frame
    return ep.omega(tau), C, psi - ep.nu2 * tau


def _mirror_sign(inertia: FloatArray, x: FloatArray, omega: FloatArray) -> float:
    """The torus of the body rate ω with slow state x (module notes): the sign of its
    momentum along the polar axis of its regime."""
    Is = np.sort(inertia)
    zs = proper_sorting(inertia) @ np.asarray(omega, dtype=float)
    polar = 2 if float(x[:3] @ x[:3]) > 2.0 * float(x[3]) * Is[1] else 0
    return 1.0 if zs[polar] >= 0.0 else -1.0


_STEP = 1e-6
"""Central differences between neighbouring motions: steps of this size relative to |L|
(the energy's relative to T)."""


def _vee(S: FloatArray) -> FloatArray:
    """The vector of (the skew part of) matrices S, shape (..., 3)."""
    return 0.5 * np.stack(
        [S[..., 2, 1] - S[..., 1, 2], S[..., 0, 2] - S[..., 2, 0], S[..., 1, 0] - S[..., 0, 1]], -1
    )


class TriaxialSystem:
    """The fast system of a triaxial body under ``eps·torque`` (module notes).

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments in the user's axis order [inertia unit].
    torque : callable
        ``torque(t, q, ω) -> body moment`` (batched; any :class:`~tumble.torques.Torque`).
    eps : float
        Its factor ε [1].
    sign : {+1, −1}
        Which of the two mirror tori (module notes).
    auxiliary : array_like, shape (3,)
        The fixed direction F(L̂)'s first axis is built from (not parallel to L̂).
    forcing_period : float, optional
        Period of the torque's explicit time dependence [time].
    """

    def __init__(
        self,
        inertia: ArrayLike,
        torque: Callable[..., Any],
        eps: float,
        sign: float,
        auxiliary: ArrayLike,
        forcing_period: float | None = None,
    ) -> None:
        self.inertia = np.asarray(inertia, dtype=float)
        self.Q = proper_sorting(self.inertia)
        self.sorted = np.sort(self.inertia)
        self.torque = BatchedTorque(torque, None, "the Euler–Poinsot motion")
        self.eps, self.sign = float(eps), float(sign)
        # The torus from each time on: (time, sign), ascending (reorient).
        self._signs: list[tuple[float, float]] = [(-math.inf, self.sign)]
        self.auxiliary = np.asarray(auxiliary, dtype=float)
        self.period = forcing_period
        self.grid: tuple[int, ...] = (32, 8) if forcing_period is None else (32, 8, 8)
        self.residual = math.nan  # of the last terms: the Jacobian's slow rows − the rates

    @classmethod
    def through(
        cls,
        inertia: ArrayLike,
        torque: Callable[..., Any],
        eps: float,
        omega: ArrayLike,
        attitude: ArrayLike,
        forcing_period: float | None = None,
    ) -> tuple[TriaxialSystem, FloatArray, FloatArray]:
        """The system of the torus through the state (ω, A) at t = 0, with that state's slow
        variables x = (A Iω, ½ω·Iω) and phases w (w3 = 0 at t = 0)."""
        inertia_ = np.asarray(inertia, dtype=float)
        w = np.asarray(omega, dtype=float)
        A = np.asarray(attitude, dtype=float)
        L_xi = A @ (inertia_ * w)
        x = np.array([*L_xi, 0.5 * float(w @ (inertia_ * w))])
        auxiliary = np.zeros(3)
        auxiliary[int(np.argmin(np.abs(L_xi)))] = 1.0
        system = cls(inertia_, torque, eps, _mirror_sign(inertia_, x, w), auxiliary,
                     forcing_period)  # fmt: skip
        return system, x, system.phases_of(x, w, A)

    def _polished(self, ep: EulerPoinsot, s: float, omega: FloatArray) -> float:
        """The polhode time of ω from ``s``, the search's minimum of |ω(s) − ω|², refined by
        Gauss–Newton steps along ω̇ = I⁻¹(Iω × ω) (the search finds a minimum only to about
        √(1e-16) of the period: the distance is flat there), kept while they shorten the
        distance; modulo the period."""
        miss = float(np.sum((ep.omega(np.array([s]))[0] - omega) ** 2))
        for _ in range(4):
            w = ep.omega(np.array([s]))[0]
            rate = np.cross(self.inertia * w, w) / self.inertia
            size = float(rate @ rate)
            if size == 0.0:  # a uniform rotation: every time is the same state
                break
            trial = s - float((w - omega) @ rate) / size
            trial_miss = float(np.sum((ep.omega(np.array([trial]))[0] - omega) ** 2))
            if not trial_miss < miss:
                break
            s, miss = trial, trial_miss
        return s % ep.period

    def reorient(self, t: float, x: FloatArray, omega: FloatArray) -> None:
        """From time t on, the system is on the torus of the body rate ω (slow state x): its
        ``sign`` read off ω as :meth:`through` reads it at t = 0. A hybrid run calls it where
        it returns from the full equations, which may have taken the body across the
        separatrix onto either torus; the terms at earlier times keep their torus."""
        sign = _mirror_sign(self.inertia, np.asarray(x, dtype=float), np.asarray(omega))
        self._signs = [entry for entry in self._signs if entry[0] < t] + [(float(t), sign)]
        self.sign = sign

    def _at(self, t: float) -> None:
        """Take the torus the body was on at time t (:meth:`reorient`)."""
        i = bisect.bisect_right([entry[0] for entry in self._signs], t) - 1
        self.sign = self._signs[max(i, 0)][1]

    def state_at(self, x: FloatArray, w: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The body rate ω [rad/time] and attitude A (body → inertial) at the phases w on the
        torus of x: the forward map of the module notes at one point, the inverse of
        :meth:`phases_of`."""
        x = np.asarray(x, dtype=float)
        w = np.asarray(w, dtype=float)
        ep = self._reference(x)
        tau = (float(w[0]) % (2.0 * math.pi)) * ep.period / (2.0 * math.pi)
        omega, C, P = _polhode_frames(ep, np.array([tau]))
        return omega[0], self._frame(x[:3]) @ rot_z(float(w[1]) + float(P[0])) @ C[0]

    def phases_of(self, x: FloatArray, omega: FloatArray, attitude: FloatArray) -> FloatArray:
        """The phases (w1, w2[, 0]) of the state (ω, A) on the torus of x [rad]."""
        from scipy.optimize import minimize_scalar  # loaded where a run starts

        ep = self._reference(x)
        n = 512
        tau = np.arange(n) * (ep.period / n)
        miss = np.sum((ep.omega(tau) - omega) ** 2, axis=1)
        i = int(np.argmin(miss))
        step = ep.period / n
        best = minimize_scalar(
            lambda s: float(np.sum((ep.omega(np.array([s]))[0] - omega) ** 2)),
            bounds=(tau[i] - step, tau[i] + step),
            method="bounded",
            options={"xatol": 1e-14 * ep.period},
        )
        t_star = self._polished(ep, float(best.x), np.asarray(omega, dtype=float))
        _, C, P = _polhode_frames(ep, np.array([t_star]))
        R = self._frame(x[:3]).T @ attitude @ C[0].T
        chi = math.atan2(R[1, 0], R[0, 0])
        w1 = 2.0 * math.pi * t_star / ep.period
        w2 = chi - float(P[0])
        return np.array([w1, w2] + ([0.0] if self.period else []))

    # -- the unperturbed motion ------------------------------------------------------------

    def frequencies(self, x: FloatArray) -> FloatArray:
        """ν = (ν1, ν2[, 2π/T_f]) [rad/time]."""
        L = float(np.linalg.norm(x[:3]))
        I1, I2, I3 = (float(v) for v in self.sorted)
        nu1, nu2 = fast_frequencies(I1, I2, I3, L, float(x[3]))
        out = [nu1, nu2] + ([2.0 * math.pi / self.period] if self.period else [])
        return np.array(out)

    def _reference(self, x: FloatArray) -> EulerPoinsot:
        """The free motion of (|L|, T) started at the polhode's reference point."""
        I1, I2, I3 = self.sorted
        L2, T2 = float(x[:3] @ x[:3]), 2.0 * float(x[3])
        z1 = math.sqrt(max((I3 * T2 - L2) / (I1 * (I3 - I1)), 0.0))
        z3 = math.sqrt(max((L2 - I1 * T2) / (I3 * (I3 - I1)), 0.0))
        if L2 > T2 * I2:  # regime x3: the polar axis is 3
            zs = np.array([z1, 0.0, self.sign * z3])
        else:
            zs = np.array([self.sign * z1, 0.0, z3])
        return EulerPoinsot.from_state(self.inertia, self.Q.T @ zs)

    def _frame(self, L: FloatArray) -> FloatArray:
        e3 = L / np.linalg.norm(L)
        e1 = np.cross(self.auxiliary, e3)
        e1 /= np.linalg.norm(e1)
        return np.stack([e1, np.cross(e3, e1), e3], axis=1)

    def states(self, x: FloatArray, shape: tuple[int, ...]) -> tuple[FloatArray, ...]:
        """Attitudes A (shape (*shape[:2], 3, 3)), body rates ω (shape (shape[0], 3)) and
        the forcing times (shape (shape[2],) or (1,)) on the phase grid of ``shape``."""
        ep = self._reference(x)
        n1, n2 = shape[0], shape[1]
        w1 = np.arange(n1) * (2.0 * math.pi / n1)
        omega, C, P = _polhode_frames(ep, w1 * ep.period / (2.0 * math.pi))
        w2 = np.arange(n2) * (2.0 * math.pi / n2)
        R = rot_z(w2[None, :] + P[:, None])  # (n1, n2, 3, 3)
        A = self._frame(x[:3]) @ R @ C[:, None]
        if len(shape) > 2:
            t = np.arange(shape[2]) * (self.period / shape[2])  # type: ignore[operator]
        else:
            t = np.zeros(1)
        return A, omega, t

    def _rates(self, x: FloatArray, shape: tuple[int, ...]) -> tuple[FloatArray, ...]:
        """f (shape (4, *shape)), the body moment εM (shape (*shape, 3)), A and ω."""
        A, omega, t = self.states(x, shape)
        n1, n2 = shape[0], shape[1]
        q = matrix_to_quat(A).reshape(-1, 4)
        w = np.broadcast_to(omega[:, None, :], (n1, n2, 3)).reshape(-1, 3)
        M = np.empty((n1, n2, t.size, 3))
        for j, tj in enumerate(t):
            M[:, :, j] = np.broadcast_to(self.torque(float(tj), q, w), (n1 * n2, 3)).reshape(
                n1, n2, 3
            )
        M *= self.eps
        f = np.empty((4, n1, n2, t.size))
        f[:3] = np.moveaxis(np.einsum("abij,abkj->abki", A, M), -1, 0)
        f[3] = np.einsum("ai,abki->abk", omega, M)
        if len(shape) == 2:
            f, M = f[..., 0], M[:, :, 0]
        return f, M, A, omega

    # -- the terms -------------------------------------------------------------------------

    def terms(self, t: float, x: ArrayLike, generator_order: int = 1) -> SecondOrder:
        """:class:`~tumble.averaging.second_order.SecondOrder` at the slow state x."""
        x = np.asarray(x, dtype=float)
        self._at(t)

        (f, M, A, omega), shape = self._resolved(x)
        n1, n2 = shape[0], shape[1]
        steps = self._steps(x)
        # Neighbouring motions at fixed phases: the Jacobian's slow columns and ∂f/∂x.
        d_att = np.empty((4, n1, n2, 3))
        d_mom = np.empty((4, n1, 3))
        d_f = np.empty((4, *f.shape))
        for i in range(4):
            up, down = x.copy(), x.copy()
            up[i] += steps[i]
            down[i] -= steps[i]
            fu, _, Au, wu = self._rates(up, shape)
            fd, _, Ad, wd = self._rates(down, shape)
            dA = (Au - Ad) / (2.0 * steps[i])
            d_att[i] = _vee(dA @ np.swapaxes(A, -1, -2))
            d_mom[i] = (wu - wd) / (2.0 * steps[i]) * self.inertia
            d_f[:, i] = (fu - fd) / (2.0 * steps[i])
        # The phases' columns: w1 spectrally, w2 the rotation about L̂.
        k1 = np.fft.fftfreq(n1) * n1
        if n1 % 2 == 0:
            k1[n1 // 2] = 0.0

        def d_w1(values: FloatArray) -> FloatArray:
            return np.fft.ifft(1j * k1.reshape(-1, *([1] * (values.ndim - 1)))
                               * np.fft.fft(values, axis=0), axis=0).real  # fmt: skip

        att_w1 = _vee(d_w1(A) @ np.swapaxes(A, -1, -2))  # (n1, n2, 3)
        mom_w1 = d_w1(omega * self.inertia)  # (n1, 3)
        J = np.zeros((n1, n2, 6, 6))
        J[..., :3, :4] = np.moveaxis(d_att, 0, -1)
        J[..., 3:, :4] = np.moveaxis(d_mom, 0, -1)[:, None]
        J[..., :3, 4] = att_w1
        J[..., 3:, 4] = mom_w1[:, None]
        J[..., :3, 5] = x[:3] / float(np.linalg.norm(x[:3]))
        rhs = np.zeros((*M.shape[:-1], 6))
        rhs[..., 3:] = M
        if len(shape) > 2:
            sol = np.linalg.solve(J[:, :, None], rhs[..., None])[..., 0]
            g = np.asarray(np.moveaxis(sol[..., 4:], -1, 0), dtype=float)
            g = np.concatenate([g, np.zeros((1, *shape))])
        else:
            sol = np.linalg.solve(J, rhs[..., None])[..., 0]
            g = np.asarray(np.moveaxis(sol[..., 4:], -1, 0), dtype=float)
        # The solve's slow rows against the exact rates: how well the map is differentiated.
        self.residual = float(np.max(np.abs(np.moveaxis(sol[..., :4], -1, 0) - f)))
        nu = self.frequencies(x)

        def along(u: FloatArray) -> FloatArray:
            return np.einsum("ci...,i...->c...", d_f, u)

        def rates_at(y: FloatArray) -> tuple[FloatArray, FloatArray]:
            return self._rates(y, shape)[0], self.frequencies(y)

        def drift(first: FloatArray) -> FloatArray:
            size = float(np.max(np.abs(first) / np.abs(steps / _STEP)))
            h = _STEP / size if size > 0.0 else 0.0
            return generator_drift(rates_at, x, first, h, f)

        d_nu = self._frequency_jacobian(x, steps)
        return grid_terms(t, x, f, g, nu, d_nu, along, drift if generator_order == 2 else None)

    def resonances(
        self, t: float, x: ArrayLike, omega: ArrayLike | None = None
    ) -> dict[tuple[int, ...], float]:
        """The signed distances from the resonances at the slow state x, on the torus the body
        was on at time t, or on that of the body rate ω where it is given (a full state's)
        (:func:`~tumble.averaging.second_order.resonance_table`): the terms' table without the
        generator, defined at a resonance too, where the generator meets a zero divisor."""
        x = np.asarray(x, dtype=float)
        if omega is None:
            self._at(t)
        else:  # until the next call that takes a time
            self.sign = _mirror_sign(self.inertia, x, np.asarray(omega, dtype=float))
        (f, *_), _ = self._resolved(x)
        drift = f.mean(axis=tuple(range(1, f.ndim)))
        return resonance_table(f, self.frequencies(x), self._frequency_jacobian(x, self._steps(x)),
                               drift)  # fmt: skip

    def _resolved(self, x: FloatArray) -> tuple[tuple[FloatArray, ...], tuple[int, ...]]:
        """:meth:`_rates` on the grid that resolves them (from the last one) and its shape."""

        def on(shape: tuple[int, ...]) -> tuple[FloatArray, tuple[FloatArray, ...]]:
            rates = self._rates(x, shape)
            return rates[0], rates

        found, shape = refine_grid(on, self.grid)
        if found is None:
            raise AveragingError(
                f"the Euler–Poinsot motion needs more than {GRID_MAX} phase nodes at "
                f"x = {x.tolist()}: too near the separatrix"
            )
        self.grid = shape
        return found, shape

    @staticmethod
    def _steps(x: FloatArray) -> FloatArray:
        """The central differences' steps in (L_ξ, T) (:data:`_STEP`)."""
        L = float(np.linalg.norm(x[:3]))
        return np.array([_STEP * L] * 3 + [_STEP * float(x[3])])

    def _frequency_jacobian(self, x: FloatArray, steps: FloatArray) -> FloatArray:
        """∂ν/∂x by central differences, shape (d, 4)."""
        columns = []
        for i in range(4):
            up, down = x.copy(), x.copy()
            up[i] += steps[i]
            down[i] -= steps[i]
            columns.append((self.frequencies(up) - self.frequencies(down)) / (2.0 * steps[i]))
        return np.stack(columns, -1)
