"""The full equations of the nonlinear-moment model: Euler's equations (1.1) with
quaternion kinematics (singularity-free) under the moment of §9, and the reduced form
(1.3), (2.1) for any perturbation.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.nutation import Perturbation
from tumble.kernels import EVENT_THETA_DOT, KIND_NONLINEAR_MOMENT, Kernel
from tumble.kernels.rhs import evaluate_event, symmetric_body
from tumble.models.base import QUATERNION_STATE, FullForm, attitude_values
from tumble.models.inputs.nonlinear_moment import Params, State
from tumble.models.nonlinear_moment.perturbation import builtin_perturbation
from tumble.rotations import euler313_to_matrix, matrix_to_euler313, matrix_to_quat, quat_to_matrix
from tumble.unperturbed.symmetric_body import potential_slope

# ---------------------------------------------------------------------------------------------
# Full equations: (1.1) with quaternion kinematics (singularity-free), and the reduced (1.3).


def full_from_slow(p: Params, st: State) -> FloatArray:
    """State ``[p, q, r, q0, q1, q2, q3]`` of the quaternion form from Euler angles and R, G
    (:func:`_rate_and_attitude`).

    Parameters
    ----------
    p : Params
        μ = C/A [1] (R = μr).
    st : State
        Euler angles θ, ψ, φ [rad], θ' [rad/t] and the momenta R, G [1/t].

    Returns
    -------
    ndarray, shape (7,)
        Body angular velocity [rad/t] and the body → inertial quaternion (z–x–z angles).
    """
    w, q = _rate_and_attitude(p, *(np.array([v], dtype=float) for v in (
        st.theta, st.theta_dot, st.psi, st.phi, st.R, st.G)))  # fmt: skip
    return np.concatenate([w[0], q[0]])


def _rate_and_attitude(
    p: Params,
    theta: FloatArray,
    theta_dot: FloatArray,
    psi: FloatArray,
    phi: FloatArray,
    R: FloatArray,
    G: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """Body angular velocities (shape (n, 3)) [rad/t] and body → inertial quaternions
    (shape (n, 4)) of Euler angles (z–x–z) and R, G: (1.2) inverted with R = μr,
    ψ' = (G − R cosθ)/sin²θ, φ' = r − ψ' cosθ (1.3)."""
    s, c = np.sin(theta), np.cos(theta)
    r = R / p.mu
    psid = (G - R * c) / (s * s)
    sp, cp = np.sin(phi), np.cos(phi)
    w = np.stack([psid * s * sp + theta_dot * cp, psid * s * cp - theta_dot * sp, r], -1)
    return w, matrix_to_quat(euler313_to_matrix(psi, theta, phi))


def full_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Euler's equations (1.1) with quaternion kinematics under the moment of §9.

    The moment (1.4)–(1.5) is written without Euler angles: with e_z in body axes,
    M0·e_n = A(a + 2b cosθ)(e_z × e3), since e_z × e3 = sinθ·e_n. Damping adds
    −εA d (p, q, 0) − εC ν (0, 0, r). One definition: the compiled kernel the integrator runs
    (:func:`tumble.kernels.rhs.symmetric_body`); only the pressure Q(εt) is evaluated here,
    so that a pressure given as a Python function works too.

    Parameters
    ----------
    t : float
        Time [t].
    y : ndarray, shape (7,)
        ``[p, q, r, q0, q1, q2, q3]`` [rad/t, 1].
    p : Params

    Returns
    -------
    ndarray, shape (7,)
        dy/dt.
    """
    if p.pressure.kind == "constant":
        a, b = p.a, p.b
    else:
        av, bv = p.ab(t)
        a, b = float(av), float(bv)
    state = np.ascontiguousarray(y, dtype=np.float64)
    return symmetric_body(state, p.mu, a, b, p.eps * p.d, p.eps * p.nu)  # type: ignore[no-any-return]


def _body_axis_components(Y: FloatArray) -> tuple[FloatArray, ...]:
    """e_z in body axes and the sine of θ from quaternion states (..., 7)."""
    q = Y[..., 3:] / np.linalg.norm(Y[..., 3:], axis=-1, keepdims=True)
    q0, q1, q2, q3 = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    ex = 2.0 * (q1 * q3 - q0 * q2)
    ey = 2.0 * (q2 * q3 + q0 * q1)
    ez = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return ex, ey, ez, np.hypot(ex, ey)


def slow_from_full(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """Output columns from quaternion states: θ, ψ, φ (z–x–z), θ', R, G, a, b.

    θ = atan2(|e_z × e3|, e_z·e3) keeps full accuracy near 0 and π; θ' = ω·(e_z × e3)/sinθ
    (from (1.2)); R = μr; G = (p, q, μr)·e_z (§1).

    Parameters
    ----------
    p : Params
    t : ndarray, shape (n,)
        Times [t].
    Y : ndarray, shape (n, 7)
        Quaternion-form states.
    """
    ex, ey, ez, s = _body_axis_components(Y)
    w1, w2, w3 = Y[:, 0], Y[:, 1], Y[:, 2]
    psi, _, phi = matrix_to_euler313(quat_to_matrix(Y[:, 3:]))
    with np.errstate(divide="ignore", invalid="ignore"):
        theta_dot = np.where(s > 0.0, (w1 * ey - w2 * ex) / s, 0.0)
    a, b = p.ab(t)
    return {
        "theta": np.arctan2(s, ez),
        "psi": psi,
        "phi": phi,
        "theta_dot": theta_dot,
        "R": p.mu * w3,
        "G": w1 * ex + w2 * ey + p.mu * w3 * ez,
        "a": a,
        "b": b,
    }


def _state_from_columns(cols: Mapping[str, FloatArray]) -> State:
    """The initial-condition record of the first row of full-form columns."""
    names = ("theta", "theta_dot", "psi", "phi", "R", "G")
    return State(*(float(cols[name][0]) for name in names))


def invariants(p: Params, Y: FloatArray) -> dict[str, FloatArray]:
    """R, G and the energy E of (1.6) from quaternion states (constant when ε = 0).

    Parameters
    ----------
    p : Params
    Y : ndarray, shape (n, 7)

    Returns
    -------
    dict
        ``R``, ``G`` [1/t] and ``E`` [1/t²], evaluated with a(0), b(0).
    """
    ex, ey, ez, _s = _body_axis_components(Y)
    w1, w2, w3 = Y[:, 0], Y[:, 1], Y[:, 2]
    R = p.mu * w3
    G = w1 * ex + w2 * ey + R * ez
    # E = θ'²/2 + (G − R u)²/(2 sin²θ) + a u + b u² = ½|ω⊥|² + a u + b u²: the transverse
    # kinetic energy over A is exactly the first two terms, and has no 1/sinθ.
    E = 0.5 * (w1 * w1 + w2 * w2) + p.a * ez + p.b * ez * ez
    return {"R": R, "G": G, "E": E}


def reduced_rhs(t: float, y: FloatArray, p: Params, perturbation: Perturbation) -> FloatArray:
    """The full model in the reduced form (1.3) and (2.1), for any perturbation.

    State ``[θ, θ', ψ, φ, R, G, a, b]``: θ'' = −F(θ, z) + εΦθ, z' = εΦz, and ψ', φ' from
    (1.3). Singular at θ = 0, π (use :func:`full_rhs` there).

    Parameters
    ----------
    t : float
        Time [t].
    y : ndarray, shape (8,)
        ``[θ, θ', ψ, φ, R, G, a, b]`` [rad, rad/t, rad, rad, 1/t, 1/t, 1/t², 1/t²].
    p : Params
        μ and ε (a, b come from the state).
    perturbation : Perturbation
        Φθ and Φz of (2.1).

    Returns
    -------
    ndarray, shape (8,)
    """
    theta, theta_dot, _, _, R, G, a, b = y.tolist()
    z = y[4:]
    tau = p.eps * t
    s, c = math.sin(theta), math.cos(theta)
    F = float(potential_slope(theta, R, G, a, b))
    eps = p.eps
    ph, pz = perturbation.evaluate(tau, np.array([theta]), np.array([theta_dot]), z)
    phi_th, phi_z = float(ph[0]), pz[:, 0]
    psid = (G - R * c) / (s * s)
    return np.array(
        [
            theta_dot,
            -F + eps * phi_th,
            psid,
            R / p.mu - psid * c,
            *(eps * phi_z).tolist(),
        ]
    )


def _reduced_from_slow(p: Params, st: State) -> FloatArray:
    a, b = p.ab(0.0)
    return np.array([st.theta, st.theta_dot, st.psi, st.phi, st.R, st.G, float(a), float(b)])


def _reduced_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    names = ("theta", "theta_dot", "psi", "phi", "R", "G", "a", "b")
    cols = {n: Y[:, i].copy() for i, n in enumerate(names)}
    w, q = _rate_and_attitude(p, *(cols[n] for n in names[:6]))
    return cols | attitude_values(q, w)


def _quaternion_columns(p: Params, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """:func:`slow_from_full` and the attitude (:func:`~tumble.models.base.attitude_values`)."""
    return slow_from_full(p, t, Y) | attitude_values(Y[:, 3:], Y[:, :3])


def _builtin_reduced_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    return reduced_rhs(t, y, p, builtin_perturbation(p))


_PRESSURE_CODES = {"constant": 0, "exp": 1, "table": 2}


_NO_PARAMS = np.zeros(0)  # the θ' event reads the state only


def full_kernel(p: Params) -> Kernel | None:
    """:func:`full_rhs` compiled (:mod:`tumble.kernels`), locating the zeros of θ' (the
    extrema of θ) as it goes; None for a pressure given as a Python function."""
    pressure = p.pressure
    if pressure.kind not in _PRESSURE_CODES:
        return None
    table = [float(len(pressure.tau)), *pressure.tau, *pressure.Q]
    params = [p.mu, p.a, p.b, p.eps, p.d, p.nu, _PRESSURE_CODES[pressure.kind], p.Q0, *table]
    # The last time the profile covers (τ_max/ε; unbounded for a closed-form profile).
    t_max = pressure.tau_max / p.eps if p.eps > 0.0 else math.inf
    message = (
        f"perturbation.pressure table covers τ in [{pressure.tau[0]:g}, {pressure.tau_max:g}], "
        "but the run needs τ beyond it"
        if pressure.tau
        else ""
    )
    return Kernel(KIND_NONLINEAR_MOMENT, np.array(params), EVENT_THETA_DOT, t_max, message)


FULL_QUATERNION: FullForm[Params, State] = FullForm(
    name="quaternion",
    equation="(1.1) with quaternion kinematics",
    state=QUATERNION_STATE,
    rhs=full_rhs,
    initial_state=full_from_slow,
    to_columns=_quaternion_columns,
    state_of=lambda p, y: _state_from_columns(slow_from_full(p, np.zeros(1), y[None, :])),
    kernel=full_kernel,
    invariants=invariants,
    event=lambda t, y, p: float(evaluate_event(EVENT_THETA_DOT, t, y, _NO_PARAMS)),
)
FULL_REDUCED: FullForm[Params, State] = FullForm(
    name="reduced",
    equation="(1.3), (2.1)",
    state=("theta", "theta_dot", "psi", "phi", "R", "G", "a", "b"),
    rhs=_builtin_reduced_rhs,
    initial_state=_reduced_from_slow,
    to_columns=_reduced_columns,
    state_of=lambda p, y: State(*(float(v) for v in y[:6])),
    event=lambda t, y, p: float(y[1]),  # θ'
)
