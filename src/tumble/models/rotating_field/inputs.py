"""The rotating-field model's inputs: parameters, initial state, physical units and scenario
keys, apart from its numerics (:mod:`tumble.models.rotating_field`).

Martynenko (1979); the nondimensional variables of (1.5): time τ = ωt, body angular velocity
z = Ω/ω, the rotation Γ from the body to the field frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.bodies import RigidBody, proper_sorting
from tumble.errors import ParameterError, ScenarioError, check_range
from tumble.models.base import TIME_TAU, Declaration, frozen_array
from tumble.models.schema import Built, Inputs, Key, ScenarioSchema, Section, Variant, required
from tumble.rotations import euler313_to_matrix, kframe_matrix, matrix_to_quat, quat_to_matrix
from tumble.torques import EddyCurrentTorque

__all__ = [
    "DECLARED",
    "GAMMA_TOL",
    "SCENARIO",
    "Params",
    "PhysicalParams",
    "Scaling",
    "State",
    "normalize_physical",
    "state_from_elements",
]

GAMMA_TOL = 1e-9
"""An initial Γ is accepted as a rotation when |Γ Γᵀ − E| ≤ this (then re-orthonormalized)."""


@dataclass(frozen=True, eq=False)
class Params:
    """Nondimensional parameters of (1.5), docs/theory/rotating-field.md §4.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments (I1, I2, I3) in the user's axis labels, in the same unit as ``eps``
        [inertia unit]; positive and satisfying the triangle inequality (a thin plate
        I3 = I1 + I2 is allowed). The stationary rotation analysed is about x3.
    beta : float
        Angle between the field and its rotation axis ξ3 [rad], in [0, π] (β = 0: a static field
        along ξ3; β = π/2: a field rotating in a plane).
    eps : float
        ε = M0/ω = k_f H²/ω > 0 [inertia unit]; the small parameter is ε/I_i.
    """

    inertia: FloatArray
    beta: float
    eps: float
    # Derived once: the right-hand sides run at every step.
    sorting: FloatArray = field(init=False, repr=False)  # S: v_sorted = S v_user, det S = +1
    sorted_inertia: tuple[float, float, float] = field(init=False, repr=False)
    hh: FloatArray = field(init=False, repr=False)  # ĥĥ = hhᵀ − E in the field frame
    torque: EddyCurrentTorque = field(init=False, repr=False)
    packed: FloatArray = field(init=False, repr=False)  # [I, ε, ĥĥ]: the kernel's parameters

    def __post_init__(self) -> None:
        inertia = frozen_array("parameters.inertia", self.inertia, (3,))
        RigidBody(*inertia.tolist())  # positive, triangle inequality
        check_range(
            "parameters.beta",
            float(self.beta),
            low=0.0,
            high=math.pi,
            low_open=False,
            high_open=False,
        )
        check_range("parameters.eps", float(self.eps), low=0.0)
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "beta", float(self.beta))
        object.__setattr__(self, "eps", float(self.eps))
        S = proper_sorting(inertia)
        S.setflags(write=False)
        object.__setattr__(self, "sorting", S)
        srt = np.abs(S) @ inertia
        object.__setattr__(self, "sorted_inertia", tuple(float(v) for v in srt))
        # ĥĥ = h hᵀ − E for h = (sin β, 0, cos β), with −cos²β and −sin²β written directly
        # (1 − sin²β by subtraction loses relative accuracy for β near 0 or π).
        sb, cb = math.sin(self.beta), math.cos(self.beta)
        hh = np.array([[-cb * cb, 0.0, sb * cb], [0.0, -1.0, 0.0], [sb * cb, 0.0, -sb * sb]])
        hh.setflags(write=False)
        object.__setattr__(self, "hh", hh)
        object.__setattr__(self, "torque", EddyCurrentTorque(self.eps, 1.0, self.beta))
        packed = np.concatenate([inertia, [float(self.eps)], hh.ravel()])
        object.__setattr__(self, "packed", packed)

    @property
    def s2(self) -> float:
        """sin²β [1]."""
        return math.sin(self.beta) ** 2

    @property
    def c2(self) -> float:
        """cos²β [1]."""
        return math.cos(self.beta) ** 2

    @property
    def small_parameter(self) -> float:
        """ε / min I_i: the true small parameter of the averaging (§4) [1]."""
        return self.eps / float(np.min(self.inertia))

    def derived(self) -> dict[str, float]:
        """ε/min I and ω0² of (2.6), for summaries."""
        I1, I2, I3 = self.inertia.tolist()
        return {
            "small_parameter": self.small_parameter,
            "omega0_squared": (I3 - I2) * (I3 - I1) / (I1 * I2),
        }

    def with_eps(self, eps: float) -> Params:
        """The same body and field with another ε."""
        return Params(self.inertia, self.beta, eps)


def _as_rotation(name: str, gamma: ArrayLike) -> FloatArray:
    G = frozen_array(name, gamma, (3, 3))
    defect = float(np.max(np.abs(G @ G.T - np.eye(3))))
    if defect > GAMMA_TOL or np.linalg.det(G) <= 0.0:
        raise ParameterError(
            f"{name} is not a rotation matrix: max |Γ Γᵀ − E| = {defect:.3g} (allowed ≤ "
            f"{GAMMA_TOL:g}) and det Γ = {np.linalg.det(G):.6g} (must be +1)"
        )
    G = quat_to_matrix(matrix_to_quat(G))  # the nearest rotation, to round-off
    G.setflags(write=False)
    return G


@dataclass(frozen=True, eq=False)
class State:
    """A full state at τ = 0, §16.

    Parameters
    ----------
    z : array_like, shape (3,)
        Body absolute angular velocity over the field rate, Ω/ω, user axes [1].
    gamma : array_like, shape (3, 3)
        Γ: body → field frame (v_η = Γ v_x); at τ = 0 the field frame is the inertial one.
        A rotation to within :data:`GAMMA_TOL`.
    """

    z: FloatArray
    gamma: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "z", frozen_array("initial.z", self.z, (3,)))
        object.__setattr__(self, "gamma", _as_rotation("initial.gamma", self.gamma))


# ---------------------------------------------------------------------------------------------
# Initial states from the slow elements, §9.


def _rate_from_elements(
    inertia: tuple[float, float, float], L: float, k2: float, regime: str, u: float
) -> FloatArray:
    """Body angular velocity (3.1) at phase u, sorted axes; regime x1 by the index swap."""
    I1, I2, I3 = inertia
    from scipy.special import ellipj  # loaded for a state given by its elements only

    sn, cn, dn, _ = ellipj(u, k2)
    k = math.sqrt(k2)
    if regime == "x3":
        I0 = I3 * (I2 - I1) + I1 * (I3 - I2) * k2
        return np.array(
            [
                L * k * math.sqrt((I3 - I2) / (I1 * I0)) * cn,
                L * k * math.sqrt((I3 - I1) / (I2 * I0)) * sn,
                L * math.sqrt((I2 - I1) / (I3 * I0)) * dn,
            ]
        )
    # Regime x1: indices 1 and 3 swapped; every ratio below is of two negatives (correction C7).
    I0 = I1 * (I2 - I3) + I3 * (I1 - I2) * k2
    return np.array(
        [
            L * math.sqrt((I2 - I3) / (I1 * I0)) * dn,
            L * k * math.sqrt((I1 - I3) / (I2 * I0)) * sn,
            L * k * math.sqrt((I1 - I2) / (I3 * I0)) * cn,
        ]
    )


def state_from_elements(
    p: Params,
    L: float,
    rho: float,
    sigma: float,
    k2: float,
    regime: Literal["x3", "x1"] = "x3",
    *,
    u0: float = 0.0,
    psi0: float = 0.0,
) -> State:
    """A full state with prescribed slow elements, §9.

    z is (3.1) at phase ``u0``; Γ(0) = C(σ, ρ) Rz(ψ0) Rx(θ) Rz(φ) P, where C(σ, ρ) takes ζ3 to
    the direction of L (§9), (ψ0, θ, φ) are the classical Euler angles of the body relative to
    the ζ frame (body components of ``L/|L|`` = (sin θ sin φ, sin θ cos φ, cos θ) in the axes P
    that make the polhode's polar axis the third), and ψ0 is the precession phase.

    Parameters
    ----------
    p : Params
    L : float
        Angular momentum ``|Iz|`` > 0 [inertia unit].
    rho, sigma : float
        Polar angle of L from ξ3, in [0, π], and its inertial azimuth [rad].
    k2 : float
        Modulus squared of the regime, in [0, 1] [1].
    regime : {"x3", "x1"}
        The axis (largest / smallest moment) the angular momentum encircles in the body.
    u0 : float
        Phase u = ν(τ − τ0) of (3.1) at τ = 0 [1].
    psi0 : float
        Precession phase of the body about L at τ = 0 [rad].
    """
    check_range("initial.L", L, low=0.0)
    check_range("initial.rho", rho, low=0.0, high=math.pi, low_open=False, high_open=False)
    check_range("initial.sigma", sigma)
    check_range("initial.k2", k2, low=0.0, high=1.0, low_open=False, high_open=False)
    check_range("initial.u0", u0)
    check_range("initial.psi0", psi0)
    if regime not in ("x3", "x1"):
        raise ParameterError(f'initial.regime = {regime!r} must be "x3" or "x1"')
    I1, I2, I3 = p.sorted_inertia
    if (regime == "x3" and I1 == I2) or (regime == "x1" and I2 == I3) or I1 == I3:
        raise ParameterError(
            f"initial.k2 does not fix the energy of a body with equal moments {p.inertia.tolist()} "
            f"in regime {regime}: give initial.z and initial.gamma instead"
        )
    z_sorted = _rate_from_elements(p.sorted_inertia, L, k2, regime, u0)
    Ls = np.array(p.sorted_inertia) * z_sorted
    # Axes whose third is the polar axis: identity for x3; cyclic (x2, x3, x1) for x1.
    P = np.eye(3) if regime == "x3" else np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0, 0]])
    e = P @ Ls / L
    theta = math.atan2(math.hypot(e[0], e[1]), e[2])
    phi = math.atan2(e[0], e[1])
    G_sorted = kframe_matrix(rho, sigma) @ euler313_to_matrix(psi0, theta, phi) @ P
    S = p.sorting
    return State(S.T @ z_sorted, G_sorted @ S)


# ---------------------------------------------------------------------------------------------
# Physical units, §4.


@dataclass(frozen=True, eq=False)
class PhysicalParams:
    """The body and the field in SI units.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments [kg·m²].
    k_f : float
        Eddy-current factor of (1.2) [N·m·s/(A/m)²], > 0.
    H : float
        Field strength [A/m], > 0.
    omega : float
        Field rotation rate [rad/s], > 0.
    beta : float
        Field cone angle [rad], in [0, π].
    """

    inertia: FloatArray
    k_f: float
    H: float
    omega: float
    beta: float

    def __post_init__(self) -> None:
        inertia = frozen_array("physical.inertia", self.inertia, (3,))
        RigidBody(*inertia.tolist())
        object.__setattr__(self, "inertia", inertia)
        check_range("physical.k_f", self.k_f, low=0.0)
        check_range("physical.H", self.H, low=0.0)
        check_range("physical.omega", self.omega, low=0.0)


@dataclass(frozen=True)
class Scaling:
    """τ = ω t, z = Ω/ω, moments over I_ref = max I_i, ε = k_f H²/(ω I_ref) (§4)."""

    omega: float  # [rad/s]
    I_ref: float  # [kg·m²]
    eps: float  # [1]

    def tau_from_time(self, t_s: ArrayLike) -> FloatArray:
        """τ = ω t for times in seconds."""
        return np.asarray(t_s, dtype=float) * self.omega

    def time_from_tau(self, tau: ArrayLike) -> FloatArray:
        """t = τ/ω [s]."""
        return np.asarray(tau, dtype=float) / self.omega

    def summary(self) -> dict[str, float]:
        """The scales, for summary.json."""
        return {"omega_rad_s": self.omega, "I_ref_kgm2": self.I_ref, "eps": self.eps}

    def si(self, name: str) -> tuple[float, str, str] | None:
        """(factor, SI unit, SI name) of an output column: L [kg m²/s], T [J], the body rate
        Ω = ωz and the frequencies ν [rad/s]."""
        if name == "L":
            return self.I_ref * self.omega, "kg m²/s", "L_kgm2_s"
        if name == "T":
            return self.I_ref * self.omega**2, "J", "T_J"
        if name in ("z1", "z2", "z3"):
            return self.omega, "rad/s", f"Omega{name[1]}_rad_s"
        if name in ("omega1", "omega2", "omega3", "nu1", "nu2"):
            return self.omega, "rad/s", f"{name}_rad_s"
        return None


def normalize_physical(
    phys: PhysicalParams, Omega0: ArrayLike, gamma0: ArrayLike
) -> tuple[Params, State, Scaling]:
    """Nondimensional parameters and initial state of a physical scenario (§4).

    Parameters
    ----------
    phys : PhysicalParams
    Omega0 : array_like, shape (3,)
        Body angular velocity at t = 0 [rad/s].
    gamma0 : array_like, shape (3, 3)
        Body → inertial rotation at t = 0 (rows).

    Returns
    -------
    (Params, State, Scaling)
    """
    I_ref = float(np.max(phys.inertia))
    eps = phys.k_f * phys.H**2 / (phys.omega * I_ref)
    p = Params(phys.inertia / I_ref, phys.beta, eps)
    st = State(frozen_array("initial.Omega", Omega0, (3,)) / phys.omega, gamma0)
    return p, st, Scaling(phys.omega, I_ref, eps)


# ---------------------------------------------------------------------------------------------
# Scenario keys.

_PARAMETERS = Section(
    "parameters",
    (
        Key("inertia", "vector3", "3 principal moments > 0 obeying the triangle inequality"),
        Key(
            "beta",
            "number",
            "an angle in [0, π]",
            "rad",
            angle=True,
            doc="angle between the field and its rotation axis",
        ),
        Key("eps", "number", "a number > 0", doc="ε = M0/ω"),
    ),
    doc="the body and the field, normalized by the field's rate",
)
_INITIAL = Section(
    "initial",
    (
        Key("z", "vector3", "body angular velocity over ω, 3 numbers", default=None),
        Key("gamma", "matrix3", "3 rows of the rotation Γ (v_η = Γ v_x)", default=None),
        Key("L", "number", "a number > 0", default=None, doc="|L|"),
        Key("rho", "number", "an angle in [0, π]", "rad", None, angle=True),
        Key("sigma", "number", "an angle", "rad", None, angle=True),
        Key("k2", "number", "a number in [0, 1]", default=None, doc="Euler–Poinsot modulus"),
        Key("regime", "text", '"x3" or "x1"', default="x3", choices=("x3", "x1")),
        Key("u0", "number", "a phase u of (3.1)", default=0.0),
        Key("psi0", "number", "an angle", "rad", 0.0, angle=True),
    ),
    doc="z and Γ, or the slow elements L, ρ, σ, k² with the regime and phases",
)
_PHYSICAL = Section(
    "physical",
    (
        Key("inertia", "vector3", "3 principal moments > 0", "kg m^2"),
        Key("k_f", "number", "eddy-current factor > 0", "N m s/(A/m)^2"),
        Key("H", "number", "field strength > 0", "A/m"),
        Key("omega", "number", "field rotation rate > 0", "rad/s"),
        Key("beta", "number", "an angle in [0, π]", "rad", angle=True),
    ),
    doc="the body and the field in SI units",
)
_PHYSICAL_INITIAL = Section(
    "initial",
    (
        Key("Omega", "vector3", "body angular velocity, 3 numbers", "rad/s"),
        Key("gamma", "matrix3", "3 rows of the body → inertial rotation"),
    ),
)


def _initial_state(p: Params, ini: Mapping[str, Any]) -> State:
    elements = ("L", "rho", "sigma", "k2")
    given = [n for n in elements if ini[n] is not None]
    direct = [n for n in ("z", "gamma") if ini[n] is not None]
    if direct and given:
        raise ScenarioError(
            "initial: give either z and gamma, or the slow elements L, rho, sigma, k2 "
            f"(with regime, u0, psi0), not both (got {', '.join(direct + given)})"
        )
    if direct:
        if len(direct) != 2:
            raise ScenarioError("initial: z and gamma go together (give both)")
        return State(np.array(ini["z"]), np.array(ini["gamma"]))
    if len(given) != len(elements):
        missing = [n for n in elements if n not in given]
        raise ScenarioError(
            "initial: give z and gamma, or all of L, rho, sigma, k2 "
            f"(missing: {', '.join(missing)})"
        )
    L, rho, sigma, k2 = (float(ini[n]) for n in elements)
    return state_from_elements(p, L, rho, sigma, k2, ini["regime"], u0=ini["u0"], psi0=ini["psi0"])


def _build(inputs: Inputs) -> Built[Params, State]:
    par, ini = required(inputs, "parameters", "initial")
    p = Params(par["inertia"], par["beta"], par["eps"])
    return Built(p, _initial_state(p, ini))


def _build_physical(inputs: Inputs) -> Built[Params, State]:
    ph, ini = required(inputs, "physical", "initial")
    phys = PhysicalParams(ph["inertia"], ph["k_f"], ph["H"], ph["omega"], ph["beta"])
    p, st, scaling = normalize_physical(phys, ini["Omega"], ini["gamma"])
    return Built(p, st, scaling)


SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant((_PARAMETERS, _INITIAL), _build, doc="normalized by the field's rate (τ = ωt)"),
        Variant((_PHYSICAL, _PHYSICAL_INITIAL), _build_physical, physical=True, doc="SI units"),
    )
)


def _check_method(p: Params, method: str) -> None:
    """Every method applies to every valid parameter set (ε = 0 averages to no evolution)."""


DECLARED: Declaration[Params, State] = Declaration(
    name="rotating_field",
    time=TIME_TAU,
    methods=("full", "averaged"),
    check=_check_method,
    scenario=SCENARIO,
    numeric=True,
    orders=(1, 2),
    hybrid=True,  # across the resonances and the separatrix (tumble.models.triaxial_mean)
)
"""What a scenario of the model may ask for."""
