"""Rotations: quaternions, rotation matrices and the angle sets of the papers.

Conventions (used everywhere in tumble)
---------------------------------------
* A quaternion is ``[q0, q1, q2, q3]``, scalar first. An *attitude* quaternion maps body
  components to inertial ones: ``v_inertial = R(q) @ v_body``. Its kinematics with the body
  angular velocity ω is ``dq/dt = ½ q ⊗ (0, ω)``.
* ``rot_x(a)``, ``rot_z(a)`` are the active rotations by ``a`` about x and z.
* Euler angles 3-1-3: ``C(ψ, ϑ, φ) = Rz(ψ) Rx(ϑ) Rz(φ)``; the columns of C are the body axes in
  the components of the reference frame.
* K-frame of the resisting-medium paper (docs/theory/resisting-medium.md §2): for the
  direction of the angular momentum at polar angle ρ from the inertial axis X3 and azimuth σ
  about X3 (from X1), ``Ξ(ρ, σ)`` has the columns ξ1 = ∂e_K/∂ρ, ξ2 = (−sin σ, cos σ, 0),
  ξ3 = e_K; the attitude is ``R = Ξ(ρ, σ) C(ψ, ϑ, φ)``.

Every function accepts arrays with leading batch dimensions.
"""

from __future__ import annotations

import numpy as np

from tumble._typing import ArrayLike, FloatArray

__all__ = [
    "SINGULAR_SIN",
    "attitude_from_kframe_angles",
    "direction_angles",
    "euler313_to_matrix",
    "kframe_angles_from_attitude",
    "kframe_matrix",
    "matrix_to_euler313",
    "matrix_to_quat",
    "quat_conjugate",
    "quat_multiply",
    "quat_normalize",
    "quat_to_matrix",
    "rot_x",
    "rot_z",
]

SINGULAR_SIN = 1e-12
"""Below this sin ϑ the 3-1-3 angles ψ and φ are not separately defined (gimbal lock): only
ψ + φ (ϑ = 0) or ψ − φ (ϑ = π) is, and ψ is set to 0."""


def _arr(x: ArrayLike) -> FloatArray:
    return np.asarray(x, dtype=float)


def quat_multiply(p: ArrayLike, q: ArrayLike) -> FloatArray:
    """Hamilton product p ⊗ q of scalar-first quaternions, shape (..., 4)."""
    p, q = _arr(p), _arr(q)
    p0, p1, p2, p3 = np.moveaxis(p, -1, 0)
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3,
            p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2,
            p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1,
            p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0,
        ],
        axis=-1,
    )


def quat_conjugate(q: ArrayLike) -> FloatArray:
    """Conjugate (inverse of a unit quaternion), shape (..., 4)."""
    return _arr(q) * np.array([1.0, -1.0, -1.0, -1.0])


def quat_normalize(q: ArrayLike) -> FloatArray:
    """Quaternion scaled to unit norm, shape (..., 4)."""
    q = _arr(q)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def quat_to_matrix(q: ArrayLike) -> FloatArray:
    """Rotation matrix of a quaternion (normalized first), shape (..., 3, 3).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Scalar-first quaternion; the result maps body to inertial components.
    """
    q0, q1, q2, q3 = np.moveaxis(quat_normalize(q), -1, 0)
    return np.stack(
        [
            np.stack(
                [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)], -1
            ),
            np.stack(
                [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)], -1
            ),
            np.stack(
                [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)], -1
            ),
        ],
        axis=-2,
    )


def matrix_to_quat(R: ArrayLike) -> FloatArray:
    """Unit quaternion of a rotation matrix (Shepperd's method), with q0 ≥ 0.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Proper rotation matrix.

    Returns
    -------
    ndarray, shape (..., 4)
        Scalar-first quaternion with ``quat_to_matrix(q) == R``.
    """
    R = _arr(R)
    tr = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2]
    # Pick, per matrix, the largest of 4 q0², 4 q1², 4 q2², 4 q3² as the pivot: no cancellation.
    cand = np.stack([tr, R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]], axis=-1)
    pivot = np.argmax(cand, axis=-1)
    # Non-pivot candidates may divide by zero; np.choose discards them.
    with np.errstate(divide="ignore", invalid="ignore"):
        # pivot 0: q0
        s = np.sqrt(np.maximum(1.0 + tr, 0.0)) * 2.0
        q0 = np.stack(
            [
                s / 4,
                (R[..., 2, 1] - R[..., 1, 2]) / s,
                (R[..., 0, 2] - R[..., 2, 0]) / s,
                (R[..., 1, 0] - R[..., 0, 1]) / s,
            ],
            -1,
        )
        s1 = np.sqrt(np.maximum(1.0 + R[..., 0, 0] - R[..., 1, 1] - R[..., 2, 2], 0.0)) * 2.0
        q1 = np.stack(
            [
                (R[..., 2, 1] - R[..., 1, 2]) / s1,
                s1 / 4,
                (R[..., 0, 1] + R[..., 1, 0]) / s1,
                (R[..., 0, 2] + R[..., 2, 0]) / s1,
            ],
            -1,
        )
        s2 = np.sqrt(np.maximum(1.0 - R[..., 0, 0] + R[..., 1, 1] - R[..., 2, 2], 0.0)) * 2.0
        q2 = np.stack(
            [
                (R[..., 0, 2] - R[..., 2, 0]) / s2,
                (R[..., 0, 1] + R[..., 1, 0]) / s2,
                s2 / 4,
                (R[..., 1, 2] + R[..., 2, 1]) / s2,
            ],
            -1,
        )
        s3 = np.sqrt(np.maximum(1.0 - R[..., 0, 0] - R[..., 1, 1] + R[..., 2, 2], 0.0)) * 2.0
        q3 = np.stack(
            [
                (R[..., 1, 0] - R[..., 0, 1]) / s3,
                (R[..., 0, 2] + R[..., 2, 0]) / s3,
                (R[..., 1, 2] + R[..., 2, 1]) / s3,
                s3 / 4,
            ],
            -1,
        )
        q = np.choose(pivot[..., None], [q0, q1, q2, q3])
    q = quat_normalize(q)
    return np.where(q[..., :1] < 0.0, -q, q)


def rot_x(a: ArrayLike) -> FloatArray:
    """Active rotation by angle ``a`` [rad] about x, shape (..., 3, 3)."""
    a = _arr(a)
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)], -2
    )


def rot_z(a: ArrayLike) -> FloatArray:
    """Active rotation by angle ``a`` [rad] about z, shape (..., 3, 3)."""
    a = _arr(a)
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    return np.stack(
        [np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2
    )


def euler313_to_matrix(psi: ArrayLike, theta: ArrayLike, phi: ArrayLike) -> FloatArray:
    """C(ψ, ϑ, φ) = Rz(ψ) Rx(ϑ) Rz(φ), docs/theory/resisting-medium.md §2.

    Parameters
    ----------
    psi, theta, phi : array_like
        Precession, nutation and proper-rotation angles [rad].

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Columns are the body axes in reference-frame components.
    """
    return rot_z(psi) @ rot_x(theta) @ rot_z(phi)


def matrix_to_euler313(C: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """3-1-3 angles (ψ, ϑ, φ) of a rotation matrix; inverse of :func:`euler313_to_matrix`.

    ϑ ∈ [0, π]; ψ, φ ∈ (−π, π]. Where sin ϑ < :data:`SINGULAR_SIN` only ψ ± φ is defined:
    ψ is set to 0 and φ carries the whole rotation about the axis. In every case
    ``euler313_to_matrix(*matrix_to_euler313(C))`` reproduces C to round-off.

    Parameters
    ----------
    C : array_like, shape (..., 3, 3)
        Proper rotation matrix.
    """
    C = _arr(C)
    sin_theta = np.hypot(C[..., 2, 0], C[..., 2, 1])
    theta = np.arctan2(sin_theta, C[..., 2, 2])
    regular = sin_theta >= SINGULAR_SIN
    psi = np.where(regular, np.arctan2(C[..., 0, 2], -C[..., 1, 2]), 0.0)
    # φ from Rz(φ) = Rx(−ϑ) Rz(−ψ) C: consistent with ψ, ϑ even where ψ is poorly conditioned.
    M = rot_x(-theta) @ rot_z(-psi) @ C
    phi = np.arctan2(M[..., 1, 0], M[..., 0, 0])
    return psi, theta, phi


def kframe_matrix(rho: ArrayLike, sigma: ArrayLike) -> FloatArray:
    """Ξ(ρ, σ): columns ξ1, ξ2, ξ3 of the angular-momentum frame
    (docs/theory/resisting-medium.md §2).

    Parameters
    ----------
    rho : array_like
        Angle between K and the inertial axis X3 [rad].
    sigma : array_like
        Azimuth of K about X3, from X1 [rad].

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertial components of ξ1 (∂e_K/∂ρ), ξ2 and ξ3 = e_K, as columns.
    """
    rho, sigma = np.broadcast_arrays(_arr(rho), _arr(sigma))
    cr, sr, cs, ss = np.cos(rho), np.sin(rho), np.cos(sigma), np.sin(sigma)
    xi1 = np.stack([cr * cs, cr * ss, -sr], -1)
    xi2 = np.stack([-ss, cs, np.zeros_like(rho)], -1)
    xi3 = np.stack([sr * cs, sr * ss, cr], -1)
    return np.stack([xi1, xi2, xi3], -1)


def direction_angles(v: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Polar angle ρ ∈ [0, π] from X3 and azimuth σ ∈ (−π, π] of a vector.

    Parameters
    ----------
    v : array_like, shape (..., 3)
        Inertial components of a non-zero vector (the angular momentum K).
    """
    v = _arr(v)
    rho = np.arctan2(np.hypot(v[..., 0], v[..., 1]), v[..., 2])
    sigma = np.arctan2(v[..., 1], v[..., 0])
    return rho, sigma


def attitude_from_kframe_angles(
    rho: ArrayLike, sigma: ArrayLike, psi: ArrayLike, theta: ArrayLike, phi: ArrayLike
) -> FloatArray:
    """Attitude matrix R = Ξ(ρ, σ) C(ψ, ϑ, φ) (body → inertial), docs/theory/resisting-medium.md §2.

    Parameters
    ----------
    rho, sigma : array_like
        Direction of K in the inertial frame [rad].
    psi, theta, phi : array_like
        3-1-3 Euler angles of the body relative to the K-frame [rad].
    """
    return kframe_matrix(rho, sigma) @ euler313_to_matrix(psi, theta, phi)


def kframe_angles_from_attitude(
    R: ArrayLike, K_inertial: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Angles (ρ, σ, ψ, ϑ, φ) of an attitude relative to the K-frame of a vector K.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Attitude matrix, body → inertial.
    K_inertial : array_like, shape (..., 3)
        Inertial components of the angular momentum (any non-zero length).

    Returns
    -------
    tuple of ndarray
        ρ ∈ [0, π], σ ∈ (−π, π], ψ ∈ (−π, π], ϑ ∈ [0, π], φ ∈ (−π, π] [rad]. At ρ ∈ {0, π}
        only σ ± ψ is defined; at ϑ ∈ {0, π} see :func:`matrix_to_euler313`.
    """
    rho, sigma = direction_angles(K_inertial)
    C = np.swapaxes(kframe_matrix(rho, sigma), -1, -2) @ _arr(R)
    psi, theta, phi = matrix_to_euler313(C)
    return rho, sigma, psi, theta, phi
