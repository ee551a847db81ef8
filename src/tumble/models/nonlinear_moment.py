"""Symmetric body under the nonlinear moment M0(θ) = A(a·sinθ + b·sin2θ): full motion, the
exact unperturbed motion, and Volosov's averaged equations for the nutation envelope.

V. M. Serov, *Rotational motion of a dynamically symmetric rigid body under the action of a
nonlinear moment* (1991), seed ``003_95a5fc288cdb1f88.txt``; ``spec/serov.md`` supersedes the
seed where they differ (its §12: A is the equatorial moment, β, τ0, γ0, χ±, λ±, L± and the
coefficient of L±). Equation numbers below are the paper's.

Variables (spec §1): time t in the unit of the coefficients (a, b [1/t²], R, G [1/t]),
μ = C/A, classical z–x–z Euler angles ψ, θ, φ of the body relative to the fixed axis e_z (for
an entry vehicle the velocity direction, θ the total angle of attack), R = μr and G = K·e_z/A
the reduced angular momenta. The perturbation of §9 (the entry capsule) has slow time τ = εt:
a = a0·Q(τ), b = b0·Q(τ) with the dynamic-pressure profile Q, pitch damping εd and roll
damping εν.

The averaged method integrates (2.2)–(2.3) for the slow variables: the energy H (form
``"energy"``, the better-conditioned one of spec §7) or the turning point θext (form
``"theta_max"``/``"theta_min"``, the paper's (2.2)), together with z = (R, G, a, b). The
averages come from the closed forms of §8 (⟨u⟩, ⟨u²⟩ by K, E, Π) for the built-in
perturbation, and from adaptive quadrature over the nutation period for any perturbation
given as Φθ(θ, θ', z), Φz(θ, z) (:class:`Perturbation`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.averaging.nutation import (
    AVERAGE_RTOL,
    Perturbation,
    numeric_averages,
    potential_gradient,
    torque_perturbation,
)
from tumble.catalogue import CATALOGUE
from tumble.errors import IntegrationError, ParameterError, ScenarioError, check_range, shorten
from tumble.kernels import EVENT_THETA_DOT, KIND_NONLINEAR_MOMENT, Kernel
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
    first_time,
    fixed_columns,
)
from tumble.models.schema import Built, Inputs, Key, ScenarioSchema, Section, Variant
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
"""1 − k² below which an averaged run is warned that it nears a separatrix (spec §11)."""

EPS_PERIOD_LIMIT = 0.5
"""ε·T (slow time per nutation period) above which ε is not small enough for averaging."""


# ---------------------------------------------------------------------------------------------
# Parameters and states.


@dataclass(frozen=True)
class Pressure:
    """Dynamic-pressure profile Q(τ) of spec §9: constant, exponential Q = e^τ, a table, or
    (from Python) any smooth function.

    Parameters
    ----------
    kind : {"constant", "exp", "table", "function"}
        The profile.
    tau, Q : sequence of float, optional
        For ``"table"``: knots τ_i (ascending, τ_0 ≤ 0) and values Q_i > 0, interpolated
        piecewise-linearly; τ outside [τ_0, τ_last] is an error.
    function, derivative : callable, optional
        For ``"function"``: vectorized Q(τ) > 0 and dQ/dτ (e.g. the dynamic pressure of a
        computed descent, :mod:`tumble.analysis.capsule`), valid on [0, ``tau_end``].
    tau_end : float
        For ``"function"``: the last τ it covers.
    breaks : tuple of float
        For ``"function"``: τ where dQ/dτ jumps (the averaged run restarts there).
    """

    kind: Literal["constant", "exp", "table", "function"] = "constant"
    tau: tuple[float, ...] = ()
    Q: tuple[float, ...] = ()
    function: Callable[[FloatArray], FloatArray] | None = field(default=None, compare=False)
    derivative: Callable[[FloatArray], FloatArray] | None = field(default=None, compare=False)
    tau_end: float = math.inf
    breaks: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        if self.kind == "function":
            if self.function is None or self.derivative is None:
                raise ParameterError("a pressure of kind 'function' needs function and derivative")
            return
        if self.kind not in ("constant", "exp", "table"):
            raise ParameterError(
                f"perturbation.pressure = {shorten(repr(self.kind), 60)} is not a profile "
                '(allowed: "constant", "exp", or a table)'
            )
        tau = tuple(float(v) for v in self.tau)
        Q = tuple(float(v) for v in self.Q)
        object.__setattr__(self, "tau", tau)
        object.__setattr__(self, "Q", Q)
        if self.kind != "table":
            if tau or Q:
                raise ParameterError(f"perturbation.pressure = {self.kind!r} takes no table")
            return
        if len(tau) < 2 or len(tau) != len(Q):
            raise ParameterError(
                "perturbation.pressure table needs at least 2 points (τ, Q) of equal count, "
                f"got {len(tau)} τ and {len(Q)} Q"
            )
        if not all(math.isfinite(v) for v in tau + Q):
            raise ParameterError("perturbation.pressure table must contain finite numbers only")
        if any(b <= a for a, b in itertools.pairwise(tau)):
            raise ParameterError("perturbation.pressure table: τ must be strictly ascending")
        if tau[0] > 0.0:
            raise ParameterError(
                f"perturbation.pressure table starts at τ = {tau[0]:g}; it must cover τ = 0"
            )
        if min(Q) <= 0.0:
            raise ParameterError(
                f"perturbation.pressure table: Q = {min(Q):g} is outside the allowed range (0, inf)"
            )

    @property
    def tau_max(self) -> float:
        """Last τ the profile covers [1]."""
        return self.tau[-1] if self.kind == "table" else self.tau_end

    def _check(self, tau: FloatArray) -> None:
        if self.kind == "function" and np.any(tau > self.tau_end):
            raise ParameterError(
                f"the pressure profile covers τ ≤ {self.tau_end:g}, but τ = "
                f"{float(np.max(tau)):g} is needed"
            )
        if self.kind == "table" and (np.any(tau < self.tau[0]) or np.any(tau > self.tau[-1])):
            bad = float(tau[(tau < self.tau[0]) | (tau > self.tau[-1])].flat[0])
            raise ParameterError(
                f"perturbation.pressure table covers τ in [{self.tau[0]:g}, {self.tau[-1]:g}], "
                f"but τ = {bad:g} is needed"
            )

    def value(self, tau: ArrayLike) -> FloatArray:
        """Q(τ) [1]."""
        return self._evaluate(tau, derivative=False)

    def rate(self, tau: ArrayLike) -> FloatArray:
        """dQ/dτ [1]; for a table the slope of the segment τ lies in (right-continuous)."""
        return self._evaluate(tau, derivative=True)

    def _evaluate(self, tau: ArrayLike, *, derivative: bool) -> FloatArray:
        t = np.asarray(tau, dtype=float)
        if self.kind == "constant":
            return np.zeros_like(t) if derivative else np.ones_like(t)
        if self.kind == "exp":
            return np.exp(t)
        self._check(t)
        fn = self.derivative if derivative else self.function
        if fn is not None:
            return np.asarray(fn(t), dtype=float)
        if not derivative:
            return np.interp(t, self.tau, self.Q)
        knots = np.asarray(self.tau)
        slopes = np.diff(self.Q) / np.diff(knots)
        i = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, slopes.size - 1)
        return slopes[i]

    def knots(self) -> tuple[float, ...]:
        """Interior τ where dQ/dτ jumps (a table's inner knots, a function's breaks) [1]."""
        return self.tau[1:-1] if self.kind == "table" else self.breaks


@dataclass(frozen=True)
class Params:
    """Parameters of (1.1)–(1.5) and of the perturbation of spec §9.

    Parameters
    ----------
    mu : float
        μ = C/A, axial over equatorial moment of inertia, in (0, 2] [1].
    a, b : float
        Coefficients of M0(θ)/A = a·sinθ + b·sin2θ at t = 0 [1/t²]; a < 0 restores towards
        θ = 0, b < 0 makes a double well (1.5).
    eps : float
        ε ≥ 0; 0 means unperturbed (R, G, E, a, b constant) [1].
    d : float
        Pitch damping: the moment −εA·d·(p e1 + q e2) [1/t].
    nu : float
        Roll damping: the moment −εC·ν·r e3 [1/t].
    pressure : Pressure
        Q(τ), τ = εt: a(τ) = a·Q(τ)/Q(0), b(τ) = b·Q(τ)/Q(0).
    """

    mu: float
    a: float
    b: float
    eps: float = 0.0
    d: float = 0.0
    nu: float = 0.0
    pressure: Pressure = field(default_factory=Pressure)
    Q0: float = field(init=False, repr=False)  # Q(0), derived

    def __post_init__(self) -> None:
        check_range("parameters.mu", float(self.mu), low=0.0, high=2.0, high_open=False)
        for name in ("a", "b"):
            if not math.isfinite(getattr(self, name)):
                raise ParameterError(f"parameters.{name} must be a finite number")
        for name in ("d", "nu"):
            if not math.isfinite(getattr(self, name)):
                raise ParameterError(f"perturbation.{name} must be a finite number")
        check_range("perturbation.eps", float(self.eps), low=0.0, high=1.0, low_open=False)
        if self.eps == 0.0 and (self.d or self.nu or self.pressure.kind != "constant"):
            raise ParameterError(
                "perturbation.eps = 0 is outside the allowed range (0, 1) for a perturbation "
                "with damping or a pressure profile"
            )
        for name in ("mu", "a", "b", "eps", "d", "nu"):
            object.__setattr__(self, name, float(getattr(self, name)))
        object.__setattr__(self, "Q0", float(self.pressure.value(0.0)))

    @property
    def perturbed(self) -> bool:
        """Whether ε > 0 (the run is perturbed)."""
        return self.eps > 0.0

    def ab(self, t: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """a(t), b(t) = (a, b)·Q(εt)/Q(0) [1/t²]."""
        q = self.pressure.value(self.eps * np.asarray(t, dtype=float)) / self.Q0
        return self.a * q, self.b * q

    def ab_rate(self, tau: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """da/dτ, db/dτ = (a, b)·Q'(τ)/Q(0) [1/t²] (Φ_a, Φ_b of spec §9)."""
        q = self.pressure.rate(np.asarray(tau, dtype=float)) / self.Q0
        return self.a * q, self.b * q

    def with_eps(self, eps: float) -> Params:
        """The same body and perturbation at another ε (for error studies: a(τ), b(τ) keep
        their slow-time profile)."""
        return replace(self, eps=eps)

    def unperturbed(self) -> Params:
        """The same body and moment at t = 0 without any perturbation: ε = 0, no damping,
        constant pressure."""
        return Params(self.mu, self.a, self.b)

    def derived(self) -> dict[str, Any]:
        """Quantities worth recording beside the inputs."""
        return {"perturbed": self.perturbed, "Q0": self.Q0}


@dataclass(frozen=True)
class State:
    """A state at t = 0, spec §14: Euler angles, nutation rate and reduced momenta.

    Parameters
    ----------
    theta : float
        Nutation angle, in (0, π) [rad].
    theta_dot : float
        θ' [rad/t].
    psi, phi : float
        Precession and proper rotation [rad].
    R : float
        R = μ r = C r / A [1/t].
    G : float
        G = K·e_z / A [1/t].
    """

    theta: float
    theta_dot: float = 0.0
    psi: float = 0.0
    phi: float = 0.0
    R: float = 0.0
    G: float = 0.0

    def __post_init__(self) -> None:
        check_range("initial.theta", float(self.theta), low=0.0, high=math.pi)
        for name in ("theta_dot", "psi", "phi", "R", "G"):
            if not math.isfinite(getattr(self, name)):
                raise ParameterError(f"initial.{name} must be a finite number")
            object.__setattr__(self, name, float(getattr(self, name)))
        object.__setattr__(self, "theta", float(self.theta))


def orbit_of(p: Params, st: State) -> NutationOrbit:
    """The unperturbed orbit through ``st`` (ε = 0), (1.9)–(1.13).

    Parameters
    ----------
    p : Params
    st : State

    Returns
    -------
    NutationOrbit
        With t = 0 at ``st``.
    """
    return NutationOrbit.from_state(
        p.mu, p.a, p.b, st.R, st.G, st.theta, st.theta_dot, psi=st.psi, phi=st.phi
    )


# ---------------------------------------------------------------------------------------------
# Full equations: (1.1) with quaternion kinematics (singularity-free), and the reduced (1.3).


def full_from_slow(p: Params, st: State) -> FloatArray:
    """State ``[p, q, r, q0, q1, q2, q3]`` of the quaternion form from Euler angles and R, G.

    Inverts (1.2) with R = μr, ψ' = (G − R cosθ)/sin²θ, φ' = r − ψ' cosθ (1.3).

    Parameters
    ----------
    p : Params
    st : State

    Returns
    -------
    ndarray, shape (7,)
        Body angular velocity [rad/t] and the body → inertial quaternion (z–x–z angles).
    """
    s, c = math.sin(st.theta), math.cos(st.theta)
    r = st.R / p.mu
    psid = (st.G - st.R * c) / (s * s)
    sp, cp = math.sin(st.phi), math.cos(st.phi)
    om = [psid * s * sp + st.theta_dot * cp, psid * s * cp - st.theta_dot * sp, r]
    q = matrix_to_quat(euler313_to_matrix(st.psi, st.theta, st.phi))
    return np.array([*om, *q.tolist()])


def full_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Euler's equations (1.1) with quaternion kinematics under the moment of spec §9.

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
    (from (1.2)); R = μr; G = (p, q, μr)·e_z (spec §1).

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
# The perturbation (2.1) in general, and the built-in one of spec §9.


def builtin_perturbation(p: Params) -> Perturbation:
    """Φθ, Φz of the descending capsule, spec §9: pitch and roll damping, pressure Q(τ).

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

    return Perturbation(phi_theta, phi_z, name="spec §9 (pitch/roll damping, pressure)")


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
    return {n: Y[:, i].copy() for i, n in enumerate(names)}


def _builtin_reduced_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    return reduced_rhs(t, y, p, builtin_perturbation(p))


# ---------------------------------------------------------------------------------------------
# Averaged equations (2.2)–(2.3).


def _builtin_averages(orbit: NutationOrbit, p: Params, tau: float) -> tuple[float, FloatArray]:
    """The averages of spec §9 in closed form: ⟨u⟩, ⟨u²⟩ by K, E, Π (§8)."""
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
            "(spec §11); do not average across a separatrix"
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
    """Volosov's averaged equations (2.2)–(2.3) of spec §7.

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
        Default: the built-in one of spec §9, averaged in closed form (§8); any other is
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
    """The averaged initial state H̄(0), z̄(0) of spec §7 and §14 (``[run] averaged_init``).

    ``start = "exact"``: H̄ = H(0), z̄ = z(0) (the paper's). ``"corrected"``:
    H̄ = H(0) − ε∫_{t*}^0 (g − ⟨g⟩)dt, z̄ = z(0) − ε∫_{t*}^0 (Φz − ⟨Φz⟩)dt along the frozen
    orbit, t* ≤ 0 its last turning point, g = Φθθ' + W^z·Φz.

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
        pert = builtin_perturbation(p) if perturbation is None else perturbation
        if perturbation is None:
            g_mean, pz_mean = _builtin_averages(orbit, p, 0.0)
        else:
            g_mean, pz_mean = numeric_averages(orbit, pert, 0.0)
        t_star = orbit.turning_time("last")
        if t_star < 0.0:

            def g(theta: FloatArray, theta_dot: FloatArray) -> FloatArray:
                ph, pz = pert.evaluate(0.0, theta, theta_dot, z)
                return ph * theta_dot + np.sum(pz * potential_gradient(np.cos(theta), z), axis=0)

            def component(i: int) -> Callable[[FloatArray, FloatArray], FloatArray]:
                def f(theta: FloatArray, theta_dot: FloatArray) -> FloatArray:
                    return pert.evaluate(0.0, theta, theta_dot, z)[1][i]

                return f

            H -= p.eps * (orbit.time_integral(g, t_star, 0.0) + g_mean * t_star)
            dz = [
                orbit.time_integral(component(i), t_star, 0.0) + pz_mean[i] * t_star
                for i in range(4)
            ]
            z = z - p.eps * np.array(dz)
            orbit = NutationOrbit.from_energy(
                p.mu, z[2], z[3], z[0], z[1], H, u_hint=0.5 * (orbit.u1 + orbit.u2)
            )
    return H, z, orbit


def damping_torque(p: Params) -> LinearDrag:
    """The damping of spec §9 as a body-axes torque per unit A and ε: −d(p, q, 0) − ν(0, 0, R).

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
    """The perturbation of spec §9 for the general engine: its damping as a torque, its
    pressure as the prescribed laws of a and b (``averaging = "numeric"``)."""
    return torque_perturbation(
        damping_torque(p),
        p.mu,
        ab_rate=lambda tau: (float(p.ab_rate(tau)[0]), float(p.ab_rate(tau)[1])),
        name="spec §9 damping through the engine",
    )


AveragedCoordinates = Literal["energy", "theta_max", "theta_min"]
_COORDINATES: dict[str, AveragedCoordinates] = {
    "energy": "energy",
    "theta_max": "theta_max",
    "theta_min": "theta_min",
}


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    """Volosov's equations (2.2)–(2.3) in the energy H (default) or a turning point besides z,
    their averages in closed form (§8–§9: K, E, Π) or by the general engine
    (:mod:`tumble.averaging.nutation`, ``averaging = "numeric"``), from the exact or the
    corrected start."""
    engine = engine_perturbation(p) if options.averaging == "numeric" else None
    H, z, orbit = averaged_initial(p, st, engine, options.start)
    form = _COORDINATES[options.coordinates or "energy"]
    u_hint = 0.5 * (orbit.u1 + orbit.u2)
    if form == "energy":
        y0 = np.array([H, *z.tolist()])
    else:
        y0 = np.array([orbit.theta_max if form == "theta_max" else orbit.theta_min, *z.tolist()])

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
        return _averaged_columns(Y, p, form, u_hint)

    # dQ/dτ jumps at the table's knots: stop and restart there so no step straddles one.
    knots = tuple(Breakpoint.at_time(tk / p.eps) for tk in p.pressure.knots() if tk > 0.0)

    def energy_of(y: FloatArray) -> float:
        x, R, G, a, b = (float(v) for v in y)
        return x if form == "energy" else float(effective_potential(x, R, G, a, b))

    def below_barriers(t: float, y: FloatArray) -> float:
        # > 0 while H is below every barrier of W, < 0 while above one: a sign change is a
        # separatrix crossing (spec §11), which one step could otherwise jump over unseen.
        barriers = barrier_energies(*(float(v) for v in y[1:]))
        return float(np.min(barriers) - energy_of(y)) if barriers.size else 1.0

    def refuse(t: float, y: FloatArray) -> FloatArray:
        raise IntegrationError(
            f"averaged equations (2.2): the motion reaches a separatrix at t = {t:.6g} (the "
            "energy crosses the barrier between two wells of W); averaging is not valid across "
            "it (spec §11): run the full model there"
        )

    separatrix = Breakpoint(below_barriers, refuse)
    return AveragedForm(
        name=form,
        equation="(2.2)-(2.3)" + (", energy form of spec §7" if form == "energy" else ""),
        slow=("H" if form == "energy" else form, "R", "G", "a", "b"),
        rhs=rhs,
        initial_state=initial_state,
        to_columns=to_columns,
        breakpoints=(*knots, separatrix),
        failure=failure,
    )


def _slow_orbit(y: Sequence[float], p: Params, form: str, u_hint: float) -> NutationOrbit:
    x, R, G, a, b = (float(v) for v in y)
    if form == "energy":
        return NutationOrbit.from_energy(p.mu, a, b, R, G, x, u_hint=u_hint)
    return NutationOrbit.from_turning_point(p.mu, a, b, R, G, x)


def _averaged_columns(Y: FloatArray, p: Params, form: str, u_hint: float) -> dict[str, FloatArray]:
    n = Y.shape[0]
    out = {k: np.empty(n) for k in ("theta_max", "theta_min", "k2", "period", "root_case", "E")}
    for i in range(n):
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

    A start at a turning point is not counted (spec §14). A compiled run located the zeros of
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


# ---------------------------------------------------------------------------------------------
# The registry entry.


def _check_method(p: Params, method: str) -> None:
    if method == "closed_form" and p.perturbed:
        raise ParameterError(
            "run.methods: closed_form is the unperturbed motion and cannot run with a "
            "[perturbation] (allowed for a perturbed run: full, averaged)"
        )
    if method == "averaged" and not p.perturbed:
        raise ParameterError(
            "run.methods: averaged needs a [perturbation] with eps > 0 "
            "(allowed for an unperturbed run: full, closed_form)"
        )


def validity(p: Params, st: State, slow: SlowPath, t_end: float) -> list[ValidityIssue]:
    """Where an averaged trajectory loses accuracy (spec §10, §11), with the first time.

    ``near_separatrix``: 1 − k² < ``NEAR_SEPARATRIX`` (the period grows like ln(1/(1 − k²))
    and averaging degrades before it fails at ``SEPARATRIX_TOL``). ``eps_not_small``: the slow
    time per nutation period ε·T exceeds ``EPS_PERIOD_LIMIT``. Both are the tool's judgement of
    the spec's "≪".

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
            "grows without bound and averaging loses accuracy (spec §11)",
        ),
        (
            "eps_not_small",
            lambda t: p.eps * cols(t)["period"] - EPS_PERIOD_LIMIT,
            f"ε·T > {EPS_PERIOD_LIMIT:g}: the slow variables change noticeably within one "
            "nutation period, so averaging is not accurate (envelope error O(ε·T), spec §10)",
        ),
    )
    for name, cond, message in checks:
        t0 = first_time(cond, grid)
        if t0 is not None:
            issues.append(ValidityIssue(name, t0, f"{message}; first at t = {t0:.6g}"))
    return issues


def limits(p: Params, st: State) -> dict[str, Json]:
    """The unperturbed orbit's constants (spec §14): root case, roots, k², E, θmin, θmax, T,
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
    (2.2) is what the averaged method predicts, spec §10); R and G: |full − averaged| at the
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
_R = Column("R", "reduced axial momentum R = Cr/A", "1/t", "§1")
_G = Column("G", "reduced momentum about e_z, G = K·e_z/A", "1/t", "§1")
_A = Column("a", "sinθ coefficient a(τ) of M0/A", "1/t^2", "(1.5), §9")
_B = Column("b", "sin2θ coefficient b(τ) of M0/A", "1/t^2", "(1.5), §9")
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
_DIAGNOSTICS = (
    Column("k2", "modulus squared k² of the nutation", "1", "§4"),
    Column("period", "nutation period T", "t", "§4"),
    Column("root_case", "root case (1: four real roots, 2: a complex pair)", "1", "§3"),
    Column("E", "energy H of (1.6) along the averaged solution", "1/t^2", "(1.6), §7"),
)


def _full_columns(p: Params) -> tuple[Column, ...]:
    # A perturbed run also writes the moment coefficients and the slow time.
    return _PERTURBED_FULL if p.perturbed else _UNPERTURBED


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
    to_columns=slow_from_full,
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

# ---------------------------------------------------------------------------------------------
# Scenario keys.

_PARAMETERS = Section(
    "parameters",
    (
        Key("mu", "number", "C/A, a number in (0, 2]"),
        Key("a", "number", "sinθ coefficient of M0/A at t = 0, a finite number", "1/t^2"),
        Key("b", "number", "sin2θ coefficient of M0/A at t = 0, a finite number", "1/t^2"),
    ),
    doc="the body and the moment M0/A = a sinθ + b sin2θ at t = 0",
)
_PERTURBATION = Section(
    "perturbation",
    (
        Key("eps", "number", "a number in (0, 1)", doc="ε: the slow time is τ = εt"),
        Key("d", "number", "pitch damping, a finite number", "1/t", 0.0),
        Key("nu", "number", "roll damping, a finite number", "1/t", 0.0),
        Key(
            "pressure",
            "any",
            '"constant", "exp", a table [[τ, Q], ...] or {tau = [...], Q = [...]}',
            default="constant",
            doc="Q(τ): the moment scales as a(τ) = a·Q(τ)/Q(0), b(τ) likewise",
        ),
    ),
    required=False,
    doc="damping and a varying dynamic pressure (absent: the unperturbed motion)",
)
_PRESSURE_TABLE = Section(
    "pressure",
    (
        Key("tau", "numbers", "ascending slow times τ = εt, from ≤ 0"),
        Key("Q", "numbers", "pressure values > 0, one per τ"),
    ),
)
_INITIAL = Section(
    "initial",
    (
        Key("theta", "number", "an angle in (0, π)", "rad", angle=True, doc="nutation angle θ"),
        Key("theta_dot", "number", "θ' at t = 0, a finite number", "rad/t", 0.0),
        Key("psi", "number", "an angle", "rad", 0.0, angle=True),
        Key("phi", "number", "an angle", "rad", 0.0, angle=True),
        Key("R", "number", "R = Cr/A, a finite number", "1/t", 0.0),
        Key("G", "number", "G = K·e_z/A, a finite number", "1/t", 0.0),
    ),
    doc="the initial state (θ, θ', ψ, φ) and the momenta R, G",
)


def _pressure_of(value: Any, inputs: Inputs) -> Pressure:
    """``perturbation.pressure`` as a :class:`Pressure`: a name, [[τ, Q], ...] or a table."""
    where = "perturbation.pressure"
    if isinstance(value, str):
        if value not in ("constant", "exp"):
            raise ScenarioError(
                f"{where} = {shorten(repr(value), 60)}: expected "
                '"constant", "exp", a table [[τ, Q], ...] or {tau = [...], Q = [...]}'
            )
        return Pressure(value)  # type: ignore[arg-type]
    if isinstance(value, dict):
        table = inputs.validate(_PRESSURE_TABLE, value, "perturbation")
        return Pressure("table", tuple(table["tau"]), tuple(table["Q"]))

    def number(x: Any) -> bool:
        return isinstance(x, int | float) and not isinstance(x, bool)

    if not isinstance(value, list) or not all(
        isinstance(row, list) and len(row) == 2 and all(map(number, row)) for row in value
    ):
        raise ScenarioError(f"{where}: a table is a list of [τ, Q] pairs of numbers")
    return Pressure("table", tuple(float(r[0]) for r in value), tuple(float(r[1]) for r in value))


def _build(inputs: Inputs) -> Built[Params, State]:
    par, pert, ini = inputs["parameters"], inputs["perturbation"], inputs["initial"]
    assert par is not None and ini is not None  # required sections
    if pert is not None and not (math.isfinite(pert["eps"]) and 0.0 < pert["eps"] < 1.0):
        raise ParameterError(
            f"perturbation.eps = {pert['eps']:g} is outside the allowed range (0, 1)"
        )
    p = Params(
        mu=par["mu"],
        a=par["a"],
        b=par["b"],
        eps=pert["eps"] if pert else 0.0,
        d=pert["d"] if pert else 0.0,
        nu=pert["nu"] if pert else 0.0,
        pressure=_pressure_of(pert["pressure"], inputs) if pert else Pressure(),
    )
    names = ("theta", "theta_dot", "psi", "phi", "R", "G")
    st = State(**{n: ini[n] for n in names})
    t_end = inputs.run_end()
    if p.eps * t_end > p.pressure.tau_max:
        raise ParameterError(
            f"perturbation.pressure table covers τ ≤ {p.pressure.tau_max:g}, but the run "
            f"reaches τ = eps·t = {p.eps * t_end:g}"
        )
    orbit_of(p, st)  # no motion (e.g. a separatrix) → one line, before any run
    methods = ("full", "averaged") if p.perturbed else ("full", "closed_form")
    return Built(p, st, methods=methods)


SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant((_PARAMETERS, _PERTURBATION, _INITIAL), _build, samples=2001, doc="the paper's t"),
    )
)


_ENTRY = CATALOGUE["nonlinear_moment"]  # name, description and paper

MODEL: Model[Params, State] = Model(
    name=_ENTRY.name,
    description=_ENTRY.description,
    paper=_ENTRY.paper,
    time=Column("t", "time t", "t"),
    full=Full(
        forms={"quaternion": FULL_QUATERNION, "reduced": FULL_REDUCED},
        default="quaternion",
        columns=_full_columns,
    ),
    check=_check_method,
    methods=("full", "closed_form", "averaged"),
    averaged=Averaged(
        form=_averaged_form,
        columns=fixed_columns(_AVERAGED),
        coordinates=("energy", "theta_max", "theta_min"),
        corrected_start=True,
        numeric=True,
        errors=slow_errors,
        diagnostics=Diagnostics(_diagnostics, _DIAGNOSTICS),
    ),
    closed_form=ClosedForm(evaluate=closed_form, columns=fixed_columns(_UNPERTURBED)),
    unperturbed=Unperturbed(
        "(1.9)-(1.13)", exact_motion, lambda t, y, p: full_rhs(t, y, p.unperturbed())
    ),
    validity=Validity(check=validity, limits=limits),
    report=report,
    scenario=SCENARIO,
)
