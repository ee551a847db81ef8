"""The full equations of the resisting-medium model: Euler's equations with quaternion
kinematics (form (a), the moment (1.2)) and the osculating-variable standard form (1.3)
(form (b)), §4 of ``docs/theory/resisting-medium.md``.
"""

from __future__ import annotations

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.spinner import body_momentum, standard_form
from tumble.kernels import Kernel
from tumble.kernels.rhs import rigid_body
from tumble.models.base import QUATERNION_STATE, FullForm, attitude_values
from tumble.models.inputs.resisting_medium import Params, State
from tumble.rotations import (
    attitude_from_kframe_angles,
    kframe_angles_from_attitude,
    matrix_to_quat,
    quat_to_matrix,
)

# ---------------------------------------------------------------------------------------------
# Full model, form (a): Euler's equations + quaternion kinematics with the moment (1.2).


def full_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Full equations of motion, Euler + quaternions with the moment (1.2), §4: the
    compiled code the integrator runs (:func:`tumble.kernels.rhs.rigid_body`).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (7,)
        ``[p, q, r, q0, q1, q2, q3]``: body angular velocity w [rad/τ] and attitude quaternion.
    p : Params
        Model parameters.
    """
    return rigid_body(t, np.ascontiguousarray(y, dtype=np.float64), p.kernel.params)  # type: ignore[no-any-return]


def full_from_slow(p: Params, st: State) -> FloatArray:
    """State vector of form (a) from (k, ρ, σ, ψ, ϑ, φ), §2 and §4.

    Returns
    -------
    ndarray, shape (7,)
        ``[w, q]`` with w = (k_b1, k_b2, k_b3/(1+κ)) and q the attitude Ξ(ρ, σ) C(ψ, ϑ, φ).
    """
    R = attitude_from_kframe_angles(st.rho, st.sigma, st.psi, st.theta, st.phi)
    w = body_momentum(st.k, st.theta, st.phi) / p.inertia
    return np.concatenate([w, matrix_to_quat(R)])


def slow_from_full(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """(k, ϑ, ρ, σ, ψ, φ) from states of form (a), with atan2 as in §4.

    Parameters
    ----------
    p : Params
        Model parameters.
    t : ndarray, shape (n,)
        Times τ [1] (unused; part of the form's interface).
    Y : ndarray, shape (n, 7)
        States ``[w, q]``.
    """
    Y = np.atleast_2d(Y)
    kb = Y[:, :3] * p.inertia
    k = np.linalg.norm(kb, axis=-1)
    theta = np.arctan2(np.hypot(kb[:, 0], kb[:, 1]), kb[:, 2])
    phi = np.arctan2(kb[:, 0], kb[:, 1])
    R = quat_to_matrix(Y[:, 3:])
    K_in = np.einsum("nij,nj->ni", R, kb)
    rho, sigma, psi, _, _ = kframe_angles_from_attitude(R, K_in)
    return {"k": k, "theta": theta, "rho": rho, "sigma": sigma, "psi": psi, "phi": phi}


def state_from_full(p: Params, y: FloatArray) -> State:
    """The initial-condition record (k, ρ, σ, ψ, ϑ, φ) of one state ``[w, q]`` of form (a)."""
    cols = slow_from_full(p, np.zeros(1), np.asarray(y)[None, :])
    return State(**{name: float(cols[name][0]) for name in _STATE_FIELDS})


_STATE_FIELDS = ("k", "rho", "sigma", "psi", "theta", "phi")


def invariants(p: Params, Y: FloatArray) -> dict[str, FloatArray]:
    """First integrals of the unperturbed motion (ε = 0), §5 and §13 item 1.

    Returns
    -------
    dict
        ``k`` = |k| [1], ``energy`` = ½ (p² + q² + (1+κ) r²) [1], and the inertial components
        ``K1, K2, K3`` of k [1].
    """
    Y = np.atleast_2d(Y)
    w = Y[:, :3]
    kb = w * p.inertia
    K_in = np.einsum("nij,nj->ni", quat_to_matrix(Y[:, 3:]), kb)
    return {
        "k": np.linalg.norm(kb, axis=-1),
        "energy": 0.5 * np.sum(w * kb, axis=-1),
        "K1": K_in[:, 0],
        "K2": K_in[:, 1],
        "K3": K_in[:, 2],
    }


# ---------------------------------------------------------------------------------------------
# Full model, form (b): the osculating-variable standard form (1.3).


def _body_moment(p: Params, w: FloatArray) -> FloatArray:
    """m = a − b w − s (w ∘ |w|) of (1.2), body axes, for w of shape (..., 3)."""
    return p.a - w @ p.b.T - (w * np.abs(w)) @ p.s.T


def osculating_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Standard form (1.3) for (k, ρ, σ, ψ, ϑ, φ), with correction E1 applied.

    The kinematics is :func:`tumble.averaging.spinner.standard_form`; this model supplies the
    moment (1.2). Singular where sin ϑ = 0 or sin ρ = 0 (§11); use :func:`full_rhs` there.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (6,)
        ``[k, ρ, σ, ψ, ϑ, φ]`` [1, rad, rad, rad, rad, rad].
    p : Params
        Model parameters.
    """
    k, rho, _sigma, psi, theta, phi = y
    m = _body_moment(p, body_momentum(k, theta, phi) / p.inertia)
    return standard_form(m, k, rho, psi, theta, phi, p.kappa, p.eps)


def osculating_from_slow(p: Params, st: State) -> FloatArray:
    """State vector ``[k, ρ, σ, ψ, ϑ, φ]`` of form (1.3)."""
    return np.array([st.k, st.rho, st.sigma, st.psi, st.theta, st.phi])


def _euler_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """:func:`slow_from_full` and the attitude (:func:`~tumble.models.base.attitude_values`)."""
    Y = np.atleast_2d(Y)
    return slow_from_full(p, t, Y) | attitude_values(Y[:, 3:], Y[:, :3])


def _osculating_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """The state's angles, and the attitude Ξ(ρ, σ) C(ψ, ϑ, φ) and body rate they give."""
    Y = np.atleast_2d(Y)
    names = ("k", "rho", "sigma", "psi", "theta", "phi")
    cols = {name: Y[:, i] for i, name in enumerate(names)}
    R = attitude_from_kframe_angles(cols["rho"], cols["sigma"], cols["psi"], cols["theta"],
                                    cols["phi"])  # fmt: skip
    w = body_momentum(cols["k"], cols["theta"], cols["phi"]) / p.inertia
    return cols | attitude_values(matrix_to_quat(R), w)


def full_kernel(p: Params) -> Kernel | None:
    """:func:`full_rhs` compiled (:mod:`tumble.kernels`): Euler + quaternions with (1.2)."""
    return p.kernel


FULL_EULER: FullForm[Params, State] = FullForm(
    name="euler",
    equation="Euler + quaternions with (1.2)",
    state=QUATERNION_STATE,
    rhs=full_rhs,
    initial_state=full_from_slow,
    to_columns=_euler_columns,
    state_of=state_from_full,
    kernel=full_kernel,
    invariants=invariants,
)
FULL_OSCULATING: FullForm[Params, State] = FullForm(
    name="osculating",
    equation="(1.3)",
    state=("k", "rho", "sigma", "psi", "theta", "phi"),
    rhs=osculating_rhs,
    initial_state=osculating_from_slow,
    to_columns=_osculating_columns,
    state_of=lambda p, y: State(*(float(v) for v in y)),
)
