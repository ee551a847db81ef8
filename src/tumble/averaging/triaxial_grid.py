"""The states of the triaxial averaging grid and a torque evaluated on them.

The product grid of :mod:`tumble.averaging.triaxial` (the polhode phase, the precession angle
about L and, with a forcing, the time) holds the attitude ``A = F Rz(χ) G(τ)``, the body rate
and the inertial rate at every node, in arrays that broadcast over the phases
(:class:`_Grid`). :class:`_Moment` evaluates a torque there: the built-in torques of
:mod:`tumble.torques` on the whole grid at once, any other torque with the package's batched
convention (q of shape (N, 4), omega (N, 3), one time per call), checked against one-state
calls, or one state at a time if it does not follow it.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cached_property
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.quadrature import BatchedTorque
from tumble.rotations import quat_multiply
from tumble.torques import (
    ConstantBodyTorque,
    ConstantInertialTorque,
    EddyCurrentTorque,
    GravityGradientTorque,
    InternalDissipation,
    LinearDrag,
    QuadraticDrag,
    ScaledTorque,
    TorqueSum,
    ZeroTorque,
)


def _rotate(A: FloatArray, v: FloatArray) -> FloatArray:
    """A v for stacks of matrices and vectors that broadcast (matmul: faster than einsum)."""
    return np.matmul(A, v[..., None])[..., 0]


def _rotate_back(A: FloatArray, v: FloatArray) -> FloatArray:
    """Aᵀ v, broadcasting."""
    return np.matmul(np.swapaxes(A, -1, -2), v[..., None])[..., 0]


class _Grid:
    """States on the product grid in shapes that broadcast, (n0, n1[, 1], …): attitude
    ``A = F Rz(χ) G(τ)``, body rate ``omega``, inertial rate ``Omega``; A and the
    quaternions are built only when a torque asks for them."""

    def __init__(
        self,
        FRz: FloatArray,
        G: FloatArray,
        omega: FloatArray,
        Omega: FloatArray,
        q_factors: tuple[Callable[[], FloatArray], FloatArray, FloatArray],
        forced: bool,
    ) -> None:
        self._FRz, self._G, self._q_factors, self._forced = FRz, G, q_factors, forced
        self.omega, self.Omega = omega, Omega

    def _expand(self, x: FloatArray) -> FloatArray:
        return x[:, :, None] if self._forced else x

    @cached_property
    def A(self) -> FloatArray:
        return self._expand(np.matmul(self._FRz[None], self._G[:, None]))

    @cached_property
    def q_nodes(self) -> FloatArray:
        """Attitude quaternions of the (polhode, precession) nodes, shape (n0, n1, 4)."""
        q_F, q_z, q_G = self._q_factors
        return quat_multiply(quat_multiply(q_F(), q_z)[None], q_G[:, None])

    @property
    def omega_nodes(self) -> FloatArray:
        """Body rates at the same nodes, shape (n0, n1, 3)."""
        n0, n1 = self._G.shape[0], self._FRz.shape[0]
        return np.broadcast_to(self.omega.reshape(n0, 1, 3), (n0, n1, 3))


class _Moment:
    """A torque on the product grid, in inertial components A M (broadcasting (n0, n1[, n2])).

    Sums and multiples of built-in torques (exact types: a subclass may override
    ``__call__``) are walked term by term: the inertial-form ones (eddy current (1.3), constant
    inertial moment) are evaluated in inertial axes with the explicit time broadcast over the
    forcing axis, the time-independent body ones in one batched call on the grid's rates, the
    gravity gradient on the grid's attitude matrices with its r̂(t) broadcast over the forcing
    axis. Any other torque is called through :class:`BatchedTorque`, once per time node, with
    the N = n0·n1 attitudes of the grid. ``batched=False`` calls the whole torque, built-ins
    included, one state at a time (the reference for the fast paths).
    """

    def __init__(self, torque: Any, batched: bool | None) -> None:
        self.torque = torque
        self.batched = batched
        self._leaves: dict[int, BatchedTorque] = {}

    def inertial(self, t: FloatArray, g: _Grid) -> FloatArray:
        if self.batched is False:
            return _rotate(g.A, self._user(self.torque, t, g))
        return self._inertial(self.torque, t, g)

    def _inertial(self, torque: Any, t: FloatArray, g: _Grid) -> FloatArray:
        kind = type(torque)
        if kind is ZeroTorque:
            return np.zeros(3)
        if kind is ConstantInertialTorque:
            return np.array(torque.moment)
        if kind is EddyCurrentTorque:
            # (1.3); EddyCurrentTorque.inertial broadcasts t against Ω_ξ.
            return np.asarray(torque.inertial(t, g.Omega), dtype=float)
        if kind in (ScaledTorque, TorqueSum):
            return _termwise(torque, t, g, self._inertial)
        return _rotate(g.A, self._body(torque, t, g))

    def _body(self, torque: Any, t: FloatArray, g: _Grid) -> FloatArray:
        kind = type(torque)
        w = g.omega
        if kind in (ConstantBodyTorque, LinearDrag, QuadraticDrag, InternalDissipation):
            # Time-independent and batch-aware: one call on the grid's body rates.
            return np.asarray(torque(0.0, None, w), dtype=float)
        if kind in (ZeroTorque, ConstantInertialTorque, EddyCurrentTorque):
            return _rotate_back(g.A, self._inertial(torque, t, g))
        if kind is GravityGradientTorque:
            # M = 3n² r̂_b × (I r̂_b), r̂_b = Aᵀ r̂(t) the body components of its radial(t):
            # GravityGradientTorque.__call__ on the grid's matrices rather than quaternions,
            # with r̂(t) broadcast over the time axis (one evaluation, not one per time node).
            rb = _rotate_back(g.A, torque.radial(t))
            return 3.0 * torque.n**2 * np.cross(rb, torque.inertia * rb)
        if kind in (ScaledTorque, TorqueSum):
            return _termwise(torque, t, g, self._body)
        return self._user(torque, t, g)

    def _user(self, torque: Any, t: FloatArray, g: _Grid) -> FloatArray:
        """Body moments of a torque called with the batched convention, one time at a time."""
        q, w = g.q_nodes, g.omega_nodes  # (n0, n1, 4), (n0, n1, 3)
        n0, n1 = q.shape[:2]
        qf, wf = q.reshape(-1, 4), w.reshape(-1, 3)
        times = np.ravel(t)
        per_time = [self._call(torque, float(tj), qf, wf).reshape(n0, n1, 3) for tj in times]
        if t.ndim == 0:
            return per_time[0]
        return np.stack(per_time, axis=2)  # (n0, n1, n2, 3): t varies along the third axis

    def _call(self, torque: Any, t: float, q: FloatArray, w: FloatArray) -> FloatArray:
        call = self._leaves.get(id(torque))
        if call is None:
            call = BatchedTorque(torque, self.batched, "the Euler–Poinsot motion (3.1)")
            self._leaves[id(torque)] = call
        return call(t, q, w)


def _termwise(
    torque: Any,
    t: FloatArray,
    g: _Grid,
    part: Callable[[Any, FloatArray, _Grid], FloatArray],
) -> FloatArray:
    """A :class:`~tumble.torques.ScaledTorque` or a :class:`~tumble.torques.TorqueSum` on the
    grid, term by term (exact types, as :class:`_Moment` tests them): ``part(term, t, g)`` gives
    each term's moment (:meth:`_Moment._inertial` for inertial components, :meth:`_Moment._body`
    for body ones) [moment unit], scaled by the factor or summed in the order of the terms."""
    if type(torque) is ScaledTorque:
        return torque.factor * part(torque.torque, t, g)
    total: FloatArray = np.zeros(3)
    for term in torque.terms:
        total = total + part(term, t, g)
    return total
