"""Symmetric body under the nonlinear moment M0(θ) = A(a·sinθ + b·sin2θ): full motion, the
exact unperturbed motion, and Volosov's averaged equations for the nutation envelope.

V. M. Serov, *Rotational motion of a dynamically symmetric rigid body under the action of a
nonlinear moment* (1991). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/nonlinear-moment.md``, which states where tumble departs from the printed paper and
why (corrections S1–S16 of its §12: A is the equatorial moment; β, τ0, γ0, χ±, λ±, L± and the
coefficient of L±).

Variables (§1): time t in the unit of the coefficients (a, b [1/t²], R, G [1/t]),
μ = C/A, classical z–x–z Euler angles ψ, θ, φ of the body relative to the fixed axis e_z (for
an entry vehicle the velocity direction, θ the total angle of attack), R = μr and G = K·e_z/A
the reduced angular momenta. The perturbation of §9 (the entry capsule) has slow time τ = εt:
a = a0·Q(τ), b = b0·Q(τ) with the dynamic-pressure profile Q, pitch damping εd and roll
damping εν.

The averaged method integrates (2.2)–(2.3) for the slow variables: the energy H (form
``"energy"``, the better-conditioned one of §7) or the turning point θext (form
``"theta_max"``/``"theta_min"``, the paper's (2.2)), together with z = (R, G, a, b). The
averages come from the closed forms of §8 (⟨u⟩, ⟨u²⟩ by K, E, Π) for the built-in
perturbation, and from adaptive quadrature over the nutation period for any perturbation
given as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any, Literal

import numpy as np

from tumble._typing import FloatArray
from tumble.averaging.nutation import (
    AVERAGE_RTOL,
    NutationSystem,
    Perturbation,
    numeric_averages,
    nutation_generator,
    potential_gradient,
    torque_perturbation,
)
from tumble.averaging.second_order import MeanSystem
from tumble.catalogue import CATALOGUE
from tumble.errors import IntegrationError, ParameterError
from tumble.kernels import (
    EVENT_NONE,
    EVENT_NUTATION_SEPARATRIX,
    EVENT_THETA_DOT,
    KIND_NONLINEAR_MOMENT,
    KIND_NUTATION_AVERAGED,
    KIND_NUTATION_ENGINE,
    Kernel,
)
from tumble.kernels.nutation import evaluate_separatrix_distance, evaluate_well, nutation_columns
from tumble.kernels.rhs import evaluate_event, symmetric_body
from tumble.models.base import (
    Averaged,
    AveragedForm,
    AveragingOptions,
    Breakpoint,
    ClosedForm,
    Column,
    Diagnostics,
    Full,
    FullForm,
    Json,
    Model,
    Report,
    Sampled,
    SlowPath,
    Unperturbed,
    Validity,
    ValidityIssue,
    attitude_columns,
    attitude_values,
    first_time,
    fixed_columns,
)
from tumble.models.inputs.nonlinear_moment import DECLARED, Params, Pressure, State, orbit_of
from tumble.rotations import euler313_to_matrix, matrix_to_euler313, matrix_to_quat, quat_to_matrix
from tumble.torques import LinearDrag
from tumble.unperturbed.symmetric_body import NutationOrbit, effective_potential, potential_slope

__all__ = [
    "AVERAGE_RTOL",
    "EPS_PERIOD_LIMIT",
    "MODEL",
    "NEAR_SEPARATRIX",
    "Params",
    "Perturbation",
    "Pressure",
    "State",
    "averaged_initial",
    "averaged_rhs",
    "barrier_energies",
    "builtin_perturbation",
    "closed_form",
    "damping_torque",
    "engine_perturbation",
    "envelope_discrepancy",
    "extrema",
    "full_from_slow",
    "full_rhs",
    "invariants",
    "numeric_averages",
    "orbit_of",
    "potential_gradient",
    "reduced_rhs",
    "slow_from_full",
    "torque_perturbation",
]

NEAR_SEPARATRIX = 1e-3
"""1 − k² below which an averaged run is warned that it nears a separatrix (§11)."""

EPS_PERIOD_LIMIT = 0.5
"""ε·T (slow time per nutation period) above which ε is not small enough for averaging."""


# ---------------------------------------------------------------------------------------------
# Parameters and states.


# ---------------------------------------------------------------------------------------------
# Full equations: (1.1) with quaternion kinematics (singularity-free), and the reduced (1.3).


def full_from_slow(p: Params, st: State) -> FloatArray:
    """State ``[p, q, r, q0, q1, q2, q3]`` of the quaternion form from Euler angles and R, G
    (:func:`_rate_and_attitude`).

    Parameters
    ----------
    p : Params
    st : State

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


# ---------------------------------------------------------------------------------------------
# The perturbation (2.1) in general, and the built-in one of §9.


def builtin_perturbation(p: Params) -> Perturbation:
    """Φθ, Φz of the descending capsule, §9: pitch and roll damping, pressure Q(τ).

    Φθ = −dθ', Φ_R = −νR, Φ_G = −d(G − Ru) − νRu, Φ_a = a0 Q'(τ), Φ_b = b0 Q'(τ).

    Parameters
    ----------
    p : Params

    Returns
    -------
    Perturbation
    """

    def phi_theta(tau: float, theta: FloatArray, theta_dot: FloatArray, z: FloatArray) -> Any:
        return -p.d * theta_dot

    def phi_z(tau: float, theta: FloatArray, z: FloatArray) -> FloatArray:
        R, G = z[0], z[1]
        u = np.cos(theta)
        da, db = p.ab_rate(tau)
        one = np.ones_like(u)
        return np.array(
            [-p.nu * R * one, -p.d * (G - R * u) - p.nu * R * u, float(da) * one, float(db) * one]
        )

    return Perturbation(phi_theta, phi_z, name="§9 (pitch/roll damping, pressure)")


def reduced_rhs(t: float, y: FloatArray, p: Params, perturbation: Perturbation) -> FloatArray:
    """The full model in the reduced form (1.3) and (2.1), for any perturbation.

    State ``[θ, θ', ψ, φ, R, G, a, b]``: θ'' = −F(θ, z) + εΦθ, z' = εΦz, and ψ', φ' from
    (1.3). Singular at θ = 0, π (use :func:`full_rhs` there).

    Parameters
    ----------
    t : float
        Time [t].
    y : ndarray, shape (8,)
    p : Params
        μ and ε (a, b come from the state).
    perturbation : Perturbation

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


# ---------------------------------------------------------------------------------------------
# Averaged equations (2.2)–(2.3).


def _builtin_averages(orbit: NutationOrbit, p: Params, tau: float) -> tuple[float, FloatArray]:
    """The averages of §9 in closed form: ⟨u⟩, ⟨u²⟩ by K, E, Π (§8)."""
    R, G, a, b, E = orbit.R, orbit.G, orbit.a, orbit.b, orbit.E
    m1, m2 = orbit.mean_u_power(1), orbit.mean_u_power(2)
    da, db = (float(v) for v in p.ab_rate(tau))
    g = -p.d * 2.0 * (E - a * m1 - b * m2) + da * m1 + db * m2
    phi_z = np.array([-p.nu * R, -p.d * (G - R * m1) - p.nu * R * m1, da, db])
    return g, phi_z


def barrier_energies(R: float, G: float, a: float, b: float) -> FloatArray:
    """Energies of the local maxima of W(θ) in (0, π): the separatrix levels of (1.6).

    F = W'(θ) = 0 is, times sin³θ, the quintic (G − Ru)(R − Gu) − (1 − u²)²(a + 2bu) = 0 in
    u = cos θ; a maximum of W is a root in (−1, 1) where F changes sign from + to − in θ.

    Parameters
    ----------
    R, G : float
        Reduced momenta [1/t].
    a, b : float
        Moment coefficients [1/t²].

    Returns
    -------
    ndarray
        The barrier energies [1/t²] (empty for a single well).
    """
    # (G − Ru)(R − Gu) = GR − (G² + R²)u + GR u²; (1 − u²)²(a + 2bu), highest power first.
    quartic = np.array([1.0, 0.0, -2.0, 0.0, 1.0])
    poly = -np.polymul(quartic, [2.0 * b, a])
    poly[-3:] += [G * R, -(G * G + R * R), G * R]
    out = []
    for r in np.roots(poly):
        if abs(r.imag) > 1e-9 or not -1.0 < r.real < 1.0:
            continue
        theta = math.acos(r.real)
        h = 1e-6 * min(theta, math.pi - theta)
        if potential_slope(theta - h, R, G, a, b) > 0.0 > potential_slope(theta + h, R, G, a, b):
            out.append(float(effective_potential(theta, R, G, a, b)))
    return np.array(out)


def _orbit_or_raise(build: Callable[[], NutationOrbit], t: float) -> NutationOrbit:
    try:
        return build()
    except ParameterError as exc:
        raise IntegrationError(
            f"averaged equations (2.2) at t = {t:.6g}: {exc} — averaging breaks down there "
            "(§11); do not average across a separatrix"
        ) from None


def averaged_rhs(
    t: float,
    y: FloatArray,
    p: Params,
    *,
    form: Literal["energy", "theta_max", "theta_min"] = "energy",
    u_hint: float = 0.0,
    perturbation: Perturbation | None = None,
) -> FloatArray:
    """Volosov's averaged equations (2.2)–(2.3) of §7.

    ``form = "energy"``: y = [H, R, G, a, b], H' = ε(⟨Φθθ'⟩ + ⟨Φz·W^z⟩), z' = ε⟨Φz⟩ (the
    better-conditioned form; the well is the allowed interval nearest ``u_hint``).
    ``form = "theta_max"`` or ``"theta_min"``: y = [θext, R, G, a, b] and (2.2),
    θext' = ε(⟨Φθθ'⟩ + ⟨Φz·W^z⟩ − ⟨Φz⟩·W^z(θext))/F(θext, z).

    Parameters
    ----------
    t : float
        Time [t].
    y : ndarray, shape (5,)
    p : Params
    form : str
    u_hint : float
        cos θ inside the tracked well (energy form).
    perturbation : Perturbation, optional
        Default: the built-in one of §9, averaged in closed form (§8); any other is
        averaged numerically (:func:`numeric_averages`).

    Returns
    -------
    ndarray, shape (5,)

    Raises
    ------
    IntegrationError
        Near a separatrix (1 − k² below ``SEPARATRIX_TOL``), or at zero amplitude in a θext
        form (F(θext) = 0: use the energy form).
    """
    x, R, G, a, b = y.tolist()
    tau = p.eps * t
    if form == "energy":
        orbit = _orbit_or_raise(
            lambda: NutationOrbit.from_energy(p.mu, a, b, R, G, x, u_hint=u_hint), t
        )
    else:
        orbit = _orbit_or_raise(lambda: NutationOrbit.from_turning_point(p.mu, a, b, R, G, x), t)
    if perturbation is None:
        g, phi_z = _builtin_averages(orbit, p, tau)
    else:
        g, phi_z = numeric_averages(orbit, perturbation, tau)
    if form == "energy":
        rate = g
    else:
        u_e = math.cos(x)
        F = float(potential_slope(x, R, G, a, b))
        if F == 0.0:
            raise IntegrationError(
                f"averaged equations (2.2) at t = {t:.6g}: F(θext) = 0 (zero nutation "
                'amplitude or an unstable equilibrium); use averaged_form = "energy"'
            )
        w_e = potential_gradient(np.array([u_e]), np.array([R, G, a, b]))[:, 0]
        rate = (g - float(phi_z @ w_e)) / F
    return p.eps * np.array([rate, *phi_z.tolist()])


def averaged_initial(
    p: Params,
    st: State,
    perturbation: Perturbation | None = None,
    start: Literal["exact", "corrected"] = "exact",
) -> tuple[float, FloatArray, NutationOrbit]:
    """The averaged initial state H̄(0), z̄(0) of §7 and §14 (``[run] averaged_init``).

    ``start = "exact"``: H̄ = H(0), z̄ = z(0) (the paper's). ``"corrected"``: the first-order
    mean state H̄ = H(0) − ε u₁_H, z̄ = z(0) − ε u₁_z, u₁ the generator of the general
    mean ↔ osculating map at the initial state (:func:`tumble.averaging.nutation
    .nutation_generator`); for the perturbations of the paper it equals
    ∫_{t*}^0 (g − ⟨g⟩)dt, ∫_{t*}^0 (Φz − ⟨Φz⟩)dt along the frozen orbit, t* ≤ 0 its last
    turning point, g = Φθθ' + W^z·Φz (measured to 1e-16).

    Parameters
    ----------
    p : Params
    st : State
    perturbation : Perturbation, optional
        Default: the built-in one.
    start : {"exact", "corrected"}
        The paper's start, or the one corrected to first order.

    Returns
    -------
    H : float
        H̄(0) [1/t²].
    z : ndarray, shape (4,)
        z̄(0) = (R, G, a, b).
    orbit : NutationOrbit
        The unperturbed orbit of (H̄(0), z̄(0)) in the initial well.
    """
    a0, b0 = (float(v) for v in p.ab(0.0))
    orbit = orbit_of(p, st)
    H = orbit.E
    z = np.array([st.R, st.G, a0, b0])
    if start == "corrected" and p.perturbed:
        # The first-order generator of the general map at the initial state: for this
        # paper's perturbations it is the integral from the last turning point (Serov 1991).
        pert = builtin_perturbation(p) if perturbation is None else perturbation
        u_H, u_z = nutation_generator(orbit, pert, 0.0)
        if u_H != 0.0 or np.any(u_z):
            H -= p.eps * u_H
            z = z - p.eps * u_z
            orbit = NutationOrbit.from_energy(
                p.mu, z[2], z[3], z[0], z[1], H, u_hint=0.5 * (orbit.u1 + orbit.u2)
            )
    return H, z, orbit


def damping_torque(p: Params) -> LinearDrag:
    """The damping of §9 as a body-axes torque per unit A and ε: −d(p, q, 0) − ν(0, 0, R).

    With R = μr this is the linear drag −diag(d, d, νμ) ω, so the engine recognises a torque
    of the body rate only and averages it over φ alone.

    Parameters
    ----------
    p : Params

    Returns
    -------
    LinearDrag
        ``(t, q, omega) -> δM/A`` [1/t²] (for ``torque_perturbation``).
    """
    return LinearDrag(np.diag([p.d, p.d, p.nu * p.mu]))


def engine_perturbation(p: Params) -> Perturbation:
    """The perturbation of §9 for the general engine: its damping as a torque, its
    pressure as the prescribed laws of a and b (``averaging = "numeric"``)."""
    return torque_perturbation(
        damping_torque(p),
        p.mu,
        ab_rate=lambda tau: (float(p.ab_rate(tau)[0]), float(p.ab_rate(tau)[1])),
        name="§9 damping through the engine",
    )


AveragedCoordinates = Literal["energy", "theta_max", "theta_min"]
_COORDINATES: dict[str, AveragedCoordinates] = {
    "energy": "energy",
    "theta_max": "theta_max",
    "theta_min": "theta_min",
}


def _compiled_start(p: Params, st: State) -> tuple[float, FloatArray, float] | None:
    """The paper's start H̄(0) = H(0), z̄(0) = z(0) and the middle of its well from the
    compiled well (:func:`tumble.kernels.nutation.well_averages`) instead of a Python orbit;
    None where that has no answer (a pole, a separatrix: the Python orbit then says why)."""
    if not 0.0 < st.theta < math.pi:
        return None
    a0, b0 = (float(v) for v in p.ab(0.0))
    u = math.cos(st.theta)
    H = 0.5 * st.theta_dot**2 + (st.G - st.R * u) ** 2 / (2.0 * math.sin(st.theta) ** 2)
    H += a0 * u + b0 * u * u  # (1.6)
    well = evaluate_well(st.R, st.G, a0, b0, H, u)
    if well[0] == 0.0 or not well[2] <= u <= well[1]:
        return None
    return H, np.array([st.R, st.G, a0, b0]), 0.5 * float(well[1] + well[2])


def nutation_phase(p: Params, st: State) -> float:
    """The nutation's angle variable of the state ``st`` on its own orbit: 2πt/T from the
    turning point θmax (the origin of :class:`tumble.averaging.nutation.NutationSystem`)
    [rad]."""
    orbit = orbit_of(p, st)
    if orbit.kind == "steady":
        return 0.0
    t_last = orbit.turning_time("last")
    at_max = abs(float(orbit.theta(t_last)) - orbit.theta_max) <= abs(
        float(orbit.theta(t_last)) - orbit.theta_min
    )
    return 2.0 * math.pi * (-t_last) / orbit.period + (0.0 if at_max else math.pi)


_MEAN_SLOW = ("H", "R", "G", "a", "b", "w")


def _well_columns(X: FloatArray, system: NutationSystem) -> FloatArray:
    """θmax, θmin, k², period, root case of the orbits of rows [H, R, G, a, b], shape (n, 5)."""
    table = nutation_columns(np.ascontiguousarray(X, dtype=float), system.u_hint)
    for i in np.flatnonzero(np.isnan(table[:, 0])):
        orbit = system.orbit(X[i])
        table[i, :5] = orbit.theta_max, orbit.theta_min, orbit.k2, orbit.period, orbit.root_case
    return table[:, :5]


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order 2 in mean variables (H̄, z̄) and the mean nutation
    phase w̄ (:class:`tumble.averaging.nutation.NutationSystem`), started from the mean state
    of the given one (``options.initial = "osculating"``) or from it; the envelope and z
    columns are those of the osculating orbit rebuilt at every time asked for (at an
    extremum of the full motion its θ is that orbit's turning point)."""
    perturbation = engine_perturbation(p) if options.averaging == "numeric" else None
    pert = builtin_perturbation(p) if perturbation is None else perturbation
    orbit0 = orbit_of(p, st)
    system = NutationSystem(p.mu, pert, p.eps, 0.5 * (orbit0.u1 + orbit0.u2))
    mean = MeanSystem(system.terms, 1, options.order)
    guarded = mean.guarded()
    a0, b0 = (float(v) for v in p.ab(0.0))
    x0 = np.array([orbit0.E, st.R, st.G, a0, b0])
    w0 = nutation_phase(p, st)

    def initial_state(p: Params, st: State) -> FloatArray:
        if options.initial == "mean":
            return np.array([*x0, w0])
        return mean.start(0.0, x0, [w0])

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        Y = np.atleast_2d(Y)
        X, _ = mean.osculating(t, Y)
        # The osculating orbit's turning points and the mean orbit's k², period, root case:
        # the compiled well, the Python orbit for a row it has no answer for.
        osc, avg = (_well_columns(rows, system) for rows in (X, Y[:, :5]))
        cols = {"theta_max": osc[:, 0], "theta_min": osc[:, 1], "k2": avg[:, 2],
                "period": avg[:, 3], "root_case": avg[:, 4], "E": Y[:, 0].copy()}  # fmt: skip
        for j, name in enumerate(("R", "G", "a", "b")):
            cols[name] = X[:, j + 1]
        cols |= {f"{name}_mean": Y[:, j] for j, name in enumerate(_MEAN_SLOW)}
        return cols

    knots = tuple(Breakpoint.at_time(tk / p.eps) for tk in p.pressure.knots() if tk > 0.0)
    return AveragedForm(
        name=f"mean_order{options.order}",
        equation=f"(2.1) averaged to order {options.order} in mean variables (tumble.averaging)",
        slow=tuple(f"{name}_mean" for name in _MEAN_SLOW),
        rhs=lambda t, y, p: guarded(t, y),
        initial_state=initial_state,
        to_columns=to_columns,
        breakpoints=knots,
    )


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """Volosov's equations (2.2)–(2.3) in the energy H (default) or a turning point besides z,
    their averages in closed form (§8–§9: K, E, Π) or by the general engine
    (:mod:`tumble.averaging.nutation`, ``averaging = "numeric"``), from the exact or the
    corrected start. The energy form with the closed-form averages is also compiled
    (:mod:`tumble.kernels.nutation`)."""
    if options.order == 2:
        return _mean_form(p, st, options)
    engine = engine_perturbation(p) if options.averaging == "numeric" else None
    form = _COORDINATES[options.coordinates or "energy"]
    full = full_kernel(p)
    program = damping_torque(p).program if engine is not None else None
    compiled = form == "energy" and full is not None and (engine is None or program is not None)
    start = _compiled_start(p, st) if compiled and options.start == "exact" else None
    if start is None:
        H, z, orbit = averaged_initial(p, st, engine, options.start)
        u_hint = 0.5 * (orbit.u1 + orbit.u2)
        if form == "energy":
            y0 = np.array([H, *z.tolist()])
        else:
            x0 = orbit.theta_max if form == "theta_max" else orbit.theta_min
            y0 = np.array([x0, *z.tolist()])
    else:
        H, z, u_hint = start
        y0 = np.array([H, *z.tolist()])

    failures: list[str] = []

    def rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
        try:
            return averaged_rhs(t, y, p, form=form, u_hint=u_hint, perturbation=engine)
        except IntegrationError as exc:
            # A trial stage of a too-long step may leave the domain of the averaged system
            # (no motion with that energy). NaN makes the solver reject the step and retry a
            # shorter one; if the true solution leaves the domain, the step size collapses and
            # the last message is reported (``failure``).
            failures.append(str(exc))
            return np.full(5, np.nan)

    def failure() -> str | None:
        return failures[-1] if failures else None

    def initial_state(p: Params, st: State) -> FloatArray:
        return y0

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        return _averaged_columns(Y, p, form, u_hint, compiled)

    # dQ/dτ jumps at the table's knots: stop and restart there so no step straddles one.
    knots = tuple(Breakpoint.at_time(tk / p.eps) for tk in p.pressure.knots() if tk > 0.0)

    def energy_of(y: FloatArray) -> float:
        x, R, G, a, b = (float(v) for v in y)
        return x if form == "energy" else float(effective_potential(x, R, G, a, b))

    def below_barriers(t: float, y: FloatArray) -> float:
        # > 0 while H is below every barrier of W, < 0 while above one: a sign change is a
        # separatrix crossing (§11), which one step could otherwise jump over unseen.
        if compiled:  # the same sign, without the roots of the quintic
            return float(evaluate_separatrix_distance(np.asarray(y, dtype=float)))
        barriers = barrier_energies(*(float(v) for v in y[1:]))
        return float(np.min(barriers) - energy_of(y)) if barriers.size else 1.0

    def refuse(t: float, y: FloatArray) -> FloatArray:
        raise IntegrationError(
            f"averaged equations (2.2): the motion reaches a separatrix at t = {t:.6g} (the "
            "energy crosses the barrier between two wells of W); averaging is not valid across "
            "it (§11): run the full model there"
        )

    def kernel(p: Params) -> Kernel | None:
        if full is None:
            return None
        if engine is None:  # the closed-form averages: the full kernel's, and the well's hint
            params = np.append(full.params, u_hint)
            return replace(full, kind=KIND_NUTATION_AVERAGED, params=params, event=EVENT_NONE)
        # the general engine on the damping as a torque program (a moment of the body rate)
        assert program is not None
        params = np.concatenate([full.params, [u_hint, AVERAGE_RTOL], program])
        return replace(full, kind=KIND_NUTATION_ENGINE, params=params, event=EVENT_NONE)

    separatrix = Breakpoint(
        below_barriers, refuse, event=EVENT_NUTATION_SEPARATRIX if compiled else EVENT_NONE
    )
    return AveragedForm(
        name=form,
        equation="(2.2)-(2.3)" + (", energy form of §7" if form == "energy" else ""),
        slow=("H" if form == "energy" else form, "R", "G", "a", "b"),
        rhs=rhs,
        initial_state=initial_state,
        to_columns=to_columns,
        breakpoints=(*knots, separatrix),
        failure=failure,
        kernel=kernel if compiled else None,
    )


def _slow_orbit(y: Sequence[float], p: Params, form: str, u_hint: float) -> NutationOrbit:
    x, R, G, a, b = (float(v) for v in y)
    if form == "energy":
        return NutationOrbit.from_energy(p.mu, a, b, R, G, x, u_hint=u_hint)
    return NutationOrbit.from_turning_point(p.mu, a, b, R, G, x)


def _averaged_columns(
    Y: FloatArray, p: Params, form: str, u_hint: float, compiled: bool = False
) -> dict[str, FloatArray]:
    n = Y.shape[0]
    names = ("theta_max", "theta_min", "k2", "period", "root_case", "E")
    if compiled:  # the compiled well; a row it has no answer for from the Python orbit
        table = nutation_columns(np.ascontiguousarray(Y, dtype=float), u_hint)
        out = {k: table[:, j].copy() for j, k in enumerate(names)}
        rows = np.flatnonzero(np.isnan(table[:, 0])).tolist()
    else:
        out = {k: np.empty(n) for k in names}
        rows = list(range(n))
    for i in rows:
        orbit = _slow_orbit(Y[i], p, form, u_hint)
        out["theta_max"][i], out["theta_min"][i] = orbit.theta_max, orbit.theta_min
        out["k2"][i], out["period"][i] = orbit.k2, orbit.period
        out["root_case"][i], out["E"][i] = orbit.root_case, orbit.E
    if form == "theta_max":  # the integrated variable itself, not its round trip
        out["theta_max"] = Y[:, 0].copy()
    elif form == "theta_min":
        out["theta_min"] = Y[:, 0].copy()
    for i, name in enumerate(("R", "G", "a", "b")):
        out[name] = Y[:, i + 1].copy()
    return out


# ---------------------------------------------------------------------------------------------
# Closed form (unperturbed), extrema of the full solution, envelope discrepancy.


def closed_form(p: Params, st: State, t: FloatArray) -> dict[str, FloatArray]:
    """The exact unperturbed motion (1.9)–(1.13) at times ``t``.

    Parameters
    ----------
    p : Params
        Unperturbed (ε = 0).
    st : State
    t : ndarray
        Times [t].

    Returns
    -------
    dict
        ``theta``, ``psi``, ``phi`` [rad] (ψ, φ continuous), ``theta_dot`` [rad/t].
    """
    orbit = orbit_of(p, st)
    return {
        "theta": orbit.theta(t),
        "psi": orbit.psi(t),
        "phi": orbit.phi(t),
        "theta_dot": orbit.theta_dot(t),
    }


def extrema(traj: Sampled, p: Params) -> list[tuple[str, int, float, float, float, float]]:
    """Every local maximum and minimum of θ(t) of a full trajectory for 0 < t < t_end.

    A start at a turning point is not counted (§14). A compiled run located the zeros of
    θ' as it integrated (:data:`tumble.kernels.EVENT_THETA_DOT`); otherwise they are
    bracketed on the integrator's steps (subdivided four times, so no swing is missed) and
    refined on the dense output.

    Parameters
    ----------
    traj : Trajectory
        A ``full`` trajectory (``slow`` gives ``theta_dot``, ``theta``, ``R``, ``G``).
    p : Params

    Returns
    -------
    list of (kind, k, t, theta, R, G)
        ``kind`` "max" or "min", ``k`` counting from 1 within its kind.
    """
    t_end = float(traj.tau[-1])
    cols = traj.event_columns
    counts = {"max": 0, "min": 0}
    out = []
    for j in np.flatnonzero((traj.events > 0.0) & (traj.events < t_end)):
        kind = "max" if traj.event_signs[j] > 0.0 else "min"
        counts[kind] += 1
        out.append((kind, counts[kind], float(traj.events[j]), float(cols["theta"][j]),
                    float(cols["R"][j]), float(cols["G"][j])))  # fmt: skip
    return out


def envelope_discrepancy(
    rows: Sequence[tuple[str, int, float, float, float, float]], averaged: Any
) -> dict[str, Any]:
    """Discrepancy of the averaged envelope θmax(t), θmin(t) at the full solution's extrema.

    Parameters
    ----------
    rows : sequence
        Output of :func:`extrema`.
    averaged : Trajectory
        An ``averaged`` trajectory (``slow`` gives ``theta_max``, ``theta_min``).

    Returns
    -------
    dict
        ``max_relative`` max over maxima of |θ̄max(t_k) − θ_k|/θ_k [1], ``max_abs_theta_max``
        and ``max_abs_theta_min`` [rad], and the counts.
    """
    out: dict[str, Any] = {"n_max": 0, "n_min": 0}
    for kind in ("max", "min"):
        sel = [(r[2], r[3]) for r in rows if r[0] == kind]
        out[f"n_{kind}"] = len(sel)
        if not sel:
            out[f"max_abs_theta_{kind}"] = None
            continue
        t_k, th = (np.array(v) for v in zip(*sel, strict=True))
        env = averaged.slow(t_k)[f"theta_{kind}"]
        out[f"max_abs_theta_{kind}"] = float(np.max(np.abs(env - th)))
        if kind == "max":
            out["max_relative"] = float(np.max(np.abs(env - th) / th))
    out.setdefault("max_relative", None)
    return out


def validity(p: Params, st: State, slow: SlowPath, t_end: float) -> list[ValidityIssue]:
    """Where an averaged trajectory loses accuracy (§10, §11), with the first time.

    ``near_separatrix``: 1 − k² < ``NEAR_SEPARATRIX`` (the period grows like ln(1/(1 − k²))
    and averaging degrades before it fails at ``SEPARATRIX_TOL``). ``eps_not_small``: the slow
    time per nutation period ε·T exceeds ``EPS_PERIOD_LIMIT``. Both are the tool's judgement of
    the "≪" of §6–§7.

    Parameters
    ----------
    p : Params
    st : State
    slow : callable
        ``slow(t) -> columns`` of the averaged run (``k2``, ``period``).
    t_end : float
        End of the run [t].

    Returns
    -------
    list of ValidityIssue
    """
    if not p.perturbed:
        return []
    grid = np.linspace(0.0, t_end, 801)
    on_grid = slow(grid)  # one orbit per grid point, shared by both checks

    def cols(t: FloatArray) -> dict[str, FloatArray]:
        return on_grid if t is grid else slow(t)

    issues = []
    checks = (
        (
            "near_separatrix",
            lambda t: NEAR_SEPARATRIX - (1.0 - cols(t)["k2"]),
            f"the nutation nears a separatrix (1 − k² < {NEAR_SEPARATRIX:g}): the period "
            "grows without bound and averaging loses accuracy (§11)",
        ),
        (
            "eps_not_small",
            lambda t: p.eps * cols(t)["period"] - EPS_PERIOD_LIMIT,
            f"ε·T > {EPS_PERIOD_LIMIT:g}: the slow variables change noticeably within one "
            "nutation period, so averaging is not accurate (envelope error O(ε·T), §10)",
        ),
    )
    for name, cond, message in checks:
        t0 = first_time(cond, grid)
        if t0 is not None:
            issues.append(ValidityIssue(name, t0, f"{message}; first at t = {t0:.6g}"))
    return issues


def limits(p: Params, st: State) -> dict[str, Json]:
    """The unperturbed orbit's constants (§14): root case, roots, k², E, θmin, θmax, T,
    mean precession and spin rates. For a perturbed run they describe the initial orbit.

    Parameters
    ----------
    p : Params
    st : State

    Returns
    -------
    dict
    """
    orbit = orbit_of(p, st)

    def root(z: complex) -> Json:
        if not math.isfinite(z.real):
            return None  # b = 0: the root at infinity
        return z.real if z.imag == 0.0 else [z.real, z.imag]

    return {
        "root_case": int(orbit.root_case),
        "roots": {f"u{i + 1}": root(complex(z)) for i, z in enumerate(orbit.roots)},
        "k2": orbit.k2,
        "E": orbit.E,
        "theta_min": orbit.theta_min,
        "theta_max": orbit.theta_max,
        "period": orbit.period,
        "mean_psidot": orbit.mean_psidot,
        "mean_phidot": orbit.mean_phidot,
        "kind": orbit.kind,
    }


def report(p: Params, st: State, trajectories: Mapping[str, Sampled]) -> Report:
    """Extrema table, envelope discrepancy and wall times (the scenario contract).

    Parameters
    ----------
    p : Params
    st : State
    trajectories : mapping
        Method → Trajectory.

    Returns
    -------
    Report
        Unperturbed: the orbit constants of :func:`limits` at the top of summary.json.
        Perturbed: ``full_extrema`` table, ``max_envelope_discrepancy`` (relative, θmax) with
        its details, and ``wall_time_s`` of each method.
    """
    summary: dict[str, Json] = {
        "wall_time_s": {m: float(t.wall_time) for m, t in trajectories.items()}
    }
    tables: dict[str, tuple[tuple[str, ...], list[tuple[Json, ...]]]] = {}
    if not p.perturbed:
        summary.update(limits(p, st))
        return Report(tables, summary)
    if "full" in trajectories:
        rows = extrema(trajectories["full"], p)
        tables["full_extrema"] = (("kind", "k", "t", "theta", "R", "G"), list(rows))
        if "averaged" in trajectories:
            env = envelope_discrepancy(rows, trajectories["averaged"])
            summary["max_envelope_discrepancy"] = env["max_relative"]
            summary["envelope"] = env
    summary["initial_orbit"] = limits(p, st)
    return Report(tables, summary)


def slow_errors(
    p: Params, full: Sampled, averaged: Sampled
) -> dict[str, tuple[FloatArray, FloatArray]]:
    """Averaging error of each slow variable, for ``tumble verify``.

    θmax and θmin: |θ̄ext(t_k) − θ_k| at the full solution's maxima and minima (the envelope
    (2.2) is what the averaged method predicts, §10); R and G: |full − averaged| at the
    sample times.

    Parameters
    ----------
    p : Params
    full, averaged : Trajectory
        Runs of the two methods on the same sample times.

    Returns
    -------
    dict
        Variable → (times [t], absolute errors [rad or 1/t]).
    """
    rows = extrema(full, p)
    out: dict[str, tuple[FloatArray, FloatArray]] = {}
    for kind in ("max", "min"):
        sel = [(r[2], r[3]) for r in rows if r[0] == kind]
        if sel:
            t_k, th = (np.array(v, dtype=float) for v in zip(*sel, strict=True))
            out[f"theta_{kind}"] = (t_k, np.abs(averaged.slow(t_k)[f"theta_{kind}"] - th))
    for name in ("R", "G"):
        out[name] = (full.tau, np.abs(full.columns[name] - averaged.columns[name]))
    return out


def _diagnostics(p: Params, st: State, cols: dict[str, FloatArray]) -> dict[str, FloatArray]:
    return {k: cols[k] for k in ("k2", "period", "root_case", "E")}


_THETA = Column("theta", "nutation angle θ", "rad", "(1.9)")
_PSI = Column("psi", "precession angle ψ", "rad", "(1.13)", angle=True, unwrap=True)
_PHI = Column("phi", "proper rotation angle φ", "rad", "(1.13)", angle=True, unwrap=True)
_THETA_DOT = Column("theta_dot", "nutation rate θ'", "rad/t", "(1.2)")
_R = Column("R", "reduced axial momentum R = Cr/A", "1/t", "docs/theory/nonlinear-moment.md §1")
_G = Column(
    "G", "reduced momentum about e_z, G = K·e_z/A", "1/t", "docs/theory/nonlinear-moment.md §1"
)
_A = Column(
    "a", "sinθ coefficient a(τ) of M0/A", "1/t^2", "(1.5), docs/theory/nonlinear-moment.md §9"
)
_B = Column(
    "b", "sin2θ coefficient b(τ) of M0/A", "1/t^2", "(1.5), docs/theory/nonlinear-moment.md §9"
)
_UNPERTURBED = (_THETA, _PSI, _PHI, _THETA_DOT)
_PERTURBED_FULL = (_THETA, _PSI, _PHI, _R, _G, _A, _B)
_AVERAGED = (
    Column("theta_max", "envelope θmax (averaged)", "rad", "(2.2)"),
    Column("theta_min", "envelope θmin (averaged)", "rad", "(2.2)"),
    _R,
    _G,
    _A,
    _B,
)
_AVERAGED_MEAN = (
    Column("H_mean", "mean energy H̄ (averaging of order 2)", "1/t^2", "(1.6)"),
    *(Column(f"{c.name}_mean", f"mean {c.long_name} (averaging of order 2)", c.units,
             c.equation) for c in (_R, _G, _A, _B)),
    Column("w_mean", "mean nutation phase w̄ from θmax (averaging of order 2)", "rad",
           "docs/theory/nonlinear-moment.md §4"),
)  # fmt: skip
_DIAGNOSTICS = (
    Column("k2", "modulus squared k² of the nutation", "1", "docs/theory/nonlinear-moment.md §4"),
    Column("period", "nutation period T", "t", "docs/theory/nonlinear-moment.md §4"),
    Column(
        "root_case",
        "root case (1: four real roots, 2: a complex pair)",
        "1",
        "docs/theory/nonlinear-moment.md §3",
    ),
    Column(
        "E",
        "energy H of (1.6) along the averaged solution",
        "1/t^2",
        "(1.6), docs/theory/nonlinear-moment.md §7",
    ),
)


def _full_columns(p: Params) -> tuple[Column, ...]:
    # A perturbed run also writes the moment coefficients; every full run its attitude.
    return (*(_PERTURBED_FULL if p.perturbed else _UNPERTURBED), *attitude_columns("t"))


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


def exact_motion(p: Params, st: State) -> Callable[[FloatArray], FloatArray]:
    """The motion at ε = 0 through ``st`` (a, b frozen at their initial values, no damping),
    (1.9)–(1.13), as states ``[p, q, r, q0, q1, q2, q3]`` of the quaternion form."""
    orbit = orbit_of(p, st)

    def states(t: FloatArray) -> FloatArray:
        tt = np.ravel(np.asarray(t, dtype=float))
        angles = zip(
            orbit.theta(tt), orbit.theta_dot(tt), orbit.psi(tt), orbit.phi(tt), strict=True
        )
        rows = [full_from_slow(p, State(th, thd, ps, ph, st.R, st.G)) for th, thd, ps, ph in angles]
        return np.array(rows).reshape(tt.size, 7)

    return states


FULL_QUATERNION: FullForm[Params, State] = FullForm(
    name="quaternion",
    equation="(1.1) with quaternion kinematics",
    state=("w1", "w2", "w3", "q0", "q1", "q2", "q3"),
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

_ENTRY = CATALOGUE["nonlinear_moment"]  # name, description and paper

MODEL: Model[Params, State] = Model(
    name=_ENTRY.name,
    description=_ENTRY.description,
    paper=_ENTRY.paper,
    time=DECLARED.time,
    full=Full(
        forms={"quaternion": FULL_QUATERNION, "reduced": FULL_REDUCED},
        default="quaternion",
        columns=_full_columns,
    ),
    check=DECLARED.check,
    methods=DECLARED.methods,
    averaged=Averaged(
        form=_averaged_form,
        columns=fixed_columns((*_AVERAGED, *_AVERAGED_MEAN)),
        coordinates=DECLARED.coordinates,
        corrected_start=DECLARED.corrected_start,
        numeric=DECLARED.numeric,
        orders=DECLARED.orders,
        errors=slow_errors,
        diagnostics=Diagnostics(_diagnostics, _DIAGNOSTICS),
    ),
    closed_form=ClosedForm(evaluate=closed_form, columns=fixed_columns(_UNPERTURBED)),
    unperturbed=Unperturbed(
        "(1.9)-(1.13)", exact_motion, lambda t, y, p: full_rhs(t, y, p.unperturbed())
    ),
    validity=Validity(check=validity, limits=limits),
    report=report,
    scenario=DECLARED.scenario,
)
