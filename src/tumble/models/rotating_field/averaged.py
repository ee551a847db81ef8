"""The averaged equations of the rotating-field model: (3.5)–(3.7) in the T- and k²-forms,
the regular vector form of §10, the general engine's quadrature, and the equations of
order 2 in mean variables.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from scipy.special import ellipe, ellipk

from tumble._typing import FloatArray
from tumble.averaging.triaxial import triaxial_average_stage, triaxial_kernel
from tumble.kernels import (
    EVENT_FIELD_SEPARATRIX,
    EVENT_TRIAXIAL_SEPARATRIX,
    KIND_FIELD_AVERAGED,
    Kernel,
    evaluate_rhs,
)
from tumble.kernels.columns import VECTOR_COLUMNS, vector_columns
from tumble.models.base import AveragedForm, AveragingOptions, Breakpoint
from tumble.models.inputs.rotating_field import Params, State
from tumble.models.rotating_field.full import _XI3, _columns_from_momentum
from tumble.models.triaxial_mean import triaxial_mean_form
from tumble.rotations import rot_z
from tumble.unperturbed import energy_from_modulus, mean_square_rate, regime

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
    One definition: the compiled code the integrator runs (:func:`averaged_kernel`), with the
    period averages by Carlson's integrals; NaN past a pure rotation (r outside [1/I3, 1/I1]
    by more than the margin of :func:`~tumble.unperturbed.reached_ratio`), so that the solver
    rejects the step. The T-form :func:`averaged_rhs` (scipy's elliptic integrals) is the
    independent form it is checked against.

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
    return evaluate_rhs(averaged_kernel(p), t, y)


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


def _no_turning_angle(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """The angle columns that turn: none, σ being constant (:func:`_vector_columns`), so that a
    compiled run does not build its columns on every step to unwrap it."""
    return {}


def _degenerate(p: Params) -> bool:
    """Two or three equal moments: k² carries no information (0)."""
    # Any state's regime says it; the separatrix's energy 2T = L²/I2 is one that always exists.
    return regime(p.sorted_inertia, 1.0, 0.5 / float(p.sorted_inertia[1])) in (
        "symmetric",
        "sphere",
    )


def _vector_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
    """L, ρ, σ, T and k² of states ``[L_ξ, r]``, in one compiled pass that holds no lock
    (:func:`tumble.kernels.columns.vector_columns`; k² as
    :func:`tumble.unperturbed.modulus_squared_of_ratio` gives it).

    The averaged equations keep σ constant: dL_ξ/dτ = ε(r D L_ξ + sin²β ξ3) with D =
    −diag(a, a, sin²β) scales L_ξ1 and L_ξ2 by one factor (§10), and the general engine's
    average of the same torque equals that form to round-off. So σ needs no unwrapping on the
    steps: each sample's value is taken within π of the initial one (on the ξ3 axis, where L
    has no azimuth, the initial one).
    """
    I1, I2, I3 = (float(v) for v in p.sorted_inertia)
    table = vector_columns(np.ascontiguousarray(Y, dtype=float), I1, I2, I3, _degenerate(p),
                           _initial_sigma(p, st))  # fmt: skip
    return {name: np.ascontiguousarray(table[:, j]) for j, name in enumerate(VECTOR_COLUMNS)}


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
    The Python engine (:func:`tumble.averaging.triaxial_average_vector`): the oracle the
    closed-form vector form is tested against; an averaged run integrates its compiled twin
    (:func:`numeric_kernel`) where one exists.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[L_ξ1, L_ξ2, L_ξ3, r]``, r = 2T/L² [inertia unit, 1/inertia unit].
    p : Params
    """
    return triaxial_average_stage(p.torque, p.inertia, y, t, 2.0 * math.pi)


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order 2 in mean variables (L̄_ξ, T̄), the mean angle
    variables of the Euler–Poinsot motion and the field's phase
    (:class:`tumble.averaging.triaxial_second.TriaxialSystem` on the eddy-current torque,
    period 2π in τ), from the mean state of the given one (``options.initial =
    "osculating"``) or from it; the columns are the osculating ones rebuilt at each time asked
    for, the mean L_ξ and T beside them."""
    return triaxial_mean_form(p.torque, p.inertia, 1.0, st.z, st.gamma, 2.0 * math.pi, options,
                              lambda L_xi, T: _columns_from_momentum(L_xi, T, p),
                              "(1.5)", _BODY_STATE)  # fmt: skip


def _full_of_body(t: float, z: FloatArray, A: FloatArray) -> FloatArray:
    """The state ``[z, Γ by rows]`` of (1.5) at τ = t of the body rate z and the inertial
    attitude A: Γ = B(τ) A, the field's frame turned by τ about ξ3 (§9)."""
    return np.concatenate([z, (rot_z(-t) @ A).ravel()])


def _body_of_full(t: float, y: FloatArray) -> tuple[FloatArray, FloatArray]:
    """z and the inertial attitude A = Bᵀ(τ) Γ of a state of (1.5) at τ = t."""
    return np.asarray(y[:3], dtype=float), rot_z(t) @ np.asarray(y[3:], dtype=float).reshape(3, 3)


_BODY_STATE = (_full_of_body, _body_of_full)


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """(3.5)–(3.7) in the vector form, or the general engine (``averaging = "numeric"``,
    :func:`tumble.averaging.triaxial_average_vector`: the eddy-current torque averaged over the
    polhode, the precession about L and the field's rotation), or the equations of order 2 in
    mean variables (:func:`_mean_form`)."""
    if options.order == 2 or options.hybrid:
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
        angles=_no_turning_angle,
    )


def numeric_kernel(p: Params) -> Kernel | None:
    """:func:`averaged_rhs_numeric` compiled (:func:`tumble.averaging.triaxial_kernel`), for
    triaxial and symmetric bodies alike."""
    return triaxial_kernel(p.torque, p.inertia, 2.0 * math.pi)


def averaged_kernel(p: Params) -> Kernel:
    """:func:`averaged_rhs_vector` compiled (:mod:`tumble.kernels`), with the period averages
    by Carlson's integrals; its event function is the separatrix r = 1/I2."""
    return Kernel(KIND_FIELD_AVERAGED, np.array([p.eps, p.s2, p.c2, *p.sorted_inertia]))
