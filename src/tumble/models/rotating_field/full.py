"""The full equations of the rotating-field model: the rotating-frame form (1.5) and the
inertial form (1.4) of a conducting body under the eddy-current moment (1.3), their
slow variables (§9), and the free motion at ε = 0.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs
from tumble.kernels import KIND_ROTATING_FIELD, Kernel
from tumble.kernels.params import ROTATING_FIELD
from tumble.kernels.rhs import rotating_field as rotating_field_rhs
from tumble.models.base import FullForm, attitude_values
from tumble.models.inputs.rotating_field import Params, State
from tumble.rotations import matrix_to_quat, quat_normalize, quat_to_matrix, rot_z
from tumble.unperturbed import EulerPoinsot, modulus_squared_of_states

_XI3 = np.array([0.0, 0.0, 1.0])


# ---------------------------------------------------------------------------------------------
# Full equations (1.4), (1.5).


def full_rhs(t: float, y: Any, p: Params) -> Any:
    """Right-hand side of the rotating-frame form (1.5), with the corrected Γ′ (correction C3).

    ``I z′ + z × I z = ε Γᵀ ĥĥ (Γ z − ξ3)``, ``Γ′ = Γ ẑ − ξ̂3 Γ``. One definition: the
    compiled kernel the integrator runs (:func:`tumble.kernels.rhs.rotating_field`).

    Parameters
    ----------
    t : float
        Time τ = ωt [1] (the system is autonomous).
    y : ndarray, shape (12,)
        ``[z1, z2, z3, Γ11, Γ12, …, Γ33]`` (Γ by rows) [1]. Complex input is allowed (for
        complex-step Jacobians).
    p : Params

    Returns
    -------
    ndarray, shape (12,)
        dy/dτ.
    """
    state = np.ascontiguousarray(y)
    if not np.iscomplexobj(state):
        state = state.astype(np.float64, copy=False)
    return rotating_field_rhs(state, p.packed)


def inertial_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Right-hand side of the inertial form (1.4) in τ: Euler's equations with the eddy-current
    moment (1.3), and quaternion kinematics of A (body → inertial).

    Parameters
    ----------
    t : float
        Time τ = ωt [1] (the field direction depends on it explicitly).
    y : ndarray, shape (7,)
        ``[z1, z2, z3, q0, q1, q2, q3]`` [1].
    p : Params

    Returns
    -------
    ndarray, shape (7,)
    """
    return rigid_body_rhs(t, y, p.inertia, p.torque)


def full_from_slow(p: Params, st: State) -> FloatArray:
    """State vector of (1.5) at τ = 0: ``[z, Γ by rows]``."""
    return np.concatenate([st.z, st.gamma.ravel()])


def _inertial_from_slow(p: Params, st: State) -> FloatArray:
    """State vector of (1.4) at τ = 0: ``[z, q]`` with A(0) = Γ(0) (B(0) = E)."""
    return np.concatenate([st.z, matrix_to_quat(st.gamma)])


def _columns_from_momentum(L_xi: FloatArray, T: FloatArray, p: Params) -> dict[str, FloatArray]:
    """L, ρ, σ, T, k² from the inertial angular momentum and the energy, §9, §16."""
    L = np.linalg.norm(L_xi, axis=-1)
    perp = np.hypot(L_xi[..., 0], L_xi[..., 1])
    rho = np.arctan2(perp, L_xi[..., 2])
    sigma = np.arctan2(L_xi[..., 1], L_xi[..., 0])
    k2 = modulus_squared_of_states(*p.sorted_inertia, L, T)
    return {"L": L, "rho": rho, "sigma": sigma, "T": T, "k2": k2}


def slow_from_full(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """Slow variables and z of full states of (1.5), §9:

    ``L_η = Γ I z``, ``L = |L_η|``, ``ρ = arccos(L_η3/L)``, ``σ = atan2(L_η2, L_η1) + τ``,
    ``T = ½ z·Iz``, k² of the current regime.

    Parameters
    ----------
    p : Params
    t : ndarray, shape (n,)
        Times τ [1].
    Y : ndarray, shape (n, 12)
        States of (1.5).

    Returns
    -------
    dict
        ``L, rho, sigma, T, k2, z1, z2, z3`` [1, rad, rad, 1, 1, 1, 1, 1].
    """
    return _full_columns(_momentum(p, t, Y), Y[:, :3], p)


def _rotating_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """:func:`slow_from_full` and the attitude A = Rz(τ) Γ with the body rate z
    (:func:`~tumble.models.base.attitude_values`)."""
    A = np.matmul(rot_z(np.asarray(t, dtype=float)), Y[:, 3:].reshape(-1, 3, 3))
    return slow_from_full(p, t, Y) | attitude_values(matrix_to_quat(A), Y[:, :3])


def slow_elements(p: Params, st: State) -> dict[str, float]:
    """Slow variables L, ρ, σ, T, k² of the state ``st``, §9."""
    cols = slow_from_full(p, np.zeros(1), full_from_slow(p, st)[None, :])
    return {k: float(v[0]) for k, v in cols.items()}


def _momentum(p: Params, t: FloatArray, Y: FloatArray) -> FloatArray:
    """Inertial angular momentum L_ξ of states of (1.5) at times τ, shape (n, 3)."""
    G = Y[:, 3:].reshape(-1, 3, 3)
    L_eta = np.einsum("nij,nj->ni", G, p.inertia * Y[:, :3])
    return np.einsum("nji,nj->ni", rot_z(-np.asarray(t)), L_eta)  # v_ξ = Bᵀ(τ) v_η


def _rotating_angles(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """σ alone (the column unwrapped on every step): without the modulus k²."""
    L_xi = _momentum(p, t, Y)
    return {"sigma": np.arctan2(L_xi[:, 1], L_xi[:, 0])}


def _full_columns(L_xi: FloatArray, z: FloatArray, p: Params) -> dict[str, FloatArray]:
    T = 0.5 * np.sum(p.inertia * z * z, axis=1)
    cols = _columns_from_momentum(L_xi, T, p)
    cols.update(z1=z[:, 0], z2=z[:, 1], z3=z[:, 2])
    return cols


def _inertial_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    z = Y[:, :3]
    L_xi = np.einsum("nij,nj->ni", quat_to_matrix(Y[:, 3:]), p.inertia * z)
    return _full_columns(L_xi, z, p) | attitude_values(Y[:, 3:], z)


def invariants(p: Params, Y: FloatArray) -> dict[str, FloatArray]:
    """Energy T = ½ z·Iz and |L| of states of (1.5): constant when ε = 0 (free body).

    Also ``orthogonality`` = max |Γ Γᵀ − E|, which the exact flow keeps at zero.
    """
    z = Y[:, :3]
    G = Y[:, 3:].reshape(-1, 3, 3)
    return {
        "T": 0.5 * np.sum(p.inertia * z * z, axis=1),
        "L": np.linalg.norm(p.inertia * z, axis=1),
        "orthogonality": np.max(np.abs(G @ np.swapaxes(G, 1, 2) - np.eye(3)), axis=(1, 2)),
    }


def full_kernel(p: Params) -> Kernel:
    """:func:`full_rhs` compiled (:mod:`tumble.kernels`): the rotating-frame form (1.5)."""
    return Kernel(KIND_ROTATING_FIELD, p.packed)


def inertial_kernel(p: Params) -> Kernel | None:
    """:func:`inertial_rhs` compiled: (1.4) with the eddy-current moment (1.3)."""
    return rigid_body_kernel(p.inertia, p.torque)


def _free_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """(1.5) without the eddy-current moment (ε = 0): the free body seen from the field
    frame; the same compiled code as :func:`full_rhs`."""
    packed = p.packed.copy()
    packed[ROTATING_FIELD.at.eps] = 0.0
    return rotating_field_rhs(np.ascontiguousarray(y, dtype=np.float64), packed)  # type: ignore[no-any-return]


def free_motion(p: Params, st: State) -> Callable[[FloatArray], FloatArray]:
    """The motion at ε = 0 through ``st``, as states ``[z, Γ by rows]`` of (1.5): the free
    body (3.1) (:class:`~tumble.unperturbed.euler_poinsot.EulerPoinsot`) seen from the field
    frame, which turns by τ about ξ3, Γ(τ) = Rz(−τ) A(τ)."""
    free = EulerPoinsot.from_state(p.inertia, st.z, st.gamma)

    def states(tau: FloatArray) -> FloatArray:
        t = np.ravel(np.asarray(tau, dtype=float))
        gamma = np.matmul(rot_z(-t), free.attitude(t))
        return np.concatenate([free.omega(t), gamma.reshape(-1, 9)], axis=1)

    return states


FULL_ROTATING: FullForm[Params, State] = FullForm(
    name="rotating",
    equation="(1.5)",
    state=("z1", "z2", "z3", "G11", "G12", "G13", "G21", "G22", "G23", "G31", "G32", "G33"),
    rhs=full_rhs,
    initial_state=full_from_slow,
    to_columns=_rotating_columns,
    state_of=lambda p, y: State(y[:3], y[3:].reshape(3, 3)),
    angles=_rotating_angles,
    kernel=full_kernel,
    invariants=invariants,
)
FULL_INERTIAL: FullForm[Params, State] = FullForm(
    name="inertial",
    equation="(1.4) with quaternions",
    state=("z1", "z2", "z3", "q0", "q1", "q2", "q3"),
    rhs=inertial_rhs,
    initial_state=_inertial_from_slow,
    to_columns=_inertial_columns,
    state_of=lambda p, y: State(y[:3], quat_to_matrix(quat_normalize(y[3:]))),
    kernel=inertial_kernel,
)
