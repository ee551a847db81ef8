"""User torques for the torqued_body examples: ``torque = "user_torques:bdot"``.

A torque is a function ``f(t, q, omega, params)`` returning the body components of the moment:
t the model time, q the attitude quaternion (scalar first, body → inertial), omega the body
angular velocity and params the scenario's ``[torque_params]`` table. Written with numpy
broadcasting over leading axes of q and omega, it is evaluated on whole quadrature grids by
the averaging engine (much faster than one state at a time). Compiled with ``numba.njit``
(``bdot_compiled``), it runs inside tumble's compiled integrators and averaging kernels.
"""

import numba
import numpy as np

from tumble.rotations import quat_to_matrix


def dipole_field(t, params):
    """Unit-strength dipole field along a circular polar orbit, inertial axes.

    The dipole axis is ξ3, the orbit lies in the ξ1ξ3 plane and the argument of latitude is
    u = n t + u0: B = 3 (d·r̂) r̂ − d with d = ξ3 and r̂ = (cos u, 0, sin u), so |B| varies by a
    factor 2 between the equator and the poles.
    """
    u = params["n"] * np.asarray(t, dtype=float) + params.get("u0", 0.0)
    s, c = np.sin(u), np.cos(u)
    return np.stack([3.0 * s * c, np.zeros_like(u), 3.0 * s * s - 1.0], axis=-1)


def bdot(t, q, omega, params):
    """The ideal B-dot detumbling law: dipole m = k (ω × B_b), moment M = m × B_b.

    With the field's own change over the orbit neglected against the tumble (the usual
    assumption, valid while |ω| ≫ n), this damps the rotation perpendicular to the field:
    M = −k |B|² ω⊥. Parameters: ``k`` the gain [moment·t per unit field²], ``n`` the orbital
    rate [rad/t], ``u0`` the initial argument of latitude [rad].
    """
    A = quat_to_matrix(np.asarray(q, dtype=float))
    B = np.einsum("...ji,...j->...i", A, np.broadcast_to(dipole_field(t, params), A.shape[:-1]))
    m = params["k"] * np.cross(omega, B)
    return np.cross(m, B)


@numba.njit
def bdot_compiled(t, q, omega, params):
    """:func:`bdot` compiled with numba: tumble then runs it inside its compiled integrators
    and averaging kernels instead of calling Python.

    A compiled torque takes one state (q of 4, omega of 3) and gets ``params`` as a float
    array of the ``[torque_params]`` values in their order: here ``k``, ``n``, ``u0``. Written
    with scalars, it allocates nothing: the averaging kernels call it on thousands of nodes.
    """
    k, n, u0 = params[0], params[1], params[2]
    u = n * t + u0
    s, c = np.sin(u), np.cos(u)
    f1, f3 = 3.0 * s * c, 3.0 * s * s - 1.0  # dipole_field (inertial, second component 0)
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    # Body components B = Aᵀ f: the first and third rows of A (body → inertial) times f.
    b1 = (1.0 - 2.0 * (q2 * q2 + q3 * q3)) * f1 + 2.0 * (q1 * q3 - q0 * q2) * f3
    b2 = 2.0 * (q1 * q2 - q0 * q3) * f1 + 2.0 * (q2 * q3 + q0 * q1) * f3
    b3 = 2.0 * (q1 * q3 + q0 * q2) * f1 + (1.0 - 2.0 * (q1 * q1 + q2 * q2)) * f3
    w1, w2, w3 = omega[0], omega[1], omega[2]
    m1, m2, m3 = k * (w2 * b3 - w3 * b2), k * (w3 * b1 - w1 * b3), k * (w1 * b2 - w2 * b1)
    return (m2 * b3 - m3 * b2, m3 * b1 - m1 * b3, m1 * b2 - m2 * b1)
