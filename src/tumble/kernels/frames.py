"""Rotations in compiled code: the one quaternion → matrix function of the kernels, and the small
vector algebra the torque terms share.

A matrix is a tuple of nine floats by rows (:data:`~tumble.kernels.layout.Mat3`), the body →
inertial attitude ``a`` of the unit quaternion (scalar first) that
:func:`tumble.rotations.quat_to_matrix` gives from Python.
"""

from __future__ import annotations

import math

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Mat3, Vec3, vec3

__all__ = [
    "attitude_matrix",
    "dot",
    "matrix_quaternion",
    "node_turned",
    "node_turned_body",
    "quaternion_matrix",
    "quaternion_rates",
    "scaled_cross",
    "to_body",
    "to_inertial",
    "turned_about_z",
]


@jit(INLINE)
def quaternion_matrix(q0: float, q1: float, q2: float, q3: float) -> Mat3:
    """Body → inertial matrix (row by row) of a quaternion, normalised first
    (:func:`tumble.rotations.quat_to_matrix`)."""
    norm = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    q0, q1, q2, q3 = q0 / norm, q1 / norm, q2 / norm, q3 / norm
    return (
        1.0 - 2.0 * (q2 * q2 + q3 * q3), 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2),
        2.0 * (q1 * q2 + q0 * q3), 1.0 - 2.0 * (q1 * q1 + q3 * q3), 2.0 * (q2 * q3 - q0 * q1),
        2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), 1.0 - 2.0 * (q1 * q1 + q2 * q2),
    )  # fmt: skip


@jit(INLINE)
def attitude_matrix(y: FloatArray) -> Mat3:
    """Body → inertial matrix (row by row) of the quaternion y[3:7] of a state ``[ω, q]``."""
    return quaternion_matrix(y[3], y[4], y[5], y[6])


@jit(INLINE)
def to_body(a: Mat3, x1: float, x2: float, x3: float) -> Vec3:
    """Aᵀ x: inertial components to body ones."""
    return (
        a[0] * x1 + a[3] * x2 + a[6] * x3,
        a[1] * x1 + a[4] * x2 + a[7] * x3,
        a[2] * x1 + a[5] * x2 + a[8] * x3,
    )


@jit(INLINE)
def to_inertial(a: Mat3, x1: float, x2: float, x3: float) -> Vec3:
    """A x: body components to inertial ones."""
    return (
        a[0] * x1 + a[1] * x2 + a[2] * x3,
        a[3] * x1 + a[4] * x2 + a[5] * x3,
        a[6] * x1 + a[7] * x2 + a[8] * x3,
    )


@jit(INLINE)
def turned_about_z(angle: float, x: Vec3) -> Vec3:
    """Rz(angle) x: an inertial vector turned about ξ3 (the node's turn of an orbit's inputs)."""
    c, s = math.cos(angle), math.sin(angle)
    return c * x[0] - s * x[1], s * x[0] + c * x[1], x[2]


@jit(INLINE)
def node_turned(prog: FloatArray, vx: int, vrate: int, t: float) -> Vec3:
    """An orbit-averaged inertial input at time t: the vector stored at prog[vx : vx + 3] (its
    value at t = 0) turned about ξ3 by Ω̇ t, with the node's rate Ω̇ [rad/time] at prog[vrate]
    and t [time]."""
    return turned_about_z(prog[vrate] * t, vec3(prog, vx))


@jit(INLINE)
def node_turned_body(a: Mat3, prog: FloatArray, vx: int, vrate: int, t: float) -> Vec3:
    """Aᵀ :func:`node_turned`: the orbit-averaged inertial input at time t [time] (stored at
    prog[vx : vx + 3] for t = 0, turned about ξ3 by Ω̇ t, Ω̇ [rad/time] at prog[vrate]) in the
    body axes of the body → inertial matrix a, as a term's moment reads it."""
    x1, x2, x3 = node_turned(prog, vx, vrate, t)
    return to_body(a, x1, x2, x3)


@jit(INLINE)
def dot(x: Vec3, y: Vec3) -> float:
    """x · y."""
    return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]


@jit(INLINE)
def scaled_cross(f: float, x: Vec3, y1: float, y2: float, y3: float) -> Vec3:
    """f x × y: the moment of a dipole x in a field y, times the factor f."""
    return f * (x[1] * y3 - x[2] * y2), f * (x[2] * y1 - x[0] * y3), f * (x[0] * y2 - x[1] * y1)


@jit(INLINE)
def matrix_quaternion(a: Mat3) -> tuple[float, float, float, float]:
    """A unit quaternion (sign arbitrary) of the rotation matrix a (by rows), by the largest of
    its four squared components (Shepperd's method: no cancellation)."""
    tr = a[0] + a[4] + a[8]
    if tr >= a[0] and tr >= a[4] and tr >= a[8]:
        s = 2.0 * math.sqrt(1.0 + tr)
        return 0.25 * s, (a[7] - a[5]) / s, (a[2] - a[6]) / s, (a[3] - a[1]) / s
    if a[0] >= a[4] and a[0] >= a[8]:
        s = 2.0 * math.sqrt(1.0 + a[0] - a[4] - a[8])
        return (a[7] - a[5]) / s, 0.25 * s, (a[1] + a[3]) / s, (a[2] + a[6]) / s
    if a[4] >= a[8]:
        s = 2.0 * math.sqrt(1.0 - a[0] + a[4] - a[8])
        return (a[2] - a[6]) / s, (a[1] + a[3]) / s, 0.25 * s, (a[5] + a[7]) / s
    s = 2.0 * math.sqrt(1.0 - a[0] - a[4] + a[8])
    return (a[3] - a[1]) / s, (a[2] + a[6]) / s, (a[5] + a[7]) / s, 0.25 * s


@jit(INLINE)
def quaternion_rates(y: FloatArray, out: FloatArray) -> None:
    """dq/dt = ½ q ⊗ (0, ω) into out[3:7] for y = [ω, q]."""
    w1, w2, w3, q0, q1, q2, q3 = y[0], y[1], y[2], y[3], y[4], y[5], y[6]
    out[3] = 0.5 * (-q1 * w1 - q2 * w2 - q3 * w3)
    out[4] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
    out[5] = 0.5 * (q0 * w2 - q1 * w3 + q3 * w1)
    out[6] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)
