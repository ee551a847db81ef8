"""Full rotational dynamics: Euler's equations with quaternion kinematics, for any torque.

State vector ``y = [ω1, ω2, ω3, q0, q1, q2, q3]``: body angular velocity and the attitude
quaternion (scalar first, body → inertial).
"""

from __future__ import annotations

import math

import numpy as np

from tumble._typing import FloatArray
from tumble.bodies import RigidBody
from tumble.rotations import quat_normalize, quat_to_matrix
from tumble.torques import Torque

__all__ = ["angular_momentum_inertial", "rigid_body_rhs", "rigid_body_state"]


def rigid_body_rhs(
    t: float, y: FloatArray, inertia: FloatArray, torque: Torque | None
) -> FloatArray:
    """Right-hand side of Euler's equations and quaternion kinematics.

    ``I dω/dt = −ω × (I ω) + M(t, q, ω)``, ``dq/dt = ½ q ⊗ (0, ω)``.

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
    # Plain floats: this runs ~1e5–1e6 times per trajectory and numpy scalars are slow.
    w1, w2, w3, q0, q1, q2, q3 = y.tolist()
    i1, i2, i3 = inertia.tolist()
    if torque is None:
        m1 = m2 = m3 = 0.0
    else:
        norm = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        m1, m2, m3 = torque(t, y[3:] / norm, y[:3]).tolist()
    return np.array(
        [
            ((i2 - i3) * w2 * w3 + m1) / i1,
            ((i3 - i1) * w3 * w1 + m2) / i2,
            ((i1 - i2) * w1 * w2 + m3) / i3,
            0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
            0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
            0.5 * (q0 * w2 - q1 * w3 + q3 * w1),
            0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
        ]
    )


def rigid_body_state(omega: FloatArray, q: FloatArray) -> FloatArray:
    """Pack body angular velocity [rad/time] and attitude quaternion into a state vector."""
    return np.concatenate([np.asarray(omega, dtype=float), quat_normalize(q)])


def angular_momentum_inertial(body: RigidBody, y: FloatArray) -> FloatArray:
    """Inertial components of K = R(q) I ω for states ``y`` of shape (..., 7)."""
    K_body = body.angular_momentum(y[..., :3])
    return np.einsum("...ij,...j->...i", quat_to_matrix(y[..., 3:]), K_body)
