"""Triaxial conducting body in a rotating magnetic field: eddy-current torque, stability of the
stationary rotation, and the averaged transient.

Yu. G. Martynenko, *On the stability of stationary rotations of a rigid body in a magnetic
field* (1979). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/rotating-field.md``, which states where tumble departs from the printed paper and
why (corrections C1–C7 of its §14: the Γ′ equation of (1.5) and the middle term of (3.6) among
them).

Variables (§2, §4): time τ = ωt, body angular velocity z = Ω/ω, ε = M0/ω with M0 = k_f H²
(in the units of the moments of inertia), Γ the body → field-frame rotation (v_η = Γ v_x). The
full model keeps the user's axis labels (the stationary rotation is about body axis x3). The
averaged transient (§§8–10) needs I1 < I2 < I3: it relabels the axes internally by a proper
permutation, and its outputs (L, ρ, σ, T, k²) do not depend on the labels. ``regime = "x3"``
means the angular momentum encircles the axis of the largest moment, ``"x1"`` the smallest.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Literal

import numpy as np
from scipy.special import ellipe, ellipk

from tumble._typing import ArrayLike, BoolArray, FloatArray
from tumble.averaging.triaxial import triaxial_average_vector, triaxial_kernel
from tumble.catalogue import CATALOGUE
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs
from tumble.kernels import (
    EVENT_FIELD_SEPARATRIX,
    EVENT_TRIAXIAL_SEPARATRIX,
    KIND_FIELD_AVERAGED,
    KIND_ROTATING_FIELD,
    Kernel,
)
from tumble.kernels.rhs import rotating_field as rotating_field_rhs
from tumble.models.base import (
    Averaged,
    AveragedForm,
    AveragingOptions,
    Breakpoint,
    Column,
    Diagnostics,
    Full,
    FullForm,
    Model,
    SlowPath,
    StationaryMotion,
    Unperturbed,
    Validity,
    ValidityIssue,
    attitude_columns,
    attitude_values,
    first_time,
    fixed_columns,
    separatrix_issue,
)
from tumble.models.inputs.rotating_field import (
    DECLARED,
    GAMMA_TOL,
    Params,
    PhysicalParams,
    Scaling,
    State,
    normalize_physical,
    state_from_elements,
)
from tumble.models.triaxial_mean import triaxial_mean_form
from tumble.rotations import (
    matrix_to_quat,
    quat_normalize,
    quat_to_matrix,
    rot_z,
)
from tumble.unperturbed import (
    EulerPoinsot,
    energy_from_modulus,
    fast_frequencies,
    mean_square_rate,
    modulus_squared_of_ratio,
    modulus_squared_of_states,
    reached_ratio,
)

__all__ = [
    "GAMMA_TOL",
    "MODEL",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "approximate_roots",
    "averaged_kernel",
    "averaged_rhs",
    "averaged_rhs_k2",
    "averaged_rhs_numeric",
    "averaged_rhs_vector",
    "characteristic_coefficients",
    "field_average",
    "final_nutation_decay_rate",
    "full_from_slow",
    "full_rhs",
    "inertial_rhs",
    "invariants",
    "linear_matrix",
    "normalize_physical",
    "predicted_limits",
    "slow_elements",
    "slow_from_full",
    "state_from_elements",
    "stationary",
    "validity",
]

VALIDITY_RATIO = 0.1
"""``ε/I ≪ 1`` and ``fast ≫ slow`` are taken to hold while the ratio stays below this value."""

RESONANCE_ORDERS = (2, 2)
"""Largest |n1|, |n2| of the resonances m = n1 ν1 + n2 ν2 (m = 1, 2) that are watched, §12."""

_XI3 = np.array([0.0, 0.0, 1.0])


# ---------------------------------------------------------------------------------------------
# Full equations (1.4), (1.5).


def _hat(v: Any) -> Any:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]], dtype=v.dtype)


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


# ---------------------------------------------------------------------------------------------
# Averaged equations (3.5)–(3.7) and the vector form, §10.


def field_average(p: Params) -> FloatArray:
    """D = mean of Bᵀ ĥĥ B over the field phase, §10: −diag((1+c²)/2, (1+c²)/2, s²)."""
    a = 0.5 * (1.0 + p.c2)
    return -np.array([a, a, p.s2])


def _A(p: Params, sin2_rho: float) -> float:
    return 2.0 * (1.0 + p.c2) + (1.0 - 3.0 * p.c2) * sin2_rho


def averaged_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """(3.5) and the corrected (3.6) (correction C5): the T-form, state ``[L, ρ, σ, T]``.

    ``L′ = ε{−[1 + c² + (1 − 3c²) cos²ρ] T/L + s² cos ρ}``,
    ``L ρ′ = ε[(1 − 3c²) sin ρ cos ρ T/L − s² sin ρ]``, ``σ′ = 0``,
    ``T′ = ε{−¼[2(1 + c²) + (1 − 3c²) sin²ρ]⟨z²⟩ + (1 − 3c²)(1 − 3cos²ρ) T²/L²
    + 2 s² cos ρ T/L}``, with c = cos β, s = sin β and ⟨z²⟩ of (3.6) (§8).

    Singular at L = 0 (use :func:`averaged_rhs_vector` there).

    Parameters
    ----------
    t : float
        Time τ [1] (unused: autonomous).
    y : ndarray, shape (4,)
        ``[L, rho, sigma, T]`` [1, rad, rad, 1].
    p : Params

    Returns
    -------
    ndarray, shape (4,)
    """
    L, rho, _, T = (float(v) for v in y)
    c2, s2, eps = p.c2, p.s2, p.eps
    cr, sr = math.cos(rho), math.sin(rho)
    q = 1.0 - 3.0 * c2
    z2 = mean_square_rate(*p.sorted_inertia, L, T)
    dL = eps * (-(1.0 + c2 + q * cr * cr) * T / L + s2 * cr)
    drho = eps * (q * sr * cr * T / L - s2 * sr) / L
    dT = eps * (
        -0.25 * _A(p, sr * sr) * z2
        + q * (1.0 - 3.0 * cr * cr) * T * T / (L * L)
        + 2.0 * s2 * cr * T / L
    )
    return np.array([dL, drho, 0.0, dT])


def _kappa(I1: float, I2: float, I3: float) -> float:
    return (2.0 * I1 * I3 - I1 * I2 - I2 * I3) / (I2 * (I3 - I1))


def modulus_rate(p: Params, k2: float, sin2_rho: float, regime: str) -> float:
    """dk²/dτ of (3.7), in the regime's own labels (x1: indices 1 and 3 swapped).

    ``dk²/dτ = ε (I3 − I1)/(4 I1 I3) · A · F(k²)``, ``A = 2(1 + c²) + (1 − 3c²) sin²ρ``,
    ``F = (1 − κ)(1 − k²) − [(1 − κ) + (1 + κ) k²] E(k)/K(k)``.

    Parameters
    ----------
    p : Params
    k2 : float
        Modulus squared of the regime, in [0, 1] [1].
    sin2_rho : float
        sin²ρ [1].
    regime : {"x3", "x1"}

    Returns
    -------
    float
        dk²/dτ [1].
    """
    I1, I2, I3 = p.sorted_inertia
    if regime == "x1":
        I1, I3 = I3, I1
    kappa = _kappa(I1, I2, I3)
    e_over_k = 0.0 if k2 >= 1.0 else float(ellipe(k2) / ellipk(k2))
    F = (1.0 - kappa) * (1.0 - k2) - ((1.0 - kappa) + (1.0 + kappa) * k2) * e_over_k
    return p.eps * (I3 - I1) / (4.0 * I1 * I3) * _A(p, sin2_rho) * F


def averaged_rhs_k2(
    t: float, y: FloatArray, p: Params, regime: Literal["x3", "x1"] = "x3"
) -> FloatArray:
    """(3.5) and (3.7): the k²-form, state ``[L, ρ, σ, k²]`` in a fixed regime.

    T follows from the T substitution of §8. Needs a regime switch at k² = 1 (the caller's).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[L, rho, sigma, k2]``.
    p : Params
    regime : {"x3", "x1"}

    Returns
    -------
    ndarray, shape (4,)
    """
    L, rho, sigma, k2 = (float(v) for v in y)
    k2c = min(max(k2, 0.0), 1.0)  # round-off outside [0, 1]
    T = energy_from_modulus(*p.sorted_inertia, L, k2c, regime)
    out = averaged_rhs(t, np.array([L, rho, sigma, T]), p)
    out[3] = modulus_rate(p, k2c, math.sin(rho) ** 2, regime)
    return out


def averaged_rhs_vector(t: float, y: FloatArray, p: Params) -> FloatArray:
    """The regular vector form of the averaged system, §10, state ``[L_ξ, r]``.

    ``dL_ξ/dτ = ε (r D L_ξ + sin²β ξ3)`` with ``r = 2T/L²``, and
    ``dr/dτ = (ε A / 2)(r² − ⟨z²⟩/L²)`` (the identity after (3.6)); ⟨z²⟩/L² depends on r only.
    No 1/L and no polar-angle singularity: it carries L through 0 and ρ through 0 and π.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[L_ξ1, L_ξ2, L_ξ3, r]`` [inertia unit, 1/inertia unit].
    p : Params

    Returns
    -------
    ndarray, shape (4,)
    """
    l1, l2, l3, r = (float(v) for v in y)
    r = reached_ratio(*p.sorted_inertia, r)
    if math.isnan(r):
        return np.full(4, math.nan)  # past a pure rotation: the solver rejects the step
    d = field_average(p)
    L2 = l1 * l1 + l2 * l2 + l3 * l3
    sin2_rho = (l1 * l1 + l2 * l2) / L2 if L2 > 0.0 else 0.0
    g = mean_square_rate(*p.sorted_inertia, 1.0, 0.5 * r)  # ⟨z²⟩/L² at L = 1
    eps = p.eps
    return np.array(
        [
            eps * r * d[0] * l1,
            eps * r * d[1] * l2,
            eps * (r * d[2] * l3 + p.s2),
            0.5 * eps * _A(p, sin2_rho) * (r * r - g),
        ]
    )


def _initial_sigma(p: Params, st: State) -> float:
    L_xi = st.gamma @ (p.inertia * st.z)
    return float(math.atan2(L_xi[1], L_xi[0]))


def _vector_from_slow(p: Params, st: State) -> FloatArray:
    L_xi = st.gamma @ (p.inertia * st.z)
    L2 = float(L_xi @ L_xi)
    if L2 > 0.0:
        r = float(st.z @ (p.inertia * st.z)) / L2
    else:
        # At rest r = 2T/L² is the limit along the direction L grows in (ξ3, body Γᵀξ3).
        e = st.gamma.T @ _XI3
        r = float(e @ (e / p.inertia))
    return np.array([*L_xi, r])


def _r_to_k2(p: Params, r: ArrayLike) -> FloatArray:
    # k² of the current regime as a function of r = 2T/L² only.
    return modulus_squared_of_ratio(*p.sorted_inertia, np.ravel(r))


def _vector_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    L_xi, r = Y[:, :3], Y[:, 3]
    L = np.linalg.norm(L_xi, axis=1)
    perp = np.hypot(L_xi[:, 0], L_xi[:, 1])
    sigma = np.where(perp > 0.0, np.arctan2(L_xi[:, 1], L_xi[:, 0]), _initial_sigma(p, st))
    return {
        "L": L,
        "rho": np.arctan2(perp, L_xi[:, 2]),
        "sigma": sigma,
        "T": 0.5 * r * L * L,
        "k2": _r_to_k2(p, r),
    }


SEPARATRIX_STEP = 1e-10
"""Relative step in r = 2T/L² taken across the separatrix when the averaged run restarts there.

On the separatrix r = 1/I2 the averaged r′ vanishes with infinite slope: r ≡ 1/I2 is a spurious
solution (§10, "k² ≡ 1"), and the physical one leaves it in finite time. The restart moves
to the side r decreases toward; the time this skips is ~ SEPARATRIX_STEP·ln(1/SEPARATRIX_STEP)
of the slow scale, far below the integration tolerance."""


def _step_over_separatrix(t: float, y: FloatArray) -> FloatArray:
    # r decreases along every averaged solution (d(2T/L²)/dτ ≤ 0, §10): step to r < 1/I2.
    out = np.array(y, dtype=float)
    out[3] *= 1.0 - SEPARATRIX_STEP
    return out


def averaged_rhs_numeric(t: float, y: FloatArray, p: Params) -> FloatArray:
    """The vector form of the averaged equations from the general engine: the
    eddy-current torque averaged over the Euler–Poinsot motion and the field's rotation by
    quadrature; equal to :func:`averaged_rhs_vector` to round-off away from the separatrix.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[L_ξ1, L_ξ2, L_ξ3, r]``, r = 2T/L² [inertia unit, 1/inertia unit].
    p : Params
    """
    r = reached_ratio(*p.sorted_inertia, float(y[3]))
    if math.isnan(r):
        return np.full(4, math.nan)  # past a pure rotation: the solver rejects the step
    state = np.array([y[0], y[1], y[2], r])
    return triaxial_average_vector(p.torque, p.inertia, state, t, forcing_period=2.0 * math.pi)


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order 2 in mean variables (L̄_ξ, T̄), the mean angle
    variables of the Euler–Poinsot motion and the field's phase
    (:class:`tumble.averaging.triaxial_second.TriaxialSystem` on the eddy-current torque,
    period 2π in τ), from the mean state of the given one (``options.initial =
    "osculating"``) or from it; the columns are the osculating ones rebuilt at each time asked
    for, the mean L_ξ and T beside them."""
    return triaxial_mean_form(p.torque, p.inertia, 1.0, st.z, st.gamma, 2.0 * math.pi, options,
                              lambda L_xi, T: _columns_from_momentum(L_xi, T, p),
                              "(1.5)")  # fmt: skip


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """(3.5)–(3.7) in the vector form, or the general engine (``averaging = "numeric"``,
    :func:`tumble.averaging.triaxial_average_vector`: the eddy-current torque averaged over the
    polhode, the precession about L and the field's rotation), or the equations of order 2 in
    mean variables (:func:`_mean_form`)."""
    if options.order == 2:
        return _mean_form(p, st, options)
    I1, I2, I3 = p.sorted_inertia
    breakpoints: tuple[Breakpoint, ...] = ()
    numeric = options.averaging == "numeric"
    if I1 < I2 < I3:
        separatrix = Breakpoint(
            lambda t, y: float(y[3]) - 1.0 / I2, _step_over_separatrix,
            event=EVENT_TRIAXIAL_SEPARATRIX if numeric else EVENT_FIELD_SEPARATRIX,
        )  # fmt: skip
        breakpoints = (separatrix,)
    return AveragedForm(
        name="numeric" if numeric else "vector",
        equation=(
            "(3.5)-(3.7) by quadrature (tumble.averaging)"
            if numeric
            else "(3.5)-(3.7), vector form of §10"
        ),
        slow=("L1", "L2", "L3", "r"),
        rhs=averaged_rhs_numeric if numeric else averaged_rhs_vector,
        initial_state=_vector_from_slow,
        to_columns=_vector_columns,
        breakpoints=breakpoints,
        kernel=numeric_kernel if numeric else averaged_kernel,
    )


def numeric_kernel(p: Params) -> Kernel | None:
    """:func:`averaged_rhs_numeric` compiled (:func:`tumble.averaging.triaxial_kernel`);
    None for a body with two equal moments (the Python engine's symmetric formulas)."""
    return triaxial_kernel(p.torque, p.inertia, 2.0 * math.pi)


def averaged_kernel(p: Params) -> Kernel:
    """:func:`averaged_rhs_vector` compiled (:mod:`tumble.kernels`), with the period averages
    by Carlson's integrals; its event function is the separatrix r = 1/I2."""
    return Kernel(KIND_FIELD_AVERAGED, np.array([p.eps, p.s2, p.c2, *p.sorted_inertia]))


# ---------------------------------------------------------------------------------------------
# Stationary rotation and its linearization (2.1)–(2.6).


def linear_matrix(p: Params) -> FloatArray:
    """The 5×5 matrix of the linearized system (2.4) in (x1, x2, x3, γ1, γ2).

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray, shape (5, 5)
        J with (x, γ)′ = J (x, γ) [1].
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    sc = 0.5 * e * math.sin(2.0 * p.beta)
    return np.array(
        [
            [-e * c2 / I1, -(I3 - I2) / I1, sc / I1, 0.0, -e * c2 / I1],
            [(I3 - I1) / I2, -e / I2, 0.0, e / I2, 0.0],
            [sc / I3, 0.0, -e * s2 / I3, 0.0, sc / I3],
            [1.0, 0.0, 0.0, 0.0, 1.0],
            [0.0, 1.0, 0.0, -1.0, 0.0],
        ]
    )


def characteristic_coefficients(p: Params) -> FloatArray:
    """Coefficients a0 … a5 of the characteristic polynomial (2.5), highest power first.

    Exact for every ε (§6); ``a0 = I1 I2 I3``.

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray, shape (6,)
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    d2, d1 = I3 - I2, I3 - I1
    return np.array(
        [
            I1 * I2 * I3,
            e * (I1 * I3 + I1 * I2 * s2 + I2 * I3 * c2),
            I1 * I2 * I3 + d2 * d1 * I3 + e * e * (I1 * s2 + I3 * c2),
            e * I3 * d2 + e * (d2 * d1 + I1 * I2) * s2 + e * I3 * d1 * c2,
            d2 * d1 * I3 + e * e * d2 * s2,
            e * d2 * d1 * s2,
        ]
    )


def approximate_roots(p: Params) -> np.ndarray:
    """First-order roots (2.6), error O(ε²) where the unperturbed roots are simple.

    ``λ1 = −ε s²/I3``, ``λ2,3 = ±iω0 − (ε/2)[(I3 − I2)/(I2 I3) + (I3 − I1)/(I1 I3) c²]``,
    ``λ4,5 = ±i − ε (1 + c²)/(2 I3)``, ``ω0² = (I3 − I2)(I3 − I1)/(I1 I2)``; for ω0² < 0 (middle
    axis) ±iω0 is the real pair ∓|ω0|.

    Parameters
    ----------
    p : Params

    Returns
    -------
    ndarray of complex, shape (5,)
    """
    I1, I2, I3 = p.inertia.tolist()
    e, c2, s2 = p.eps, p.c2, p.s2
    w02 = (I3 - I2) * (I3 - I1) / (I1 * I2)
    iw0 = 1j * math.sqrt(w02) if w02 >= 0.0 else complex(math.sqrt(-w02))
    d23 = -0.5 * e * ((I3 - I2) / (I2 * I3) + (I3 - I1) / (I1 * I3) * c2)
    d45 = -e * (1.0 + c2) / (2.0 * I3)
    return np.array([-e * s2 / I3, iw0 + d23, -iw0 + d23, 1j + d45, -1j + d45])


def _approx_note(p: Params) -> str:
    I1, I2, I3 = p.inertia.tolist()
    w02 = (I3 - I2) * (I3 - I1) / (I1 * I2)
    small = p.eps / min(I1, I2, I3)
    if w02 == 0.0:
        return "(2.6) is invalid: I3 equals another moment, ω0 = 0 is a double root (§6)"
    if abs(math.sqrt(abs(w02)) - 1.0) <= small and w02 > 0.0:  # (2.6) needs ε/I ≪ |1 − ω0|
        return (
            "(2.6) is invalid: near a thin plate I3 ≈ I1 + I2 the roots ±iω0 and ±i (nearly) "
            "coincide, so the first-order corrections can be wrong at O(ε) (§6)"
        )
    if small > VALIDITY_RATIO:
        return f"(2.6) is a small-ε approximation; ε/min I = {small:.3g} is not small (§6)"
    return ""


def stationary(p: Params, phase: float = 0.0) -> StationaryMotion[Params]:
    """The stationary co-rotation (2.1) about body x3 and its linearization chart (2.2).

    The co-rotations form a family Γ = R3(φ), z = ξ3 (§5): the body's phase φ relative to
    the field is free. The paper linearizes at φ = 0 (Γ = E), where (2.5) and (2.6) hold; at
    other phases the field lies in another plane of the body and the decay rates differ (the
    family is reported by :attr:`StationaryMotion.family`).

    Parameters
    ----------
    p : Params
    phase : float
        φ of Γ = R3(φ) [rad]; 0 is the paper's (2.1).

    Returns
    -------
    StationaryMotion
        Local coordinates (x1, x2, x3, γ1, γ2, γ3) with z = ξ3 + x, Γ = R3(φ)(E + γ̂); γ3 (the
        free phase) decouples, so stability is decided on the first five (§5).
    """
    R = rot_z(phase)

    def embed(x: Any) -> Any:
        # Exact to first order in x, which is all the Jacobian at the stationary point needs.
        return np.concatenate([_XI3 + x[:3], (R @ (np.eye(3) + _hat(x[3:6]))).ravel()])

    def tangent(y: Any, dy: Any) -> Any:
        # γ̂′ = the skew part of R3(φ)ᵀ Γ′ (first order at Γ = R3(φ)).
        W = R.T @ dy[3:].reshape(3, 3)
        W = 0.5 * (W - W.T)
        return np.concatenate([dy[:3], [W[2, 1], W[0, 2], W[1, 0]]])

    paper = phase == 0.0
    coeffs = characteristic_coefficients(p) if paper else None
    return StationaryMotion(
        name="co-rotation about body x3 (2.1)" + ("" if paper else f", phase {phase:.6g} rad"),
        equation="(1.5) linearized as (2.3)/(2.4)",
        state=np.concatenate([_XI3, R.ravel()]),
        rhs=full_rhs,
        embed=embed,
        tangent=tangent,
        coordinates=("x1", "x2", "x3", "gamma1", "gamma2", "gamma3"),
        keep=(0, 1, 2, 3, 4),
        leading=float(np.prod(p.inertia)),
        coefficients=coeffs,
        approx_roots=approximate_roots(p) if paper else None,
        approx_note=_approx_note(p) if paper else "",
        structural_zero=bool(characteristic_coefficients(p)[5] == 0.0),
        family=(lambda phi: stationary(p, phi)) if paper else None,
    )


# ---------------------------------------------------------------------------------------------
# Validity, frequencies and predicted limits, §§11–13.


def _frequencies(p: Params, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    nu = np.array(
        [
            fast_frequencies(*p.sorted_inertia, L, T)
            for L, T in zip(cols["L"], cols["T"], strict=True)
        ]
    )
    return {"nu1": nu[:, 0], "nu2": nu[:, 1]}


def diagnostics(p: Params, st: State, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    """Fast frequencies along an averaged solution, §8 and §15.

    Parameters
    ----------
    p : Params
    st : State
    cols : dict
        Averaged columns (``L``, ``T``).

    Returns
    -------
    dict
        ``nu1`` (polhode frequency 2πν/4K) and ``nu2`` (mean precession rate about L), in units
        of the field rate [1].
    """
    return _frequencies(p, cols)


def _resonances() -> list[tuple[int, int, int]]:
    n1max, n2max = RESONANCE_ORDERS
    out = []
    for m in (1, 2):
        for n2 in range(-n2max, n2max + 1):
            for n1 in range(-n1max, n1max + 1):
                if (n1, n2) != (0, 0) and (m, n1, n2) != (1, -1, 1):
                    out.append((m, n1, n2))
    return out


def validity(p: Params, st: State, slow: SlowPath, tau_end: float) -> list[ValidityIssue]:
    """Regions of §12 that an averaged trajectory enters, with the first τ of each.

    Parameters
    ----------
    p : Params
    st : State
    slow : callable
        ``slow(tau) -> columns`` along the averaged trajectory.
    tau_end : float
        End of the run [1].

    Returns
    -------
    list of ValidityIssue
        ``eps_not_small`` (ε/min I > 0.1), ``separatrix`` (L² = 2T I2 crossed: ν1 → 0),
        ``momentum_small`` (L so small that the fast frequencies are not fast), ``resonance``
        (m = n1 ν1 + n2 ν2 for m = 1, 2, |n1|, |n2| ≤ 2, crossed or approached within
        √(ε/min I)), ``co_rotation`` (the final stage, |ν2 − ν1 − 1| ≤ ε/min I, where the
        body's phase relative to the field is slow and (3.7) over-predicts the nutation decay of
        a triaxial body; (2.6) gives the true rate).
    """
    small = p.small_parameter
    issues: list[ValidityIssue] = []
    if small > VALIDITY_RATIO:
        issues.append(
            ValidityIssue(
                "eps_not_small",
                0.0,
                f"ε/min I = {small:.3g} is not small (> {VALIDITY_RATIO:g}): the averaged "
                "equations do not apply; only the full model and the linear stability results "
                "are exact (docs/theory/rotating-field.md §12)",
            )
        )
    if tau_end <= 0.0:
        return issues
    grid = np.linspace(0.0, tau_end, 2001)
    cols = slow(grid)
    # Fast frequencies ~ L/I3 against the slow rates ~ ε/I1.
    I1, I2, I3 = p.sorted_inertia
    L_small = I3 * small / VALIDITY_RATIO
    found = (
        separatrix_issue(slow, grid, I2, time="τ") if I1 < I2 < I3 else None,
        _momentum_issue(slow, grid, L_small),
        *_frequency_issues(p, grid, cols, L_small),
    )
    return issues + [issue for issue in found if issue is not None]


def _momentum_issue(slow: SlowPath, grid: FloatArray, L_small: float) -> ValidityIssue | None:
    """The first time L falls below ``L_small``, where the fast frequencies stop being fast."""

    def momentum_small(t: FloatArray) -> FloatArray:
        return L_small - slow(t)["L"]

    tau_l = first_time(momentum_small, grid)
    if tau_l is None:
        return None
    return ValidityIssue(
        "momentum_small",
        tau_l,
        f"from τ = {tau_l:.6g} L < {L_small:.3g}: the fast frequencies are no longer "
        "fast against the slow drift, averaging is locally invalid; the vector form "
        "carries L through 0, but k² after such a passage is not predicted "
        "(docs/theory/rotating-field.md §12)",
    )


def _frequency_issues(
    p: Params, grid: FloatArray, cols: dict[str, FloatArray], L_small: float
) -> tuple[ValidityIssue | None, ValidityIssue | None]:
    """The first resonance the averaged motion meets, and the start of the co-rotation."""
    small = p.small_parameter
    nu = _frequencies(p, cols)
    moving = cols["L"] > L_small
    det_co = np.abs(nu["nu2"] - nu["nu1"] - 1.0)
    co = np.flatnonzero(moving & (det_co <= small))
    co_rotation = None
    if co.size:
        tau_c = float(grid[co[0]])
        co_rotation = ValidityIssue(
            "co_rotation",
            tau_c,
            f"from τ ≈ {tau_c:.6g} the body nearly co-rotates with the field (|ν2 − ν1 − 1| "
            "≤ ε/min I): the phase relative to the field is slow, independent averaging "
            "fails, and the final nutation decay of a triaxial body depends on the phase at "
            "which it settles, between the rate of (2.6) and 1.8 times it; (3.7) gives its mean "
            "over that phase (docs/theory/rotating-field.md §12)",
        )
    return _resonance_issue(p, grid, nu, moving), co_rotation


def _resonance_issue(
    p: Params, grid: FloatArray, nu: dict[str, FloatArray], moving: BoolArray
) -> ValidityIssue | None:
    """The first resonance m = n1 ν1 + n2 ν2 (m = 1, 2; |n1|, |n2| ≤ 2) crossed or approached
    within √(ε/min I), and how long the motion lingers near it."""
    small = p.small_parameter
    width = math.sqrt(small)
    first: tuple[float, float, tuple[int, int, int]] | None = None
    dtau = grid[1] - grid[0]
    for m, n1, n2 in _resonances():
        det = n1 * nu["nu1"] + n2 * nu["nu2"] - m
        near = moving & (np.abs(det) <= width)
        crossed = moving[1:] & moving[:-1] & (det[1:] * det[:-1] < 0.0)
        candidates = [int(i) for i in np.flatnonzero(near)[:1]]
        candidates += [int(i) + 1 for i in np.flatnonzero(crossed)[:1]]
        if candidates:
            i = min(candidates)
            if first is None or grid[i] < first[0]:
                first = (float(grid[i]), float(np.count_nonzero(near)) * dtau, (m, n1, n2))
    if first is None:
        return None
    tau_r, linger, (m, n1, n2) = first
    # Lingering over a tenth of the slow scale 1/(ε/min I) or more: the resonant terms act
    # as long as the averaged ones, O(1) effect (§12).
    effect = (
        "it lingers there long enough to put averaged k² and T off by O(1)"
        if linger >= VALIDITY_RATIO / small
        else "a passage shifts averaged k² and T by O(√ε) at most"
    )
    sign = "+" if n2 >= 0 else "−"
    return ValidityIssue(
        "resonance",
        tau_r,
        f"at τ ≈ {tau_r:.6g} the averaged motion meets the resonance {m} = {n1}·ν1 "
        f"{sign} {abs(n2)}·ν2 (field harmonic vs polhode ν1 and "
        f"precession ν2) and stays within √(ε/min I) of it for Δτ ≈ {linger:.3g}: "
        f"{effect}; L and ρ stay O(ε)-accurate (docs/theory/rotating-field.md §12)",
        label=f"resonance {m}·ω = {n1}·ν1 {sign} {abs(n2)}·ν2",
    )


def final_nutation_decay_rate(p: Params, phase: float = 0.0) -> float:
    """Decay rate of k² (∝ nutation amplitude²) at co-rotation with phase φ, 2 Re λ2,3.

    ``2 Re λ2,3 = −ε [a (cos²φ + c² sin²φ) + b (c² cos²φ + sin²φ)]`` with
    ``a = (I3 − I2)/(I2 I3)``, ``b = (I3 − I1)/(I1 I3)`` (body x3 the largest axis, user
    labels). At φ = 0 this is (2.6); the co-rotations Γ = R3(φ) form a family (§5) and the
    phase a body settles at decides its final rate. The mean over φ is the linearization of
    (3.7) at k → 0, ρ = 0, −ε (1 + c²)(a + b)/2: averaging over the field phase is exact for
    this rate only on average (§12 compares with φ = 0 alone). Derived here by first-order
    perturbation of the linearization at Γ = R3(φ); tests check it against the exact roots.

    Parameters
    ----------
    p : Params
    phase : float
        φ [rad].

    Returns
    -------
    float
        d ln k²/dτ [1/τ], first order in ε.
    """
    I1, I2, I3 = p.inertia.tolist()
    a, b = (I3 - I2) / (I2 * I3), (I3 - I1) / (I1 * I3)
    cp, sp = math.cos(phase) ** 2, math.sin(phase) ** 2
    return -p.eps * (a * (cp + p.c2 * sp) + b * (p.c2 * cp + sp))


def predicted_limits(p: Params, st: State) -> dict[str, Any]:
    """End state of the averaged system, §11, and the final nutation decay rates, §12.

    For β ≠ 0: ρ → 0, k² → 0, L → I_max (co-rotation about the largest axis), T → I_max/2.
    For β = 0: L_ξ3 is conserved, ρ → 0 or π by the initial hemisphere, L → |L_ξ3(0)|.

    Parameters
    ----------
    p : Params
    st : State

    Returns
    -------
    dict
    """
    I1, I2, I3 = p.sorted_inertia
    out: dict[str, Any] = {"sigma": _initial_sigma(p, st), "k2": 0.0}
    if p.s2 > 0.0:
        out.update(L=I3, rho=0.0, T=0.5 * I3, end_state="co-rotation about the largest axis")
    else:
        L3 = float((st.gamma @ (p.inertia * st.z))[2])
        out.update(
            L=abs(L3),
            rho=0.0 if L3 > 0 else (math.pi if L3 < 0 else float("nan")),
            T=0.5 * L3 * L3 / I3,
            end_state="spin about the static field along ξ3 (β = 0)",
        )
    # Nutation decay at the end: linearization of (3.7) vs 2 Re λ2,3 at the final phase, §12.
    if I3 > I1:
        rates = [final_nutation_decay_rate(p, phi) for phi in (0.0, 0.5 * math.pi)]
        out["nutation_decay_rate_averaged"] = (
            -p.eps * (1.0 + p.c2) / 2.0 * ((I3 - I2) / (I2 * I3) + (I3 - I1) / (I1 * I3))
        )
        out["nutation_decay_rate_phase0"] = rates[0]
        out["nutation_decay_rate_range"] = [min(rates), max(rates)]
    return out


# ---------------------------------------------------------------------------------------------
# Registry record.

_COLUMNS_MEAN = (
    *(Column(f"L{i}_mean", f"mean inertial angular momentum L_ξ{i} (averaging of order 2)",
             "1", "(3.5)") for i in (1, 2, 3)),
    Column("T_mean", "mean kinetic energy T (averaging of order 2)", "1", "(3.6)"),
)  # fmt: skip
_COLUMNS_SLOW = (
    Column("L", "angular momentum |L|", "1", "(3.5)"),
    Column("rho", "polar angle ρ of L from ξ3", "rad", "(3.5)"),
    Column("sigma", "inertial azimuth σ of L", "rad", "(3.5)", angle=True, unwrap=True),
    Column("T", "kinetic energy T", "1", "(3.6)"),
    Column("k2", "Euler–Poinsot modulus k² of the current regime", "1", "(3.7)"),
)
_COLUMNS_FULL = (
    *_COLUMNS_SLOW,
    Column("z1", "body angular velocity z1 = Ω1/ω", "1", "(1.5)"),
    Column("z2", "body angular velocity z2 = Ω2/ω", "1", "(1.5)"),
    Column("z3", "body angular velocity z3 = Ω3/ω", "1", "(1.5)"),
    *attitude_columns("τ"),  # ω1, ω2, ω3 = z1, z2, z3, as in every model
)
_DIAGNOSTICS = (
    Column("nu1", "polhode frequency ν1 = 2πν/4K", "1", "docs/theory/rotating-field.md §8"),
    Column("nu2", "mean precession rate ν2 about L", "1", "docs/theory/rotating-field.md §8"),
)


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
    packed[3] = 0.0  # ε
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


_ENTRY = CATALOGUE["rotating_field"]  # name, description and paper

MODEL: Model[Params, State] = Model(
    name=_ENTRY.name,
    description=_ENTRY.description,
    paper=_ENTRY.paper,
    time=DECLARED.time,
    full=Full(
        forms={"rotating": FULL_ROTATING, "inertial": FULL_INERTIAL},
        default="rotating",
        columns=fixed_columns(_COLUMNS_FULL),
    ),
    check=DECLARED.check,
    methods=DECLARED.methods,
    averaged=Averaged(
        form=_averaged_form,
        columns=fixed_columns((*_COLUMNS_SLOW, *_COLUMNS_MEAN)),
        # σ is left out: it is the azimuth of L about ξ3, undefined as the transient aligns L
        # with ξ3 (ρ → 0), where its error says nothing about the motion.
        compare=("L", "rho", "T"),
        diagnostics=Diagnostics(diagnostics, _DIAGNOSTICS),
        numeric=DECLARED.numeric,
        orders=DECLARED.orders,
    ),
    unperturbed=Unperturbed("the free body (3.1)", free_motion, _free_rhs),
    validity=Validity(check=validity, limits=predicted_limits),
    stationary=stationary,
    scenario=DECLARED.scenario,
)
