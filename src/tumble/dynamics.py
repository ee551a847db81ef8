"""Full rotational dynamics: Euler's equations with quaternion kinematics, for any torque.

State vector ``y = [ω1, ω2, ω3, q0, q1, q2, q3]``: body angular velocity and the attitude
quaternion (scalar first, body → inertial).
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.bodies import RigidBody
from tumble.kernels import KIND_ORBITING_BODY, KIND_RIGID_BODY, Kernel
from tumble.kernels.rhs import euler_quaternion
from tumble.rotations import quat_normalize, quat_to_matrix
from tumble.torques import Torque

__all__ = [
    "angular_momentum_inertial",
    "rigid_body_kernel",
    "rigid_body_rhs",
    "rigid_body_state",
]


def rigid_body_rhs(
    t: float, y: FloatArray, inertia: FloatArray, torque: Torque | None
) -> FloatArray:
    """Right-hand side of Euler's equations and quaternion kinematics.

    ``I dω/dt = −ω × (I ω) + M(t, q, ω)``, ``dq/dt = ½ q ⊗ (0, ω)``. The torque is evaluated
    here (it may be a Python function); the equations are the compiled ones the integrator
    runs (:func:`tumble.kernels.rhs.euler_quaternion`).

    Parameters
    ----------
    t : float
        Time [problem time unit].
    y : ndarray, shape (7,)
        State ``[ω, q]`` [rad/time, 1].
    inertia : ndarray, shape (3,)
        Principal moments (I1, I2, I3) [problem inertia unit].
    torque : Torque or None
        External moment in body axes; None for the free body.

    Returns
    -------
    ndarray, shape (7,)
        dy/dt.
    """
    state = np.ascontiguousarray(y, dtype=np.float64)
    if torque is None:
        moment = _ZERO
    else:
        q = state[3:]
        moment = np.asarray(torque(t, q / math.sqrt(float(q @ q)), state[:3]), dtype=np.float64)
    return euler_quaternion(state, np.asarray(inertia, dtype=np.float64), moment)  # type: ignore[no-any-return]


_ZERO = np.zeros(3)
_NO_TORQUE = np.zeros(1)  # a program of no terms


def rigid_body_kernel(inertia: ArrayLike, torque: Torque | None) -> Kernel | None:
    """The compiled form of :func:`rigid_body_rhs` for principal moments ``inertia``
    [inertia unit] under ``torque`` (None: the free body); None if the torque is a Python
    function."""
    program = _NO_TORQUE if torque is None else torque.program
    if program is None:
        return None
    # A term along an orbit or calling out runs on the right-hand side of every term (a kind of
    # its own, so that the common one stays small and free of opaque calls).
    kind = KIND_ORBITING_BODY if torque is not None and torque.compiled_apart else KIND_RIGID_BODY
    return Kernel(kind, np.concatenate([np.asarray(inertia, dtype=float), program]))


def rigid_body_state(omega: FloatArray, q: FloatArray) -> FloatArray:
    """Pack body angular velocity [rad/time] and attitude quaternion into a state vector."""
    return np.concatenate([np.asarray(omega, dtype=float), quat_normalize(q)])


def angular_momentum_inertial(body: RigidBody, y: FloatArray) -> FloatArray:
    """Inertial components of K = R(q) I ω for states ``y`` of shape (..., 7)."""
    K_body = body.angular_momentum(y[..., :3])
    return np.einsum("...ij,...j->...i", quat_to_matrix(y[..., 3:]), K_body)
