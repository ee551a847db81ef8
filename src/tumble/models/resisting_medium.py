"""Fast-spinning symmetric gyroscope under a constant body-fixed moment in a resisting medium.

A. V. Medvedev, *Motion of a fast-spinning gyroscope under a constant moment in a resisting
medium* (1987). Equation numbers are the paper's; section numbers (§) are those of
``docs/theory/resisting-medium.md``, which states where tumble departs from the printed paper
and why (corrections E1–E10).

Everything here is in the paper's normalized variables (1.3): time τ, angular momentum
``k = |K|/K0``, inertia ``I1 = 1``, ``I3 = 1 + κ``, moment ``ε m`` with
``m = a − b w − s (w ∘ |w|)``, body angular velocity ``w = (p, q, r)``. Angles follow §2:
ρ, σ locate K in the inertial frame; ψ, ϑ, φ are the 3-1-3 Euler angles of the body in the
K-frame. The averaged system and its closed forms are written in the slow time ``s = ε τ``
internally and take τ at the interface.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.quadrature import AVERAGE_RTOL
from tumble.averaging.second_order import RESONANCE_WIDTHS, MeanSystem, nearest_resonance
from tumble.averaging.spinner import (
    SPINNER_GRID,
    body_momentum,
    spinner_average,
    spinner_system,
    standard_form,
)
from tumble.catalogue import CATALOGUE
from tumble.errors import (
    IntegrationError,
    ParameterError,
)
from tumble.kernels import EVENT_EQUATOR, KIND_MEDIUM_AVERAGED, KIND_SPINNER_AVERAGED, Kernel
from tumble.kernels.rhs import rigid_body
from tumble.models.base import (
    Averaged,
    AveragedForm,
    AveragingOptions,
    Breakpoint,
    ClosedForm,
    Column,
    Crossing,
    Full,
    FullForm,
    Model,
    SlowPath,
    Unperturbed,
    Validity,
    ValidityIssue,
    attitude_columns,
    attitude_values,
    first_time,
    fixed_columns,
)
from tumble.models.inputs.resisting_medium import (
    DECLARED,
    Params,
    PhysicalParams,
    Scaling,
    State,
    normalize_physical,
)
from tumble.rotations import (
    attitude_from_kframe_angles,
    kframe_angles_from_attitude,
    matrix_to_quat,
    quat_to_matrix,
)
from tumble.unperturbed.euler_poinsot import EulerPoinsot

__all__ = [
    "MODEL",
    "VALIDITY_RATIO",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "averaged_rhs",
    "averaged_rhs_numeric",
    "averaged_rhs_wv",
    "axial_lower_double_root",
    "axial_lower_exp",
    "axial_lower_tan",
    "axial_momentum",
    "axial_upper_double_root",
    "axial_upper_exp",
    "axial_upper_tan",
    "closed_form",
    "crossing_time",
    "equatorial_momentum",
    "full_from_slow",
    "full_rhs",
    "invariants",
    "moment_depends_on_phi",
    "normalize_physical",
    "osculating_from_slow",
    "osculating_rhs",
    "predicted_limits",
    "slow_from_full",
    "tan_theta_a3_zero_lower",
    "tan_theta_a3_zero_upper",
    "tan_theta_quadratic",
    "validity",
]

VALIDITY_RATIO = 0.1
"""Averaging is trusted while the slow rates stay below this fraction of the fast rates
(§6: ``ε(|a|/k² + |b|/k + |s|) ≪ |κ cos ϑ|/(1+κ)``); beyond it a run is warned."""


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


# ---------------------------------------------------------------------------------------------
# Averaged system (2.2) and its W, V form (2.3).


def averaged_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Averaged equations (2.2) for (k, ϑ); ρ and σ are constant.

    The a3 term of the ϑ-equation is evaluated as a3 sin ϑ / k, regular at ϑ = π/2 (§6).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (2,)
        ``[k, ϑ]`` [1, rad].
    p : Params
        Model parameters.
    """
    k, theta = y
    c, s = math.cos(theta), math.sin(theta)
    ac, as_ = abs(c), abs(s)
    a3 = float(p.a[2])
    al, be, ga, de = p.alpha, p.beta, p.gamma, p.delta
    dk = a3 * c - k * (al * s * s + be * c * c + k * (ga * s * s * as_ + de * c * c * ac))
    dtheta = -(a3 * s / k + (al - be + k * (ga * as_ - de * ac)) * s * c)
    return p.eps * np.array([dk, dtheta])


def averaged_rhs_wv(t: float, y: FloatArray, p: Params) -> FloatArray:
    """W, V form (2.3): dW/dτ = ε(a3 − βW − δW|W|), dV/dτ = −ε(αV + γV²).

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (2,)
        ``[W, V]`` = ``[k cos ϑ, k sin ϑ]`` [1].
    p : Params
        Model parameters.
    """
    W, V = y
    return p.eps * np.array(
        [float(p.a[2]) - p.beta * W - p.delta * W * abs(W), -(p.alpha * V + p.gamma * V * V)]
    )


def _averaged_columns_ktheta(
    p: Params, st: State, t: FloatArray, Y: FloatArray
) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    n = Y.shape[0]
    return {
        "k": Y[:, 0],
        "theta": Y[:, 1],
        "rho": np.full(n, st.rho),
        "sigma": np.full(n, st.sigma),
    }


def _averaged_columns_wv(
    p: Params, st: State, t: FloatArray, Y: FloatArray
) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    n = Y.shape[0]
    return {
        "k": np.hypot(Y[:, 0], Y[:, 1]),
        "theta": np.arctan2(Y[:, 1], Y[:, 0]),
        "rho": np.full(n, st.rho),
        "sigma": np.full(n, st.sigma),
    }


def _averaged_kernel(form: int) -> Callable[[Params], Kernel]:
    """The compiled (2.2) (``form`` 0) or (2.3) (1): the same code as :func:`averaged_rhs`
    and :func:`averaged_rhs_wv`."""

    def kernel(p: Params) -> Kernel:
        a3 = float(p.a[2])
        packed = [p.eps, a3, p.alpha, p.beta, p.gamma, p.delta, float(form)]
        return Kernel(KIND_MEDIUM_AVERAGED, np.array(packed))

    return kernel


_AVERAGED_KTHETA: AveragedForm[Params, State] = AveragedForm(
    name="k_theta",
    equation="(2.2)",
    slow=("k", "theta"),
    rhs=averaged_rhs,
    initial_state=lambda p, st: np.array([st.k, st.theta]),
    to_columns=_averaged_columns_ktheta,
    kernel=_averaged_kernel(0),
)
_AVERAGED_WV: AveragedForm[Params, State] = AveragedForm(
    name="W_V",
    equation="(2.3)",
    slow=("W", "V"),
    rhs=averaged_rhs_wv,
    initial_state=lambda p, st: np.array([st.W, st.V]),
    to_columns=_averaged_columns_wv,
    kernel=_averaged_kernel(1),
)


def _equator(p: Params, st: State) -> tuple[Breakpoint, ...]:
    """(2.2) and (2.3) hold |cos ϑ| and W|W|: not smooth at the equator, which W crosses at
    most once, at the time the closed form of W gives (§8.4): the run is split there."""
    tau1 = crossing_time(st.W, p)
    return () if math.isinf(tau1) else (Breakpoint.at_time(tau1),)


def averaged_rhs_numeric(t: float, y: FloatArray, p: Params) -> FloatArray:
    """The averaged equations from the general engine: the moment (1.2) averaged over ψ and φ
    of the standard form (1.3) by quadrature; equal to (2.2) to round-off.

    Parameters
    ----------
    t : float
        Time τ [1].
    y : ndarray, shape (4,)
        ``[k, ρ, σ, ϑ]`` [1, rad, rad, rad].
    p : Params
    """
    k, rho, sigma, theta = (float(v) for v in y)
    return spinner_average(p.torque, p.kappa, 1.0, k, rho, sigma, theta, t=t)


def _averaged_columns_numeric(
    p: Params, st: State, t: FloatArray, Y: FloatArray
) -> dict[str, FloatArray]:
    Y = np.atleast_2d(Y)
    return {"k": Y[:, 0], "rho": Y[:, 1], "sigma": Y[:, 2], "theta": Y[:, 3]}


def spinner_kernel(p: Params) -> Kernel | None:
    """:func:`averaged_rhs_numeric` compiled (:mod:`tumble.kernels.spinner`) when the moment
    depends on the body rate alone (the law (1.2) and its built-in parts); None otherwise
    (an attitude-dependent or a Python torque: the Python engine)."""
    program = p.torque.program
    if program is None or not p.torque.rate_only or p.kappa == 0.0:
        return None
    return Kernel(KIND_SPINNER_AVERAGED, np.concatenate([[p.kappa, AVERAGE_RTOL], program]))


_AVERAGED_NUMERIC: AveragedForm[Params, State] = AveragedForm(
    name="numeric",
    equation="(1.3) averaged over ψ, φ by quadrature (tumble.averaging)",
    slow=("k", "rho", "sigma", "theta"),
    rhs=averaged_rhs_numeric,
    initial_state=lambda p, st: np.array([st.k, st.rho, st.sigma, st.theta]),
    to_columns=_averaged_columns_numeric,
    # the equator, as above; a moment of the body rate only runs compiled
    breakpoints=(Breakpoint(lambda t, y: math.cos(y[3]), event=EVENT_EQUATOR),),
    kernel=spinner_kernel,
)


_SLOW = ("k", "rho", "sigma", "theta")
_PHASES = ("psi", "phi")


def mean_system(p: Params, order: int, refuse: bool = True) -> MeanSystem:
    """The averaged equations of ``order`` in mean variables (k, ρ, σ, ϑ) and mean phases
    (ψ, φ), with the mean ↔ osculating map (:mod:`tumble.averaging.second_order` on the
    standard form (1.3)); F₁ by :func:`tumble.averaging.spinner_average`."""

    def first(t: float, y: FloatArray) -> FloatArray:
        k, rho, sigma, theta = (float(v) for v in y)
        return spinner_average(p.torque, p.kappa, 1.0, k, rho, sigma, theta, t=t)

    rates, frequencies = spinner_system(p.torque, p.kappa)
    return MeanSystem.of_rates(rates, frequencies, SPINNER_GRID, order, first, refuse=refuse)


def _mean_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """The averaged equations of order ``options.order`` in mean variables, started from the
    mean state of the given one (``options.initial = "osculating"``) or from it, with the
    osculating variables rebuilt at the samples (:func:`mean_system`)."""
    system = mean_system(p, options.order, refuse=not options.hybrid)
    guarded = system.guarded()

    def initial_state(p: Params, st: State) -> FloatArray:
        x = np.array([st.k, st.rho, st.sigma, st.theta])
        phases = np.array([st.psi, st.phi])
        if options.initial == "mean":
            return np.concatenate([x, phases])
        return system.start(0.0, x, phases)

    def mean_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        Y = np.atleast_2d(Y)
        cols = {name: Y[:, i] for i, name in enumerate(_SLOW)}
        cols |= {f"{name}_mean": Y[:, i] for i, name in enumerate(_SLOW + _PHASES)}
        return cols

    def osculating(p: Params, st: State, t: FloatArray, Y: FloatArray) -> dict[str, FloatArray]:
        X, _ = system.osculating(t, Y)
        return {name: X[:, i] for i, name in enumerate(_SLOW)}

    return AveragedForm(
        crossing=_resonance_band(p, st, system) if options.hybrid else None,
        name=f"mean_order{options.order}",
        equation=f"(1.3) averaged to order {options.order} in mean variables (tumble.averaging)",
        slow=(*(f"{v}_mean" for v in _SLOW), *(f"{v}_mean" for v in _PHASES)),
        rhs=lambda t, y, p: guarded(t, y),
        initial_state=initial_state,
        to_columns=mean_columns,
        breakpoints=(Breakpoint(lambda t, y: math.cos(y[3])),),
        osculating=osculating,
    )


def _resonance_band(p: Params, st: State, system: MeanSystem) -> Crossing:
    """The bands where the mean state is within RESONANCE_WIDTHS widths of a resonance of
    the phases (:func:`tumble.averaging.second_order.resonance_distance`): about ϑ = π/2,
    where φ stops (the harmonic (0, 1)), and about the commensurabilities ψ̇ = j|φ̇| the
    moment's harmonics (±1, j) meet as ϑ drifts. A hybrid run crosses them on the full
    equations (Euler + quaternions)."""
    mapping = system.map()

    last: list[Any] = [None, {}]  # the last state's table: band and signed ask for it in turn

    def signed(x: FloatArray) -> dict[tuple[int, ...], float]:
        key = np.asarray(x[:4], dtype=float).tobytes()
        if last[0] != key:
            last[:] = [key, system.resonances(0.0, x[:4])]
        return dict(last[1])

    def distance(x: FloatArray) -> float:
        return nearest_resonance(signed(x))[0]

    def band(z: FloatArray) -> float:
        return distance(z) / RESONANCE_WIDTHS - 1.0

    def osculating(y: FloatArray) -> tuple[FloatArray, FloatArray]:
        cols = slow_from_full(p, np.zeros(1), np.asarray(y)[None, :])
        x = np.array([float(cols[name][0]) for name in _SLOW])
        return x, np.array([float(cols["psi"][0]), float(cols["phi"][0])])

    def band_full(y: FloatArray) -> float:
        return distance(osculating(y)[0]) / RESONANCE_WIDTHS - 1.0

    def to_full(t: float, z: FloatArray) -> FloatArray:
        x, phases = mapping.to_osculating(t, z[:4], z[4:])
        k, rho, sigma, theta = (float(v) for v in x)
        return full_from_slow(p, State(k, rho, sigma, float(phases[0]), theta, float(phases[1])))

    def to_mean(t: float, y: FloatArray, z_entry: FloatArray) -> FloatArray:
        x, phases = osculating(y)
        # σ on the branch of the mean σ at entry (the azimuth is continuous)
        x[2] += 2.0 * math.pi * round((float(z_entry[2]) - x[2]) / (2.0 * math.pi))
        y_mean, psi = mapping.to_mean(t, x, phases)
        return np.concatenate([y_mean, psi])

    chunk = 20.0 * 2.0 * math.pi / max(st.k, 1e-3)  # 20 turns of ψ at the initial spin
    return Crossing(band, band_full, to_full, to_mean, "a resonance of ψ and φ", chunk, signed)


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """(2.2), its W, V form (2.3), the general engine (``averaging = "numeric"``,
    :func:`tumble.averaging.spinner_average`: the moment (1.2) averaged over ψ and φ), or the
    equations of order 2 in mean variables (:func:`_mean_form`)."""
    if options.order == 2 or options.hybrid:
        return _mean_form(p, st, options)
    if options.averaging == "numeric":
        return _AVERAGED_NUMERIC
    # (2.2) is written in polar coordinates (k, ϑ): at V0 = 0 (ϑ0 = 0 or π) the solution may
    # pass through k = 0, the polar singularity; (2.3) is the same system and regular there.
    form = _AVERAGED_WV if abs(math.sin(st.theta)) < 1e-12 else _AVERAGED_KTHETA
    return replace(form, breakpoints=_equator(p, st))


# ---------------------------------------------------------------------------------------------
# Closed forms, §8. Internally in slow time s = ε τ.
#
# Both components obey scalar Riccati equations. In a window where W keeps its sign, with
# d = δ (W ≥ 0) or d = −δ (W < 0):  dW/ds = a3 − βW − dW².  V obeys dV/ds = −αV − γV².
# Real roots: with r the root that stays bounded as d → 0 and λ = β + 2dr, u = W − r solves the
# Bernoulli equation du/ds = −λu − du² (this is (2.4) for V, and (2.5)/(2.7) rewritten so that
# neither d → 0 nor a double root loses digits). Complex roots: the tangent law (2.6)/(2.8), in
# the division-free form of §8.5.


def _bernoulli(u0: float, lam: float, d: float, s: FloatArray) -> FloatArray:
    """Solution of du/ds = −λu − du², u(0) = u0 (no blow-up inside ``s`` assumed)."""
    if lam >= 0.0:
        growth = s if lam == 0.0 else -np.expm1(-lam * s) / lam  # (1 − e^{−λs})/λ
        return u0 * np.exp(-lam * s) / (1.0 + d * u0 * growth)
    # λ < 0: divide through by e^{−λs}, which grows, to avoid overflow.
    return u0 / (np.exp(lam * s) + d * u0 * np.expm1(lam * s) / lam)


def _bernoulli_blowup(u0: float, lam: float, d: float) -> float:
    """Slow time at which the Bernoulli solution diverges, or inf."""
    c = d * u0
    if c >= 0.0:
        return math.inf
    e_star = -1.0 / c  # the denominator 1 + c (1 − e^{−λs})/λ vanishes there
    if lam == 0.0:
        return e_star
    if lam > 0.0 and lam * e_star >= 1.0:
        return math.inf
    return -math.log1p(-lam * e_star) / lam


@dataclass(frozen=True)
class _Riccati:
    """dW/ds = a3 − βW − dW² from W(0) = W0 (one sign window of (2.3))."""

    W0: float
    a3: float
    beta: float
    d: float

    @property
    def _disc(self) -> float:
        return self.beta * self.beta + 4.0 * self.d * self.a3

    def _root_rate(self) -> tuple[float, float]:
        lam = math.sqrt(self._disc)
        lam = lam if self.beta >= 0.0 else -lam
        r = 0.0 if self.beta + lam == 0.0 else 2.0 * self.a3 / (self.beta + lam)
        return r, lam

    def __call__(self, s: FloatArray) -> FloatArray:
        s = np.asarray(s, dtype=float)
        a3, beta, d, W0 = self.a3, self.beta, self.d, self.W0
        if d == 0.0:
            if beta == 0.0:
                return W0 + a3 * s
            return W0 * np.exp(-beta * s) - a3 * np.expm1(-beta * s) / beta
        if self._disc >= 0.0:
            r, lam = self._root_rate()
            return r + _bernoulli(W0 - r, lam, d, s)
        # Complex roots: y = W + h obeys dy/dx = −(y² + μ²), x = d s (§8.5, tan branch).
        h = beta / (2.0 * d)
        mu = math.sqrt(-self._disc) / (2.0 * abs(d))
        x = d * s
        y0 = W0 + h
        c = np.cos(mu * x)
        sin_over_mu = x * np.sinc(mu * x / math.pi)
        return (y0 * c - mu * mu * sin_over_mu) / (c + y0 * sin_over_mu) - h

    def blowup(self) -> float:
        """Slow time at which W diverges (inf if never)."""
        if self.d == 0.0:
            return math.inf
        if self._disc >= 0.0:
            r, lam = self._root_rate()
            return _bernoulli_blowup(self.W0 - r, lam, self.d)
        h = self.beta / (2.0 * self.d)
        mu = math.sqrt(-self._disc) / (2.0 * abs(self.d))
        theta0 = math.atan((self.W0 + h) / mu)
        # y = μ tan(θ0 − μx) has its pole at θ0 − μx = ∓π/2, reached for x of the sign of d.
        x_pole = (theta0 + math.pi / 2) / mu if self.d > 0 else (theta0 - math.pi / 2) / mu
        return x_pole / self.d

    def zero_crossing(self) -> float:
        """Slow time at which W reaches 0 (inf if it does not), §8.4."""
        a3, beta, d, W0 = self.a3, self.beta, self.d, self.W0
        if W0 == 0.0 or a3 == 0.0 or (a3 > 0) == (W0 > 0):
            return math.inf  # W = 0 is crossed only in the direction of a3
        if d == 0.0:
            if beta == 0.0:
                s1 = -W0 / a3
            else:
                arg = -beta * W0 / a3
                s1 = math.log1p(arg) / beta if arg > -1.0 else math.inf
        elif self._disc >= 0.0:
            r, lam = self._root_rate()
            u0 = W0 - r
            if u0 == 0.0:
                return math.inf
            e_star = W0 / (u0 * 0.5 * (lam + beta))  # u(s1) = −r
            if e_star <= 0.0 or (lam > 0.0 and lam * e_star >= 1.0):
                return math.inf
            s1 = e_star if lam == 0.0 else -math.log1p(-lam * e_star) / lam
        else:
            h = beta / (2.0 * d)
            mu = math.sqrt(-self._disc) / (2.0 * abs(d))
            y0 = W0 + h
            # (arctan(y0/μ) − arctan(h/μ))/μ without losing the branch (§8.4 table);
            # y0 − h is W0 itself, kept exact for a start near ϑ = π/2.
            s1 = math.atan2(mu * W0, mu * mu + y0 * h) / mu / d
        return s1 if (s1 >= 0.0 and s1 < self.blowup()) else math.inf


@dataclass(frozen=True)
class _AxialSolution:
    """W(s) over both sign windows, switching branch at the crossing (§8.4)."""

    first: _Riccati | None  # None: W ≡ 0
    s_cross: float
    second: _Riccati | None
    s_blowup: float

    def __call__(self, s: FloatArray) -> FloatArray:
        s = np.asarray(s, dtype=float)
        if self.first is None:
            return np.zeros_like(s)
        out = np.empty_like(s)
        before = s <= self.s_cross
        out[before] = self.first(s[before])
        if self.second is not None and np.any(~before):
            out[~before] = self.second(s[~before] - self.s_cross)
        return out


def _axial_solution(W0: float, a3: float, beta: float, delta: float) -> _AxialSolution:
    if W0 == 0.0 and a3 == 0.0:
        return _AxialSolution(None, math.inf, None, math.inf)
    side = math.copysign(1.0, W0) if W0 != 0.0 else math.copysign(1.0, a3)
    # Lower hemisphere: −δW|W| = +δW², i.e. d = −δ (the "∓" of (2.3)).
    first = _Riccati(W0, a3, beta, side * delta)
    s_cross = first.zero_crossing()
    if math.isinf(s_cross):
        return _AxialSolution(first, math.inf, None, first.blowup())
    second = _Riccati(0.0, a3, beta, -side * delta)
    return _AxialSolution(first, s_cross, second, s_cross + second.blowup())


def _slow_time(tau: ArrayLike, p: Params) -> FloatArray:
    return p.eps * np.asarray(tau, dtype=float)


def _check_no_blowup(s: FloatArray, s_blow: float, what: str, p: Params) -> None:
    if s.size and np.max(s) >= s_blow:
        raise IntegrationError(
            f"the closed-form {what} diverges at τ = {s_blow / p.eps:.6g} (negative damping "
            f"coefficients, §11); request times before it"
        )


def equatorial_momentum(tau: ArrayLike, V0: float, p: Params) -> FloatArray:
    """V(τ) = k sin ϑ, closed form (2.4), valid in both hemispheres.

    Parameters
    ----------
    tau : array_like
        Times τ ≥ 0 [1].
    V0 : float
        Initial k0 sin ϑ0 ≥ 0 [1].
    p : Params
        Model parameters (α, γ, ε are used).

    Returns
    -------
    ndarray
        V at the requested times [1].
    """
    s = _slow_time(tau, p)
    _check_no_blowup(s, _bernoulli_blowup(V0, p.alpha, p.gamma), "V = k sin ϑ of (2.4)", p)
    return _bernoulli(V0, p.alpha, p.gamma, s)


def axial_momentum(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """W(τ) = k cos ϑ, closed forms (2.5)–(2.8) with the branch switch of §8.4.

    Each hemisphere's formula is used only while W keeps its sign; at the crossing time τ1 the
    other hemisphere's formula continues from W = 0. Written in the well-conditioned forms of
    §8.5 (algebraically identical to (2.5)–(2.8), the double roots and δ = 0).

    Parameters
    ----------
    tau : array_like
        Times τ ≥ 0 [1].
    W0 : float
        Initial k0 cos ϑ0 [1].
    p : Params
        Model parameters (a3, β, δ, ε are used).

    Returns
    -------
    ndarray
        W at the requested times [1].
    """
    s = _slow_time(tau, p)
    sol = _axial_solution(W0, float(p.a[2]), p.beta, p.delta)
    _check_no_blowup(s, sol.s_blowup, "W = k cos ϑ of (2.3)", p)
    return sol(s)


def crossing_time(W0: float, p: Params) -> float:
    """Time τ1 at which the averaged W = k cos ϑ reaches 0 (ϑ = π/2), §8.4; inf if never.

    Parameters
    ----------
    W0 : float
        Initial k0 cos ϑ0 [1].
    p : Params
        Model parameters.
    """
    s1 = _axial_solution(W0, float(p.a[2]), p.beta, p.delta).s_cross
    return math.inf if (math.isinf(s1) or p.eps == 0.0) else s1 / p.eps


def closed_form(p: Params, st: State, tau: ArrayLike) -> dict[str, FloatArray]:
    """Averaged motion in closed form: k, ϑ from (2.4)–(2.8) through W and V, ρ, σ constant.

    ϑ = atan2(V, W) (§8.6: no trouble at ϑ = π/2, no α/β division).

    Parameters
    ----------
    p : Params
        Model parameters.
    st : State
        Initial state (ψ, φ unused).
    tau : array_like
        Times τ ≥ 0 [1].

    Returns
    -------
    dict
        Columns ``k``, ``theta``, ``rho``, ``sigma`` at the requested times.
    """
    tau = np.asarray(tau, dtype=float)
    W = axial_momentum(tau, st.W, p)
    V = equatorial_momentum(tau, st.V, p)
    n = tau.shape
    return {
        "k": np.hypot(W, V),
        "theta": np.arctan2(V, W),
        "rho": np.full(n, st.rho),
        "sigma": np.full(n, st.sigma),
    }


# The paper's printed formulas, one per case, each valid only in its window (§8).


def _coeffs(p: Params) -> tuple[float, float, float, float]:
    if p.delta == 0.0:
        raise ParameterError("parameters.s[2][2] = 0: (2.5)–(2.8) need δ > 0; use axial_momentum")
    return float(p.a[2]), p.beta, p.delta, p.beta / (2.0 * p.delta)


def axial_upper_exp(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.5) with correction E3: k cos ϑ for W ≥ 0 when a3/δ > −h², h = β/(2δ).

    Parameters
    ----------
    tau : array_like
        Times τ [1], before any crossing of ϑ = π/2.
    W0 : float
        k0 cos ϑ0 ≥ 0 [1].
    p : Params
        Model parameters with δ > 0.
    """
    a3, be, de, h = _coeffs(p)
    nu1_sq = h * h + a3 / de
    if nu1_sq <= 0.0:
        raise ParameterError(f"(2.5) needs a3/δ > −(β/2δ)², got ν1² = {nu1_sq:g}")
    nu1 = math.sqrt(nu1_sq)
    c1 = (2 * de * W0 + be - 2 * de * nu1) / (2 * de * W0 + be + 2 * de * nu1)
    e = c1 * np.exp(-2 * p.eps * de * nu1 * np.asarray(tau, dtype=float))
    return (2 * de * nu1 - be + (2 * de * nu1 + be) * e) / (2 * de * (1 - e))


def axial_upper_tan(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.6): k cos ϑ for W ≥ 0 when a3/δ < −h² (μ1² = −h² − a3/δ > 0)."""
    a3, be, de, h = _coeffs(p)
    mu1_sq = -h * h - a3 / de
    if mu1_sq <= 0.0:
        raise ParameterError(f"(2.6) needs a3/δ < −(β/2δ)², got μ1² = {mu1_sq:g}")
    mu1 = math.sqrt(mu1_sq)
    arg = math.atan((2 * de * W0 + be) / (2 * de * mu1)) - p.eps * de * mu1 * np.asarray(
        tau, dtype=float
    )
    return (-be + 2 * de * mu1 * np.tan(arg)) / (2 * de)


def axial_upper_double_root(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """Double root a3/δ = −h² of the upper branch: W = −h + y0/(1 + εδ y0 τ), y0 = W0 + h."""
    _, _, de, h = _coeffs(p)
    y0 = W0 + h
    return -h + y0 / (1 + p.eps * de * y0 * np.asarray(tau, dtype=float))


def axial_lower_exp(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.7): k cos ϑ for W < 0 when a3/δ < h² (ν2² = h² − a3/δ > 0)."""
    a3, be, de, h = _coeffs(p)
    nu2_sq = h * h - a3 / de
    if nu2_sq <= 0.0:
        raise ParameterError(f"(2.7) needs a3/δ < (β/2δ)², got ν2² = {nu2_sq:g}")
    nu2 = math.sqrt(nu2_sq)
    c2 = (2 * de * (W0 - nu2) - be) / (2 * de * (W0 + nu2) - be)
    e = c2 * np.exp(2 * p.eps * de * nu2 * np.asarray(tau, dtype=float))
    return (2 * de * nu2 + be + (2 * de * nu2 - be) * e) / (2 * de * (1 - e))


def axial_lower_tan(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """(2.8): k cos ϑ for W < 0 when a3/δ > h² (μ2² = a3/δ − h² > 0)."""
    a3, be, de, h = _coeffs(p)
    mu2_sq = a3 / de - h * h
    if mu2_sq <= 0.0:
        raise ParameterError(f"(2.8) needs a3/δ > (β/2δ)², got μ2² = {mu2_sq:g}")
    mu2 = math.sqrt(mu2_sq)
    arg = math.atan((2 * de * W0 - be) / (2 * de * mu2)) + p.eps * de * mu2 * np.asarray(
        tau, dtype=float
    )
    return (be + 2 * de * mu2 * np.tan(arg)) / (2 * de)


def axial_lower_double_root(tau: ArrayLike, W0: float, p: Params) -> FloatArray:
    """Double root a3/δ = h² of the lower branch: W = h + y0/(1 − εδ y0 τ), y0 = W0 − h."""
    _, _, de, h = _coeffs(p)
    y0 = W0 - h
    return h + y0 / (1 - p.eps * de * y0 * np.asarray(tau, dtype=float))


def tan_theta_a3_zero_upper(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """(2.9): tan ϑ for a3 = 0, α, β > 0, 0 ≤ ϑ < π/2 (correction E7)."""
    t = np.asarray(tau, dtype=float)
    al, be, ga, de, e = p.alpha, p.beta, p.gamma, p.delta, p.eps
    num = be + de * k0 * math.cos(theta0) * (-np.expm1(-e * be * t))
    den = al + ga * k0 * math.sin(theta0) * (-np.expm1(-e * al * t))
    return al / be * math.tan(theta0) * num / den * np.exp(e * (be - al) * t)


def tan_theta_a3_zero_lower(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """(2.10): tan ϑ for a3 = 0, α, β > 0, π/2 < ϑ ≤ π (tan ϑ < 0; ϑ = π + arctan)."""
    t = np.asarray(tau, dtype=float)
    al, be, ga, de, e = p.alpha, p.beta, p.gamma, p.delta, p.eps
    w = de * k0 * math.cos(theta0)
    num = w - (w - be) * np.exp(e * be * t)
    den = al + ga * k0 * math.sin(theta0) * (-np.expm1(-e * al * t))
    return al / be * math.tan(theta0) * num / den * np.exp(-e * al * t)


def tan_theta_quadratic(tau: ArrayLike, k0: float, theta0: float, p: Params) -> FloatArray:
    """Quadratic-only medium (a3 = α = β = 0), §8.7, both hemispheres (correction E8).

    tan ϑ = tan ϑ0 (1 + εδ k0 |cos ϑ0| τ)/(1 + εγ k0 sin ϑ0 τ).
    """
    t = np.asarray(tau, dtype=float)
    num = 1 + p.eps * p.delta * k0 * abs(math.cos(theta0)) * t
    den = 1 + p.eps * p.gamma * k0 * math.sin(theta0) * t
    return math.tan(theta0) * num / den


# ---------------------------------------------------------------------------------------------
# Asymptotic conclusions, §9.


def _scalar_limit(x0: float, f: Callable[[float], float], roots: list[float]) -> float:
    """Limit of a monotone scalar flow dx/ds = f(x) from x0: the nearest root ahead, or ±inf."""
    f0 = f(x0)
    if f0 == 0.0:
        return x0
    direction = math.copysign(1.0, f0)
    ahead = [r for r in roots if (r - x0) * direction > 0.0]
    return min(ahead, key=lambda r: abs(r - x0)) if ahead else direction * math.inf


def _riccati_roots(a3: float, beta: float, d: float) -> list[float]:
    if d == 0.0:
        return [a3 / beta] if beta != 0.0 else []
    disc = beta * beta + 4.0 * d * a3
    if disc < 0.0:
        return []
    sq = math.sqrt(disc)
    return [(-beta + sq) / (2 * d), (-beta - sq) / (2 * d)]


def _W_limit(W0: float, a3: float, beta: float, delta: float) -> float:
    if W0 == 0.0 and a3 == 0.0:
        return 0.0
    side = math.copysign(1.0, W0) if W0 != 0.0 else math.copysign(1.0, a3)
    start = W0
    for _ in range(2):
        d = side * delta

        def rate(w: float, d: float = d) -> float:
            return a3 - beta * w - d * w * w

        target = _scalar_limit(start, rate, _riccati_roots(a3, beta, d))
        if side * target >= 0.0:
            return target
        side, start = -side, 0.0  # W reaches 0 first and continues in the other hemisphere
    raise AssertionError("W crosses 0 at most once")  # pragma: no cover (a3 fixes the direction)


def predicted_limits(p: Params, st: State) -> dict[str, Any]:
    """Limits of ϑ and k of the averaged system as τ → ∞, §9 (the paper's conclusions).

    Handles every sign of a3, the a3 = 0 split by β ≷ α, β = α, the quadratic-only medium,
    degenerate and negative coefficients (by the phase line of each scalar equation of (2.3)).

    Parameters
    ----------
    p : Params
        Model parameters.
    st : State
        Initial state.

    Returns
    -------
    dict
        ``theta`` [rad] (None where undefined), ``k``, ``W``, ``V`` [1] (may be ±inf), and
        ``statement``: which conclusion of §9 applies.
    """
    a3, al, be, ga, de = float(p.a[2]), p.alpha, p.beta, p.gamma, p.delta
    W0, V0 = st.W, st.V
    if p.eps == 0.0:
        return {"theta": st.theta, "k": st.k, "W": W0, "V": V0, "statement": "ε = 0: no evolution"}
    W_inf = _W_limit(W0, a3, be, de)
    V_inf = _scalar_limit(V0, lambda v: -(al * v + ga * v * v), [0.0] + ([-al / ga] if ga else []))
    theta: float | None
    if W_inf != 0.0 or V_inf != 0.0:
        if math.isinf(W_inf) and math.isinf(V_inf):
            theta, statement = None, "both W and V diverge: ϑ has no limit from (2.3) alone"
        else:
            theta = math.atan2(V_inf, W_inf)
            statement = {1.0: "a3 > 0: ϑ → 0", -1.0: "a3 < 0: ϑ → π"}.get(
                math.copysign(1.0, a3) if a3 else 0.0, "a3 = 0"
            )
            if V_inf != 0.0:
                statement = "V does not decay (α = γ = 0 or self-excitation): ϑ → atan2(V∞, W∞)"
    elif V0 == 0.0:
        theta = 0.0 if math.copysign(1.0, W0) > 0 else math.pi
        statement = "V0 = 0: the axis stays along ±K"
    elif W0 == 0.0:
        theta, statement = math.pi / 2, "W ≡ 0: ϑ stays π/2"
    else:
        # Both components decay (a3 = 0): the slower one wins. Asymptotic amplitudes follow from
        # (2.4) and the a3 = 0 Riccati solution: V ~ αV0/(α+γV0) e^{−αs}, W ~ βW0/(β+δ|W0|) e^{−βs};
        # a zero linear coefficient leaves an algebraic 1/(γs) or 1/(δs) decay.
        if al > 0 and be > 0:
            # β = α to round-off (e.g. b33/(1+κ) computed from b33 = α(1+κ)) is the β = α case:
            # a difference of 1e-16 would only act after ετ ~ 1e16.
            if math.isclose(al, be, rel_tol=1e-12):
                theta = math.atan2(al * V0 / (al + ga * V0), be * W0 / (be + de * abs(W0)))
                statement = "a3 = 0, β = α: tan ϑ∞ = tan ϑ0 (β + δ|W0|)/(α + γV0)"
            elif be > al:
                theta, statement = math.pi / 2, "a3 = 0, β > α: ϑ → π/2"
            else:
                theta = 0.0 if W0 > 0 else math.pi
                statement = "a3 = 0, β < α: ϑ → 0 or π by hemisphere"
        elif be > 0:
            theta, statement = math.pi / 2, "a3 = 0, β > 0 = α: ϑ → π/2"
        elif al > 0:
            theta = 0.0 if W0 > 0 else math.pi
            statement = "a3 = 0, α > 0 = β: ϑ → 0 or π by hemisphere"
        else:
            theta = math.atan2(de, math.copysign(ga, W0))
            statement = "quadratic-only medium: tan ϑ → ±δ/γ (§8.7, correction E8)"
    return {
        "theta": theta,
        "k": math.hypot(W_inf, V_inf),
        "W": W_inf,
        "V": V_inf,
        "statement": statement,
    }


# ---------------------------------------------------------------------------------------------
# Where averaging fails, §10 and §11.


def moment_depends_on_phi(p: Params) -> bool:
    """True if the k, ϑ equations of the full model depend on φ (§10.1 special case).

    They do not (and then (2.2) is exact for k, ϑ, even across ϑ = π/2) when a1 = a2 = 0,
    b11 = b22, b12 = −b21, b13 = b23 = b31 = b32 = 0, and s has no entry but s33.
    """
    a, b, s = p.a, p.b, p.s
    s_other = s.copy()
    s_other[2, 2] = 0.0
    return bool(
        a[0] != 0.0
        or a[1] != 0.0
        or b[0, 0] != b[1, 1]
        or b[0, 1] + b[1, 0] != 0.0
        or np.any(b[[0, 1, 2, 2], [2, 2, 0, 1]] != 0.0)
        or np.any(s_other != 0.0)
    )


def _slow_rate_per_k(p: Params, k: FloatArray) -> FloatArray:
    """Slow rate per unit k, ε(|a|/k² + c|b|/k + c²|s|), §6.

    It bounds |dϑ/dτ|/k and |dk/dτ|/k² since |m| ≤ |a| + |b||w| + |s||w|² with
    |w| ≤ c k, c = 1/min(1, 1+κ); norms are Euclidean (matrix 2-norms).
    """
    c = 1.0 / min(1.0, 1.0 + p.kappa)
    na = float(np.linalg.norm(p.a))
    nb = float(np.linalg.norm(p.b, 2))
    ns = float(np.linalg.norm(p.s, 2))
    with np.errstate(divide="ignore"):
        return p.eps * (na / k**2 + c * nb / k + c * c * ns)


def validity(p: Params, st: State, slow: SlowPath, tau_end: float) -> list[ValidityIssue]:
    """Regions of §10–§11 that an averaged trajectory enters, with the first τ of each.

    Parameters
    ----------
    p : Params
        Model parameters.
    st : State
        Initial state.
    slow : callable
        ``slow(tau) -> {"k": ..., "theta": ...}`` along the averaged trajectory.
    tau_end : float
        End of the run [1].

    Returns
    -------
    list of ValidityIssue
        ``theta_crossing`` (ϑ = π/2 passed with a φ-dependent moment: O(√ε) after it, §10.2),
        ``phi_not_fast`` (slow rates not small against |κ cos ϑ|/(1+κ), §6, §10.3),
        ``spin_not_fast`` (k too small: slow rates not small against the precession rate k,
        §10.5), ``through_k_zero`` (ϑ0 ∈ {0, π} and W changes sign: k passes through 0, §11),
        ``resonance`` (the precession rate k = n|Ω_φ|, |cos ϑ| = (1+κ)/(n|κ|), n ≤
        RESONANCE_ORDER, crossed with a φ-dependent moment: ρ, σ may shift, §10.5).
    """
    if p.eps == 0.0 or tau_end <= 0.0:
        return []
    grid = np.linspace(0.0, tau_end, 4001)
    phi_dependent = moment_depends_on_phi(p)

    def cols(t: FloatArray) -> tuple[FloatArray, FloatArray]:
        c = slow(t)
        return c["k"], c["theta"]

    found = [_crossing_issue(p, st, tau_end, phi_dependent)]
    if phi_dependent:
        found += [_resonance_issue(p, cols, grid), _phi_issue(p, cols, grid)]
    found.append(_spin_issue(p, cols, grid))
    return [issue for issue in found if issue is not None]


_KTheta = Callable[[FloatArray], tuple[FloatArray, FloatArray]]  # τ → (k, ϑ) of the trajectory


def _crossing_issue(
    p: Params, st: State, tau_end: float, phi_dependent: bool
) -> ValidityIssue | None:
    """ϑ = π/2 crossed with a φ-dependent moment (§10.2), or k through 0 from ϑ0 ∈ {0, π}
    (§11)."""
    tau1 = crossing_time(st.W, p)
    crosses = tau1 <= tau_end
    if st.W == 0.0 and float(p.a[2]) != 0.0:
        tau1, crosses = 0.0, True  # starts on ϑ = π/2 and leaves it at once
    if crosses and abs(math.sin(st.theta)) < 1e-12:
        return ValidityIssue(
            "through_k_zero",
            tau1,
            f"ϑ0 is 0 or π and W = k cos ϑ changes sign at τ = {tau1:.6g}: the averaged "
            "solution passes through k = 0 and ϑ jumps between 0 and π, outside the "
            "validity of averaging (docs/theory/resisting-medium.md §11)",
        )
    if crosses and phi_dependent:
        return ValidityIssue(
            "theta_crossing",
            tau1,
            f"the averaged trajectory crosses ϑ = π/2 at τ = {tau1:.6g}: φ stops rotating "
            "there and, with a φ-dependent moment, the averaged model is only O(√ε) "
            "accurate after the passage (docs/theory/resisting-medium.md §10.2)",
            label="ϑ = π/2",
        )
    return None


def _resonance_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """The first resonance k = n|Ω_φ| crossed (§10.5)."""
    resonance = _first_resonance(p, lambda t: np.abs(np.cos(cols(t)[1])), grid)
    if resonance is None:
        return None
    tau_r, n = resonance
    return ValidityIssue(
        "resonance",
        tau_r,
        f"at τ ≈ {tau_r:.6g} the precession rate k equals {n}× the spin rate "
        f"|Ω_φ| (|cos ϑ| = (1+κ)/({n}|κ|)): the resonant terms, which first-order "
        "averaging drops, can shift ρ and σ; k and ϑ are unaffected "
        "(docs/theory/resisting-medium.md §10.5)",
        label=f"resonance ψ̇ = {n}·|φ̇|",
    )


def _phi_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """The spin φ no longer fast against the slow drift (§6, §10.3)."""

    def phi_slow(t: FloatArray) -> FloatArray:
        k, theta = cols(t)
        fast = np.abs(p.kappa * np.cos(theta)) / (1.0 + p.kappa)
        return _slow_rate_per_k(p, k) - VALIDITY_RATIO * fast

    t_phi = first_time(phi_slow, grid)
    if t_phi is None:
        return None
    return ValidityIssue(
        "phi_not_fast",
        t_phi,
        f"from τ = {t_phi:.6g} the spin φ is no longer fast against the slow drift "
        f"(ε(|a|/k² + |b|/k + |s|) > {VALIDITY_RATIO:g}·|κ cos ϑ|/(1+κ)): averaging "
        "loses accuracy there (docs/theory/resisting-medium.md §6, §10.3)",
    )


def _spin_issue(p: Params, cols: _KTheta, grid: FloatArray) -> ValidityIssue | None:
    """k too small for the body to spin fast against the moment (§10.5)."""

    def spin_slow(t: FloatArray) -> FloatArray:
        k, _ = cols(t)
        return _slow_rate_per_k(p, k) - VALIDITY_RATIO

    t_spin = first_time(spin_slow, grid)
    if t_spin is None:
        return None
    k_at = float(cols(np.array([t_spin]))[0][0])
    return ValidityIssue(
        "spin_not_fast",
        t_spin,
        f"from τ = {t_spin:.6g} (k = {k_at:.3g}) the body no longer spins fast against "
        f"the moment (ε(|a|/k² + |b|/k + |s|) > {VALIDITY_RATIO:g}): the averaged model "
        "is invalid as k → 0 (docs/theory/resisting-medium.md §10.5)",
    )


RESONANCE_ORDER = 4
"""Largest n of the resonances k = n|Ω_φ| reported (§10.5): for a smooth moment the
resonant harmonics fall off with n, and a pass through one of order n costs O(ε^{1/2})
times that harmonic."""


def _first_resonance(
    p: Params, abs_cos: Callable[[FloatArray], FloatArray], grid: FloatArray
) -> tuple[float, int] | None:
    """First τ on ``grid`` where |cos ϑ| crosses (1+κ)/(n|κ|), n ≤ RESONANCE_ORDER, and n."""
    values = abs_cos(grid)
    found: tuple[float, int] | None = None
    for n in range(1, RESONANCE_ORDER + 1):
        level = (1.0 + p.kappa) / (n * abs(p.kappa))
        if level >= 1.0:
            continue
        side = np.sign(values - level)
        flips = np.flatnonzero(side[1:] * side[:-1] < 0.0)
        if not flips.size:
            continue
        s0 = float(side[flips[0]])

        def beyond(t: FloatArray, s0: float = s0, level: float = level) -> FloatArray:
            return -s0 * (abs_cos(t) - level)

        t = first_time(beyond, grid)
        if t is not None and (found is None or t < found[0]):
            found = (t, n)
    return found


# ---------------------------------------------------------------------------------------------
# Registry record.

_ANGLE = "rad"
_COLUMNS_SLOW = (
    Column("k", "angular momentum |K|/K0", "1", "(1.3)"),
    Column("theta", "nutation angle ϑ between x3 and K", _ANGLE, "(1.3)", angle=False),
    Column("rho", "polar angle ρ of K from X3", _ANGLE, "(1.3)"),
    Column("sigma", "azimuth σ of K about X3", _ANGLE, "(1.3)", angle=True, unwrap=True),
)
_COLUMNS_MEAN = tuple(
    Column(f"{c.name}_mean", f"mean {c.long_name} (averaging of order 2)", c.units, c.equation,
           angle=c.angle)
    for c in (
        *_COLUMNS_SLOW,
        Column("psi", "precession angle ψ of x3 about K", _ANGLE, "(1.3)", angle=True),
        Column("phi", "proper rotation angle φ", _ANGLE, "(1.3)", angle=True),
    )
)  # fmt: skip
_COLUMNS_FULL = (
    *_COLUMNS_SLOW,
    Column("psi", "precession angle ψ of x3 about K", _ANGLE, "(1.3)", angle=True, unwrap=True),
    Column("phi", "proper rotation angle φ", _ANGLE, "(1.3)", angle=True, unwrap=True),
    *attitude_columns("τ"),
)


def full_kernel(p: Params) -> Kernel | None:
    """:func:`full_rhs` compiled (:mod:`tumble.kernels`): Euler + quaternions with (1.2)."""
    return p.kernel


FULL_EULER: FullForm[Params, State] = FullForm(
    name="euler",
    equation="Euler + quaternions with (1.2)",
    state=("w1", "w2", "w3", "q0", "q1", "q2", "q3"),
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

_COLUMNS_FULL_OF = fixed_columns(_COLUMNS_FULL)
_COLUMNS_SLOW_OF = fixed_columns(_COLUMNS_SLOW)
_COLUMNS_AVERAGED_OF = fixed_columns((*_COLUMNS_SLOW, *_COLUMNS_MEAN))

_ENTRY = CATALOGUE["resisting_medium"]  # name, description and paper

MODEL: Model[Params, State] = Model(
    name=_ENTRY.name,
    description=_ENTRY.description,
    paper=_ENTRY.paper,
    time=DECLARED.time,
    full=Full(
        forms={"euler": FULL_EULER, "osculating": FULL_OSCULATING},
        default="euler",
        columns=_COLUMNS_FULL_OF,
    ),
    check=DECLARED.check,
    methods=DECLARED.methods,
    averaged=Averaged(
        form=_averaged_form,
        columns=_COLUMNS_AVERAGED_OF,
        compare=("k", "rho", "sigma", "theta"),
        numeric=DECLARED.numeric,
        orders=DECLARED.orders,
        hybrid=DECLARED.hybrid,
    ),
    closed_form=ClosedForm(evaluate=closed_form, columns=_COLUMNS_SLOW_OF),
    unperturbed=Unperturbed(
        "the free symmetric body",
        lambda p, st: EulerPoinsot.from_rigid_body_state(p.inertia, full_from_slow(p, st)).states,
        lambda t, y, p: full_rhs(t, y, p.with_eps(0.0)),
    ),
    validity=Validity(check=validity, limits=predicted_limits),
    scenario=DECLARED.scenario,
)
