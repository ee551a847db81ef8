"""The nonlinear-moment model's inputs: parameters, the dynamic-pressure profile, initial
state and scenario keys, apart from its numerics (:mod:`tumble.models.nonlinear_moment`).

Serov (1991): μ = C/A, the moment M0/A = a·sinθ + b·sin2θ, the z–x–z Euler angles of the body
relative to the fixed axis e_z and the reduced momenta R = μr, G = K·e_z/A; the perturbation
of the entry capsule in slow time τ = εt.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError, ScenarioError, check_range, shorten
from tumble.models.base import TIME_T, Declaration
from tumble.models.schema import Built, Inputs, Key, ScenarioSchema, Section, Variant, required

if TYPE_CHECKING:
    from tumble.unperturbed.symmetric_body import NutationOrbit

__all__ = ["DECLARED", "SCENARIO", "Params", "Pressure", "State", "orbit_of"]


@dataclass(frozen=True)
class Pressure:
    """Dynamic-pressure profile Q(τ) of §9: constant, exponential Q = e^τ, a table, or
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
    """Parameters of (1.1)–(1.5) and of the perturbation of §9.

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
        """da/dτ, db/dτ = (a, b)·Q'(τ)/Q(0) [1/t²] (Φ_a, Φ_b of §9)."""
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
    """A state at t = 0, §14: Euler angles, nutation rate and reduced momenta.

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
        μ [1] and the moment's a, b at t = 0 [1/t²]; the perturbation is ignored.
    st : State
        The state the orbit passes through at t = 0.

    Returns
    -------
    NutationOrbit
        With t = 0 at ``st``.
    """
    from tumble.unperturbed.symmetric_body import NutationOrbit  # elliptic functions

    return NutationOrbit.from_state(
        p.mu, p.a, p.b, st.R, st.G, st.theta, st.theta_dot, psi=st.psi, phi=st.phi
    )


# ---------------------------------------------------------------------------------------------
# The methods a parameter set allows.


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
    par, ini = required(inputs, "parameters", "initial")
    pert = inputs["perturbation"]
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


DECLARED: Declaration[Params, State] = Declaration(
    name="nonlinear_moment",
    time=TIME_T,
    methods=("full", "closed_form", "averaged"),
    check=_check_method,
    scenario=SCENARIO,
    numeric=True,
    coordinates=("energy", "theta_max", "theta_min"),
    corrected_start=True,
    orders=(1, 2),
)
"""What a scenario of the model may ask for."""
