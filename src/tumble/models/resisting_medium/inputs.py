"""The resisting-medium model's inputs: parameters, initial state, physical units and scenario
keys, apart from its numerics (:mod:`tumble.models.resisting_medium`).

Medvedev (1987); the normalized variables of (1.3): time τ, angular momentum k = |K|/K0,
inertia I1 = 1, I3 = 1 + κ, moment ε m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from tumble._typing import ArrayLike, FloatArray, Json
from tumble.bodies import RigidBody
from tumble.errors import ParameterError, ScenarioError, check_finite, check_range
from tumble.kernels import Kernel
from tumble.models.base import TIME_TAU, Declaration, frozen_array
from tumble.models.schema import Built, Inputs, Key, ScenarioSchema, Section, Variant, required
from tumble.rotations import kframe_angles_from_attitude, quat_to_matrix
from tumble.torques import ConstantBodyTorque, LinearDrag, QuadraticDrag, Torque

__all__ = [
    "DECLARED",
    "SCENARIO",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "normalize_physical",
]


@dataclass(frozen=True, eq=False)
class Params:
    """Normalized parameters of (1.3), docs/theory/resisting-medium.md §4.

    Parameters
    ----------
    eps : float
        Small parameter ε = M0 I1 / K0² [1], ε ≥ 0 (0 gives the free Euler–Poinsot motion).
    kappa : float
        Oblateness κ with I3 = I1 (1 + κ) [1], in (−1, 1] (triangle inequality).
    a : array_like, shape (3,)
        Constant body-fixed moment a_i = A_i / M0 [1].
    b : array_like, shape (3, 3)
        Linear drag b_ij = B_ij / (M0 T0) [1]; any sign, off-diagonal entries allowed.
    s : array_like, shape (3, 3)
        Quadratic drag s_ij = S_ij / (M0 T0²) [1].
    """

    eps: float
    kappa: float
    a: FloatArray = field(default_factory=lambda: np.zeros(3))
    b: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    s: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))

    def __post_init__(self) -> None:
        check_range("parameters.eps", float(self.eps), low=0.0, low_open=False)
        check_range("parameters.kappa", float(self.kappa), low=-1.0, high=1.0, high_open=False)
        object.__setattr__(self, "eps", float(self.eps))
        object.__setattr__(self, "kappa", float(self.kappa))
        object.__setattr__(self, "a", frozen_array("parameters.a", self.a, (3,)))
        object.__setattr__(self, "b", frozen_array("parameters.b", self.b, (3, 3)))
        object.__setattr__(self, "s", frozen_array("parameters.s", self.s, (3, 3)))

    # Combinations of (2.2), §6.
    @property
    def alpha(self) -> float:
        """α = (b11 + b22)/2 of (2.2) [1]."""
        return 0.5 * float(self.b[0, 0] + self.b[1, 1])

    @property
    def beta(self) -> float:
        """β = b33/(1 + κ) of (2.2) [1]."""
        return float(self.b[2, 2]) / (1.0 + self.kappa)

    @property
    def gamma(self) -> float:
        """γ = 4 (s11 + s22)/(3π) of (2.2), correction E6 [1]."""
        return 4.0 * float(self.s[0, 0] + self.s[1, 1]) / (3.0 * math.pi)

    @property
    def delta(self) -> float:
        """δ = s33/(1 + κ)² of (2.2) [1]."""
        return float(self.s[2, 2]) / (1.0 + self.kappa) ** 2

    def derived(self) -> dict[str, float]:
        """The combinations α, β, γ, δ of (2.2), for summaries."""
        return {"alpha": self.alpha, "beta": self.beta, "gamma": self.gamma, "delta": self.delta}

    # Built on first use (the right-hand sides call them at every evaluation), not when a
    # scenario is read.
    @cached_property
    def inertia(self) -> FloatArray:
        """Normalized principal moments (1, 1, 1 + κ)."""
        return np.array([1.0, 1.0, 1.0 + self.kappa])

    @cached_property
    def torque(self) -> Torque:
        """The moment ε m of (1.2) in normalized units, as a composable torque."""
        moment = ConstantBodyTorque(self.a) + LinearDrag(self.b) + QuadraticDrag(self.s)
        return self.eps * moment

    @cached_property
    def kernel(self) -> Kernel:
        """The full equations (1.2) compiled: Euler + quaternions with ε m."""
        from tumble.dynamics import rigid_body_kernel  # compiled code: loaded for a run

        kernel = rigid_body_kernel(self.inertia, self.torque)
        assert kernel is not None  # (1.2) is built of compiled terms only
        return kernel

    def with_eps(self, eps: float) -> Params:
        """The same medium at another ε (for error studies)."""
        return replace(self, eps=eps)


@dataclass(frozen=True)
class State:
    """Slow and fast variables (k, ρ, σ, ψ, ϑ, φ) of (1.3), §2 conventions [1, rad]."""

    k: float
    rho: float
    sigma: float
    psi: float
    theta: float
    phi: float

    def __post_init__(self) -> None:
        check_range("initial.k", self.k, low=0.0)
        check_range(
            "initial.theta", self.theta, low=0.0, high=math.pi, low_open=False, high_open=False
        )
        check_range("initial.rho", self.rho, low=0.0, high=math.pi, low_open=False, high_open=False)
        for name in ("sigma", "psi", "phi"):
            check_finite(f"initial.{name}", getattr(self, name))

    @property
    def W(self) -> float:
        """Axial component k cos ϑ of (2.3)."""
        return self.k * math.cos(self.theta)

    @property
    def V(self) -> float:
        """Equatorial component k sin ϑ ≥ 0 of (2.3)."""
        return self.k * math.sin(self.theta)


def _check_method(p: Params, method: str) -> None:
    if method in ("averaged", "closed_form") and p.kappa == 0.0:
        raise ParameterError(
            "parameters.kappa = 0 is outside the allowed range for the averaged and closed_form "
            "methods (κ ≠ 0: a spherical inertia ellipsoid has no fast spin φ, §10.5); "
            'use methods = ["full"]'
        )


# ---------------------------------------------------------------------------------------------
# Physical units, §4.


@dataclass(frozen=True, eq=False)
class PhysicalParams:
    """The body and the medium in SI units, converted with the scaling of §4.

    Parameters
    ----------
    I1, I3 : float
        Equatorial and polar moments of inertia [kg·m²], I3 ≤ 2 I1.
    A : array_like, shape (3,)
        Constant body-fixed moment [N·m].
    B : array_like, shape (3, 3)
        Linear drag [N·m·s].
    S : array_like, shape (3, 3)
        Quadratic drag [N·m·s²].
    M0 : float, optional
        Moment scale [N·m]; default max(|A_i|, |B_ij|/T0, |S_ij|/T0²) (§4).
    """

    I1: float
    I3: float
    A: FloatArray = field(default_factory=lambda: np.zeros(3))
    B: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    S: FloatArray = field(default_factory=lambda: np.zeros((3, 3)))
    M0: float | None = None

    def __post_init__(self) -> None:
        RigidBody.symmetric(self.I1, self.I3)  # positivity and the triangle inequality
        object.__setattr__(self, "A", frozen_array("physical.A", self.A, (3,)))
        object.__setattr__(self, "B", frozen_array("physical.B", self.B, (3, 3)))
        object.__setattr__(self, "S", frozen_array("physical.S", self.S, (3, 3)))
        if self.M0 is not None:
            check_range("physical.M0", self.M0, low=0.0)


@dataclass(frozen=True)
class Scaling:
    """Scales of §4: K = K0 k, t = T0 τ, M = M0 m, ε = M0 I1 / K0²."""

    K0: float  # [N·m·s]
    T0: float  # [s]
    M0: float  # [N·m]
    eps: float  # [1]

    def tau_from_time(self, t_s: ArrayLike) -> FloatArray:
        """τ = t / T0 for times in seconds."""
        return np.asarray(t_s, dtype=float) / self.T0

    def time_from_tau(self, tau: ArrayLike) -> FloatArray:
        """t = T0 τ [s]."""
        return np.asarray(tau, dtype=float) * self.T0

    def si(self, name: str) -> tuple[float, str, str] | None:
        """(factor, SI unit, SI name) of an output column: k → K [N m s], ω [rad/s]."""
        if name == "k":
            return self.K0, "N m s", "K_Nms"
        if name in ("omega1", "omega2", "omega3"):
            return 1.0 / self.T0, "rad/s", f"{name}_rad_s"
        return None

    def summary(self) -> dict[str, float]:
        """The scales, for summary.json."""
        return {"K0_Nms": self.K0, "T0_s": self.T0, "M0_Nm": self.M0, "eps": self.eps}


def normalize_physical(
    phys: PhysicalParams,
    omega0: ArrayLike,
    *,
    attitude: ArrayLike | None = None,
    rho: float | None = None,
    sigma: float | None = None,
    psi: float | None = None,
) -> tuple[Params, State, Scaling]:
    """Normalized parameters and initial state of a physical scenario, §4.

    K0 = |K(0)| (so k0 = 1), T0 = I1/K0, M0 as in :class:`PhysicalParams`, ε = M0 I1/K0²,
    a = A/M0, b = B/(M0 T0), s = S/(M0 T0²), κ = I3/I1 − 1.

    Parameters
    ----------
    phys : PhysicalParams
        Body and medium [SI].
    omega0 : array_like, shape (3,)
        Initial body angular velocity (P0, Q0, R0) [rad/s]; not zero.
    attitude : array_like, shape (4,), optional
        Initial attitude quaternion (scalar first, body → inertial). Either this, or
    rho, sigma, psi : float, optional
        the direction of K in the inertial frame and the precession angle [rad]; ϑ0, φ0 always
        come from the direction of K in the body.

    Returns
    -------
    (Params, State, Scaling)
    """
    w0 = frozen_array("initial.omega", omega0, (3,))
    Kb = np.array([phys.I1, phys.I1, phys.I3]) * w0
    K0 = float(np.linalg.norm(Kb))
    if K0 == 0.0:
        raise ParameterError("initial.omega = [0, 0, 0]: the body must rotate (K0 = |K(0)| > 0)")
    T0 = phys.I1 / K0
    M0 = phys.M0
    if M0 is None:
        M0 = max(
            float(np.max(np.abs(phys.A))),
            float(np.max(np.abs(phys.B))) / T0,
            float(np.max(np.abs(phys.S))) / T0**2,
        )
        if M0 == 0.0:
            M0 = K0 / T0  # a free body: any scale will do
    p = Params(
        eps=M0 * phys.I1 / K0**2,
        kappa=phys.I3 / phys.I1 - 1.0,
        a=phys.A / M0,
        b=phys.B / (M0 * T0),
        s=phys.S / (M0 * T0**2),
    )
    theta0 = math.atan2(math.hypot(Kb[0], Kb[1]), Kb[2])
    phi0 = math.atan2(Kb[0], Kb[1])
    if attitude is not None:
        R = quat_to_matrix(frozen_array("initial.quaternion", attitude, (4,)))
        r, sg, ps, _, _ = kframe_angles_from_attitude(R, R @ Kb)
        st = State(1.0, float(r), float(sg), float(ps), theta0, phi0)
    else:
        if rho is None or sigma is None or psi is None:
            raise ParameterError("initial: give either quaternion or all of rho, sigma, psi")
        st = State(1.0, rho, sigma, psi, theta0, phi0)
    return p, st, Scaling(K0=K0, T0=T0, M0=M0, eps=p.eps)


_ANGLE_0_PI = "an angle in [0, π]"
_ZERO3: list[Json] = [0.0, 0.0, 0.0]
_ZERO33: list[Json] = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]

_PARAMETERS = Section(
    "parameters",
    (
        Key("eps", "number", "a number ≥ 0", doc="small parameter ε = M0 I1/K0²"),
        Key("kappa", "number", "a number in (-1, 1]", doc="oblateness κ, I3 = I1 (1 + κ)"),
        Key("a", "vector3", "3 numbers", default=_ZERO3, doc="constant body moment A/M0"),
        Key("b", "matrix3", "3×3", default=_ZERO33, doc="linear drag B/(M0 T0)"),
        Key("s", "matrix3", "3×3", default=_ZERO33, doc="quadratic drag S/(M0 T0²)"),
    ),
    doc="the normalized parameters of (1.3)",
)
_INITIAL = Section(
    "initial",
    (
        Key("k", "number", "a number > 0", default=1.0, doc="angular momentum |K|/K0"),
        Key("rho", "number", _ANGLE_0_PI, "rad", 0.0, angle=True, doc="polar angle ρ of K"),
        Key("sigma", "number", "an angle", "rad", 0.0, angle=True, doc="azimuth σ of K"),
        Key("psi", "number", "an angle", "rad", 0.0, angle=True, doc="precession angle ψ"),
        Key("theta", "number", _ANGLE_0_PI, "rad", angle=True, doc="nutation angle ϑ"),
        Key("phi", "number", "an angle", "rad", 0.0, angle=True, doc="proper rotation φ"),
    ),
    doc="the initial state in the K-frame angles of §2",
)
_PHYSICAL = Section(
    "physical",
    (
        Key("I1", "number", "equatorial moment of inertia > 0", "kg m^2"),
        Key("I3", "number", "polar moment of inertia in (0, 2 I1]", "kg m^2"),
        Key("A", "vector3", "3 moments", "N m", _ZERO3, doc="constant body moment"),
        Key("B", "matrix3", "3×3", "N m s", _ZERO33, doc="linear drag"),
        Key("S", "matrix3", "3×3", "N m s^2", _ZERO33, doc="quadratic drag"),
        Key("M0", "number", "a moment scale > 0", "N m", None, doc="default: from A, B, S"),
    ),
    doc="the body and the medium in SI units",
)
_PHYSICAL_INITIAL = Section(
    "initial",
    (
        Key("omega", "vector3", "body angular velocity, 3 numbers", "rad/s"),
        Key("quaternion", "vector4", "attitude quaternion [q0, q1, q2, q3]", default=None),
        Key("rho", "number", _ANGLE_0_PI, "rad", None, angle=True),
        Key("sigma", "number", "an angle", "rad", None, angle=True),
        Key("psi", "number", "an angle", "rad", None, angle=True),
    ),
    doc="the body rate and its attitude (a quaternion, or the K-frame angles ρ, σ, ψ)",
)


def _build(inputs: Inputs) -> Built[Params, State]:
    par, ini = required(inputs, "parameters", "initial")
    p = Params(eps=par["eps"], kappa=par["kappa"], a=par["a"], b=par["b"], s=par["s"])
    angles = {n: ini[n] for n in ("k", "rho", "sigma", "psi", "theta", "phi")}
    return Built(p, State(**angles))


def _build_physical(inputs: Inputs) -> Built[Params, State]:
    ph, ini = required(inputs, "physical", "initial")
    phys = PhysicalParams(I1=ph["I1"], I3=ph["I3"], A=ph["A"], B=ph["B"], S=ph["S"], M0=ph["M0"])
    given = [n for n in ("rho", "sigma", "psi") if ini[n] is not None]
    if ini["quaternion"] is not None and given:
        raise ScenarioError("initial: give either quaternion or rho, sigma, psi, not both")
    if ini["quaternion"] is None and len(given) != 3:
        raise ScenarioError("initial: give the attitude as quaternion or as all of rho, sigma, psi")
    if ini["quaternion"] is not None and not np.any(ini["quaternion"]):
        raise ParameterError("initial.quaternion = [0, 0, 0, 0] is not a rotation")
    p, st, scaling = normalize_physical(
        phys, ini["omega"], attitude=ini["quaternion"], rho=ini["rho"], sigma=ini["sigma"],
        psi=ini["psi"],
    )  # fmt: skip
    return Built(p, st, scaling)


SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant((_PARAMETERS, _INITIAL), _build, doc="normalized variables (τ, k, ε)"),
        Variant((_PHYSICAL, _PHYSICAL_INITIAL), _build_physical, physical=True, doc="SI units"),
    )
)


DECLARED: Declaration[Params, State] = Declaration(
    name="resisting_medium",
    time=TIME_TAU,
    methods=("full", "averaged", "closed_form"),
    check=_check_method,
    scenario=SCENARIO,
    numeric=True,
    orders=(1, 2),
    hybrid=True,
    steps=True,
)
"""What a scenario of the model may ask for."""
