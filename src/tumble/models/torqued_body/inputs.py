"""The torqued body's inputs: the body, the torque terms, the initial state and the scenario
keys, apart from its numerics (:mod:`tumble.models.torqued_body`).

Principal moments in any order, a time t in which the rotation rates are O(1), and the moment
ε M(t, q, ω) in body axes: a sum of built-in torques (:mod:`tumble.torques`) and user
functions ``f(t, q, omega, params)``.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property, partial
from typing import Any

import numpy as np

from tumble._typing import FloatArray
from tumble.bodies import RigidBody
from tumble.errors import ParameterError, ScenarioError, UserCodeError, check_range, shorten
from tumble.kernels import Kernel
from tumble.models.base import Column, Declaration, frozen_array
from tumble.models.schema import Built, Inputs, Key, ScenarioSchema, Section, Variant
from tumble.rotations import euler313_to_matrix, matrix_to_quat, quat_normalize
from tumble.space.orbit import EARTH_MU, EARTH_RADIUS
from tumble.torques import (
    ConstantBodyTorque,
    ConstantInertialTorque,
    GravityGradientTorque,
    InternalDissipation,
    LinearDrag,
    QuadraticDrag,
    ScaledTorque,
    Torque,
    TorqueSum,
    UserTorque,
    ZeroTorque,
)

__all__ = [
    "DECLARED",
    "EARTH_MU",
    "EARTH_RADIUS",
    "PHYSICAL_TERMS",
    "SCENARIO",
    "TERMS",
    "TORQUE_KINDS",
    "Params",
    "Scaling",
    "State",
    "initial_attitude",
    "orbital_rate",
    "torque_from_terms",
]

_BODY_ONLY = (ConstantBodyTorque, LinearDrag, QuadraticDrag, InternalDissipation, ZeroTorque)
"""Torques that depend on the body angular velocity only: the body's phases enter the rates of
|L| and T only through ω, so commensurabilities of the free motion (m = 0 resonances) do not
move them, and none is reported. The direction of L, whose rate turns with the precession
angle, does feel the resonances ν2 = kν1 (theory of separatrix crossing, §5)."""


def _terms(torque: Torque) -> tuple[Torque, ...]:
    if isinstance(torque, TorqueSum):
        return tuple(t for term in torque.terms for t in _terms(term))
    if isinstance(torque, ScaledTorque):
        return _terms(torque.torque)
    return (torque,)


def _orbit_rate_scaled(torque: Torque, factor: float) -> Torque:
    """``torque`` with the orbital rate n of every gravity-gradient term multiplied by
    ``factor``."""
    if isinstance(torque, GravityGradientTorque):
        return replace(torque, n=torque.n * factor)
    if isinstance(torque, TorqueSum):
        return TorqueSum(tuple(_orbit_rate_scaled(t, factor) for t in torque.terms))
    if isinstance(torque, ScaledTorque):
        return ScaledTorque(torque.factor, _orbit_rate_scaled(torque.torque, factor))
    return torque


TORQUE_KINDS = (
    "gravity_gradient",
    "inertial_constant",
    "body_constant",
    "linear_drag",
    "quadratic_drag",
    "internal_dissipation",
    "user",
)
"""The ``kind`` of a torque term in a scenario."""

PERIOD_RTOL = 1e-12
"""Periods of two periodic torque terms equal to this are one forcing period."""


def _term_torque(i: int, term: dict[str, Any], inertia: Any) -> tuple[Torque, str, float | None]:
    """One torque term of :func:`torque_from_terms`: the torque, its label and its period."""
    kind = term["kind"]
    if kind == "gravity_gradient":
        gg = GravityGradientTorque(inertia, term["n"], term["normal"], term["u0"])
        return gg, f"gravity gradient (n = {gg.n:g})", gg.period
    if kind == "inertial_constant":
        return (
            ConstantInertialTorque(term["moment"]),
            f"inertial moment {list(term['moment'])}",
            None,
        )
    if kind == "body_constant":
        return ConstantBodyTorque(term["moment"]), f"body moment {list(term['moment'])}", None
    if kind == "linear_drag":
        return LinearDrag(term["B"]), "linear drag", None
    if kind == "quadratic_drag":
        return QuadraticDrag(term["S"]), "quadratic drag", None
    if kind == "internal_dissipation":
        damper = InternalDissipation(inertia, term["tau"])
        return damper, f"internal dissipation (τ = {damper.tau:g})", None
    if kind == "user":
        period = term.get("period")
        if period is not None:
            check_range(f"torque[{i}].period", float(period), low=0.0)
        user = UserTorque(term["function"], term.get("params", {}), term["name"])
        return user, term["name"], None if period is None else float(period)
    raise ParameterError(
        f"torque[{i}].kind = {kind!r} is not a torque (allowed: {', '.join(TORQUE_KINDS)})"
    )


def torque_from_terms(
    inertia: Any, terms: list[dict[str, Any]]
) -> tuple[Torque, float | None, str]:
    """The sum of torque terms, its forcing period and a label.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments of the body (the gravity gradient acts on them) [inertia unit].
    terms : list of dict
        Each with ``kind`` (one of :data:`TORQUE_KINDS`) and its values:
        ``gravity_gradient``: ``n`` [rad/t], ``normal`` (3), ``u0`` [rad];
        ``inertial_constant``, ``body_constant``: ``moment`` (3) [moment unit];
        ``linear_drag``: ``B`` (3×3); ``quadratic_drag``: ``S`` (3×3);
        ``internal_dissipation``: ``tau`` [t], the energy's time constant near major-axis
        rotation;
        ``user``: ``function`` (callable ``f(t, q, omega, params)``), ``name``, ``params``,
        ``period`` [t] or None.

    Returns
    -------
    torque : Torque
    period : float or None
        The common period of the explicit time dependence [t].
    label : str

    Raises
    ------
    ParameterError
        For an unknown kind, bad values, or two periodic terms with different periods.
    """
    if not terms:
        raise ParameterError("torque: give at least one torque term")
    parts: list[Torque] = []
    labels: list[str] = []
    periods: list[float] = []
    for i, term in enumerate(terms):
        try:
            part, label, period = _term_torque(i, term, inertia)
        except ParameterError as exc:
            where = f"torque[{i}]"
            message = str(exc)
            raise ParameterError(
                message if message.startswith(where) else f"{where}.{message}"
            ) from None
        parts.append(part)
        labels.append(label)
        periods += [period] if period is not None else []
    period = periods[0] if periods else None
    for other in periods[1:]:
        if abs(other - periods[0]) > PERIOD_RTOL * periods[0]:
            raise ParameterError(
                f"torque: periodic terms with periods {periods[0]:g} and {other:g} cannot be "
                "averaged over one forcing phase (give them a common period)"
            )
    torque = parts[0] if len(parts) == 1 else TorqueSum(tuple(parts))
    return torque, period, " + ".join(labels)


@dataclass(frozen=True)
class Params:
    """Parameters of the torqued body.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        Principal moments (I1, I2, I3), any order, positive and obeying the triangle
        inequality [inertia unit].
    eps : float
        Small parameter ε ≥ 0 multiplying the torque [1] (0: the free body).
    torque : Torque
        The moment M(t, q, ω) in body axes before the factor ε [moment unit].
    forcing_period : float, optional
        Period of the torque's explicit time dependence [t] (the orbital period 2π/n of a
        gravity gradient); None when the torque does not depend on time on the fast scale.
    label : str
        What the torque is, for messages and ``summary.json``.
    mean_torque : Torque, optional
        The torque already averaged over its explicit fast time dependence (an orbiting
        body's orbit and the Earth's rotation: :mod:`tumble.space.torques`), which the
        averaged equations then average over the free rotation alone; ``forcing_period``
        still names the forcing for the checks of validity (resonances, fast phases). None:
        the engine averages ``torque`` over its forcing period itself.
    """

    inertia: FloatArray
    eps: float
    torque: Torque
    forcing_period: float | None = None
    label: str = "torque"
    mean_torque: Torque | None = None
    sorted_inertia: tuple[float, float, float] = field(init=False, repr=False)
    scaled: Torque = field(init=False, repr=False)
    attitude_dependent: bool = field(init=False, repr=False)

    def __post_init__(self) -> None:
        inertia = frozen_array("parameters.inertia", self.inertia, (3,))
        RigidBody(*inertia.tolist())  # positive, triangle inequality
        check_range("parameters.eps", float(self.eps), low=0.0, low_open=False)
        if self.forcing_period is not None:
            check_range("torque period", float(self.forcing_period), low=0.0)
            object.__setattr__(self, "forcing_period", float(self.forcing_period))
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "eps", float(self.eps))
        object.__setattr__(self, "sorted_inertia", tuple(sorted(inertia.tolist())))
        object.__setattr__(self, "scaled", self.eps * self.torque)
        dependent = not all(isinstance(t, _BODY_ONLY) for t in _terms(self.torque))
        object.__setattr__(self, "attitude_dependent", dependent or self.forcing_period is not None)

    @cached_property
    def kernel(self) -> Kernel | None:
        """The full equations compiled; None when the torque holds a Python function. Built
        on first use (a run), not when a scenario is read."""
        from tumble.dynamics import rigid_body_kernel  # compiled code

        return rigid_body_kernel(self.inertia, self.scaled)

    @cached_property
    def averaged_kernel(self) -> Kernel | None:
        """The averaged equations compiled (the triaxial engine's kernel of the torque it
        averages, :attr:`averaging`); None for a torque given as a Python function. Built on
        first use and kept: its program is packed from every term (~0.2 ms), as much as a
        short averaged run's integration."""
        from tumble.averaging.triaxial import triaxial_kernel  # compiled code

        torque, period = self.averaging
        return triaxial_kernel(torque, self.inertia, period, factor=self.eps)

    def __getstate__(self) -> dict[str, Any]:
        # Without the compiled kernels: they may hold a user callback's address in this
        # process.
        state = dict(self.__dict__)
        state.pop("kernel", None)
        state.pop("averaged_kernel", None)
        return state

    @property
    def averaging(self) -> tuple[Torque, float | None]:
        """The torque the averaged equations average over the free rotation, and the period
        of its explicit time dependence they average over too (None: none)."""
        if self.mean_torque is not None:
            return self.mean_torque, None
        if self.torque.along_orbit:
            # Two incommensurate fast phases (the orbit, the Earth's turn): the engine's one
            # forcing phase cannot average them, and a frozen time would not be an average.
            raise ParameterError(
                "torque: an orbit's eddy-current or gravity-gradient term is averaged over the "
                "orbit first (its .averaged(), given as the mean torque; model orbiting_body)"
            )
        return self.torque, self.forcing_period

    def with_eps(self, eps: float) -> Params:
        """The same body and torque at another ε (for error studies)."""
        return replace(self, eps=eps)

    SCALABLE = ("n",)
    """Parameters ``tumble verify`` can scale with ε besides ε itself: the orbital rate n of
    the gravity-gradient terms (``[run] verify_scaling``)."""

    def family(self) -> dict[str, float]:
        """The default family of ``tumble verify``: with a gravity-gradient term, the physical
        one, orbits of other radii: the torque 3n² r̂ × I r̂ is of the size n²/ω², so ε ∝ n²,
        n ∝ √ε and the given ε stays (the orbital phase is then only √ε-fast); otherwise ε
        alone."""
        terms = _terms(self.torque)
        user = any(isinstance(t, UserTorque) for t in terms)
        if not user and any(isinstance(t, GravityGradientTorque) for t in terms):
            return {"eps": 0.0, "n": 0.5}
        return {"eps": 1.0}

    def along(self, ratio: float, exponents: dict[str, float]) -> Params:
        """The parameters with n scaled by ratio^exponents["n"] (the forcing period with it)."""
        factor = ratio ** exponents.get("n", 0.0)
        if factor != 1.0 and any(isinstance(t, UserTorque) for t in _terms(self.torque)):
            raise ParameterError(
                "run.verify_scaling: n cannot scale beside a user torque term (its period, if "
                "any, would no longer be the orbit's); give verify_scaling = { n = 0 }"
            )
        period = None if self.forcing_period is None else self.forcing_period / factor
        return replace(self, torque=_orbit_rate_scaled(self.torque, factor), forcing_period=period)


@dataclass(frozen=True)
class State:
    """Initial body angular velocity ω [rad/t] and attitude quaternion q (scalar first,
    body → inertial; normalized here)."""

    omega: FloatArray
    q: FloatArray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))

    def __post_init__(self) -> None:
        object.__setattr__(self, "omega", frozen_array("initial.omega", self.omega, (3,)))
        q = frozen_array("initial.quaternion", self.q, (4,))
        if not np.any(q):
            raise ParameterError("initial.quaternion = [0, 0, 0, 0] is not a rotation")
        object.__setattr__(self, "q", quat_normalize(q))


def _check_method(p: Params, method: str) -> None:
    if method == "averaged" and p.eps == 0.0:
        raise ParameterError(
            "parameters.eps = 0 is outside the allowed range (0, inf) for the averaged "
            "method (there is nothing to average)"
        )


def _check_initial(p: Params, st: State, method: str) -> None:
    """The averaged equations follow the angular momentum L = I ω: none at rest (refused
    with the scenario, before a user's torque file loads or a run starts)."""
    if method == "averaged" and not np.any(st.omega):
        raise ParameterError(
            "initial.omega = [0, 0, 0]: the averaged method needs a rotating body (|ω| > 0)"
        )


# ---------------------------------------------------------------------------------------------
# Scenario keys.

_PARAMETERS = Section(
    "parameters",
    (
        Key("inertia", "vector3", "3 principal moments > 0 obeying the triangle inequality"),
        Key("eps", "number", "a number ≥ 0 (the factor of the torque)"),
    ),
    doc="the body and the size of the torque",
)
_TORQUE = Section(
    "",
    (
        Key(
            "torque",
            "any",
            '"file:function" or a list of [[torque]] tables with a kind',
            doc="a user function f(t, q, omega, params), or built-in terms",
        ),
        Key("torque_params", "table", "a table passed to the user function", default={}),
        Key(
            "torque_period",
            "number",
            "period of the user function's time dependence > 0",
            "t",
            None,
        ),
    ),
    doc="the torque (top-level keys)",
)
_INITIAL = Section(
    "initial",
    (
        Key("omega", "vector3", "body angular velocity, 3 numbers", "rad/t"),
        Key("quaternion", "vector4", "attitude quaternion [q0, q1, q2, q3]", default=None),
        Key("psi", "number", "3-1-3 Euler angle ψ", "rad", None, angle=True),
        Key("theta", "number", "3-1-3 Euler angle ϑ", "rad", None, angle=True),
        Key("phi", "number", "3-1-3 Euler angle φ", "rad", None, angle=True),
    ),
    doc="the body rate and its attitude (a quaternion or 3-1-3 Euler angles; default identity)",
)


def _term(kind: str, *keys: Key) -> Section:
    return Section("torque", (Key("kind", "text", f'"{kind}"', choices=(kind,)), *keys))


_MOMENT = Key("moment", "vector3", "3 components of the moment")
_TAU_MEANING = "time constant > 0 of the energy above major-axis rotation"
_TAU = Key("tau", "number", _TAU_MEANING, "t")
TERMS: dict[str, Section] = {
    "gravity_gradient": _term(
        "gravity_gradient",
        Key("n", "number", "orbital rate > 0", "rad/t"),
        Key("normal", "vector3", "orbit normal", default=[0.0, 0.0, 1.0]),
        Key(
            "u0",
            "number",
            "argument of latitude at t = 0, from the ascending node",
            "rad",
            0.0,
            angle=True,
        ),
    ),
    "inertial_constant": _term("inertial_constant", _MOMENT),
    "body_constant": _term("body_constant", _MOMENT),
    "linear_drag": _term("linear_drag", Key("B", "matrix3", "3×3 damping matrix, M = −B ω")),
    "quadratic_drag": _term("quadratic_drag", Key("S", "matrix3", "3×3 matrix, M = −S (ω ∘ |ω|)")),
    "internal_dissipation": _term("internal_dissipation", _TAU),
    "user": _term(
        "user",
        Key("function", "text", '"file:function", f(t, q, omega, params) -> body moment'),
        Key("params", "table", "a table for f", default={}),
        Key("period", "number", "period of f's time dependence > 0", "t", None),
    ),
}
"""The [[torque]] tables by kind."""


def _validated_tables(
    inputs: Inputs, tables: list[dict[str, Any]], kinds: Mapping[str, Section], what: str
) -> Iterator[tuple[str, dict[str, Any]]]:
    """Each [[torque]] table checked against the keys of its kind, one at a time (the caller
    acts on a table before the next is checked).

    Parameters
    ----------
    inputs : Inputs
        The scenario being read (its key validation).
    tables : list of dict
        The raw [[torque]] tables, in order.
    kinds : mapping
        The allowed kinds and their keys (:data:`TERMS` or :data:`PHYSICAL_TERMS`).
    what : str
        What a kind names, in the error of an unknown one ("a torque", …).

    Yields
    ------
    (str, dict)
        Each table's kind and its validated keys; ScenarioError at a bad table, naming it
        ``torque[i]``.
    """
    for i, raw in enumerate(tables):
        kind = raw.get("kind")
        if not isinstance(kind, str) or kind not in kinds:
            raise ScenarioError(
                f"torque[{i}].kind = {shorten(repr(kind), 60)} is not {what} "
                f"(allowed: {', '.join(kinds)})"
            )
        yield kind, inputs.validate(kinds[kind], raw, f"torque[{i}]")


def _term_tables(inputs: Inputs) -> list[dict[str, Any]]:
    top = inputs[""]
    assert top is not None  # the top-level keys
    torque = top["torque"]
    if isinstance(torque, str):
        function = inputs.import_function(torque, "torque")
        return [
            {"kind": "user", "function": function, "name": torque,
             "params": top["torque_params"], "period": top["torque_period"]}
        ]  # fmt: skip
    if top["torque_params"] or top["torque_period"] is not None:
        raise ScenarioError(
            'torque_params, torque_period: only with torque = "file:function" (in a '
            "[[torque]] table give params and period inside it)"
        )
    if not isinstance(torque, list) or not all(isinstance(t, dict) for t in torque):
        raise ScenarioError(
            f"torque = {torque!r}: expected " + '"file:function" or [[torque]] tables'
        )
    terms = []
    for i, (kind, term) in enumerate(_validated_tables(inputs, torque, TERMS, "a torque")):
        if kind == "user":
            term["name"] = term["function"]
            term["function"] = inputs.import_function(term["function"], f"torque[{i}].function")
        terms.append(term)
    return terms


def _check_user_torque(torque: Torque, st: State) -> None:
    """Call the torque once at the initial state: a broken user function fails here, in one
    line, rather than deep inside an integration. Run by the scenario loader once the whole
    scenario is valid and the user has been told which file runs (:attr:`Built.user_checks`);
    a numba function is checked when its compiled form is made (:attr:`Torque.program`)."""
    if torque.program is not None:  # compiled: its own checks ran in making the program
        return
    try:
        m = np.asarray(torque(0.0, st.q, st.omega), dtype=float)
    except UserCodeError:
        raise  # already one line naming the function, the state and the fault
    except Exception as exc:
        raise ScenarioError(
            f"torque: evaluating it at the initial state raised {type(exc).__name__}: {exc}"
        ) from None
    if m.shape != (3,) or not np.all(np.isfinite(m)):
        raise ScenarioError(
            f"torque: at the initial state it returned {m.tolist()!r} (expected 3 finite "
            "numbers, the body components of the moment)"
        )


def _build(inputs: Inputs) -> Built[Params, State]:
    par, ini = inputs["parameters"], inputs["initial"]
    assert par is not None and ini is not None  # required sections
    terms = _term_tables(inputs)
    p, st = _params_and_state(np.array(par["inertia"]), par["eps"], terms, ini)
    if not any(term["kind"] == "user" for term in terms):
        return Built(p, st)
    # The user's file is loaded only after every key is checked: the call waits for the loader.
    return Built(p, st, user_checks=(partial(_check_user_torque, p.torque, st),))


def initial_attitude(ini: Mapping[str, Any]) -> FloatArray:
    """The attitude quaternion (body → inertial) of an [initial] table: ``quaternion`` or the
    3-1-3 Euler angles ``psi``, ``theta``, ``phi``, or the identity (normalised by State)."""
    angles = [n for n in ("psi", "theta", "phi") if ini[n] is not None]
    if ini["quaternion"] is not None and angles:
        raise ScenarioError("initial: give either quaternion or psi, theta, phi, not both")
    if angles and len(angles) != 3:
        raise ScenarioError("initial: give all of psi, theta, phi (3-1-3 Euler angles)")
    if angles:
        return matrix_to_quat(euler313_to_matrix(ini["psi"], ini["theta"], ini["phi"]))
    return np.array(ini["quaternion"] if ini["quaternion"] is not None else [1.0, 0.0, 0.0, 0.0])


def _params_and_state(
    inertia: FloatArray, eps: float, terms: list[dict[str, Any]], ini: Mapping[str, Any]
) -> tuple[Params, State]:
    """Params and State of normalised inertia, ε, torque terms and [initial] values."""
    torque, period, label = torque_from_terms(inertia, terms)
    st = State(np.array(ini["omega"]), initial_attitude(ini))
    p = Params(np.asarray(inertia, dtype=float), eps, torque, period, label)
    return p, st


# ---------------------------------------------------------------------------------------------
# Physical units.


def orbital_rate(altitude_km: float) -> float:
    """Mean motion n = √(GM/r³) of a circular orbit about the Earth [rad/s] at ``altitude_km``
    above the equatorial radius (r = R + h)."""
    check_range("torque.altitude [km]", altitude_km, low=0.0)
    r = EARTH_RADIUS + 1e3 * altitude_km
    return float(np.sqrt(EARTH_MU / r**3))


@dataclass(frozen=True)
class Scaling:
    """The normalisation of a physical scenario: t = T0 τ with T0 = 1/|ω(0)| (the initial
    rotation turns at 1 rad per unit of time), moments of inertia over I0 = max I_i, moments
    over I0/T0². The torque is then the physical one, ε = 1: its size relative to the
    rotation (e.g. 3n²T0² for the gravity gradient) is what makes it small."""

    T0: float  # [s]
    I0: float  # [kg·m²]
    eps: float = 1.0  # [1]

    def tau_from_time(self, t_s: Any) -> FloatArray:
        """τ = t / T0 for times in seconds."""
        return np.asarray(t_s, dtype=float) / self.T0

    def time_from_tau(self, tau: Any) -> FloatArray:
        """t = T0 τ [s]."""
        return np.asarray(tau, dtype=float) * self.T0

    def summary(self) -> dict[str, float]:
        """The scales, for summary.json."""
        return {"T0_s": self.T0, "I0_kgm2": self.I0, "eps": self.eps}

    def si(self, name: str) -> tuple[float, str, str] | None:
        """(factor, SI unit, SI name) of an output column: L [kg m²/s], T [J], ω [rad/s]."""
        if name in ("L1", "L2", "L3", "L"):
            return self.I0 / self.T0, "kg m²/s", f"{name}_kgm2_s"
        if name == "T":
            return self.I0 / self.T0**2, "J", "T_J"
        if name in ("omega1", "omega2", "omega3"):
            return 1.0 / self.T0, "rad/s", f"{name}_rad_s"
        return None


_PHYSICAL = Section(
    "physical",
    (
        Key(
            "inertia",
            "vector3",
            "3 principal moments > 0 obeying the triangle inequality",
            "kg m^2",
        ),
    ),
    doc="the body in SI units; the [[torque]] terms and [initial] in SI too",
)
_PHYSICAL_TORQUE = Section(
    "",
    (
        Key(
            "torque",
            "any",
            "a list of [[torque]] tables with a kind",
            doc="built-in terms in SI units",
        ),
    ),
    doc="the torque (top-level keys)",
)
_PHYSICAL_INITIAL = Section(
    "initial",
    (
        Key("omega", "vector3", "body angular velocity, 3 numbers, not all 0", "rad/s"),
        *_INITIAL.keys[1:],
    ),
    doc="the body rate and its attitude (a quaternion or 3-1-3 Euler angles; default identity)",
)
PHYSICAL_TERMS: dict[str, Section] = {
    "gravity_gradient": _term(
        "gravity_gradient",
        Key("altitude", "number", "circular orbit's altitude above the Earth > 0", "km", None),
        Key("n", "number", "orbital rate > 0", "rad/s", None),
        *TERMS["gravity_gradient"].keys[2:],
    ),
    "inertial_constant": _term("inertial_constant", Key("moment", "vector3", "3 numbers", "N m")),
    "body_constant": _term("body_constant", Key("moment", "vector3", "3 numbers", "N m")),
    "linear_drag": _term("linear_drag", Key("B", "matrix3", "3×3, M = −B ω", "N m s")),
    "quadratic_drag": _term(
        "quadratic_drag", Key("S", "matrix3", "3×3, M = −S (ω ∘ |ω|)", "N m s^2")
    ),
    "internal_dissipation": _term("internal_dissipation", Key("tau", "number", _TAU_MEANING, "s")),
}
"""The [[torque]] tables of a physical scenario by kind, in SI units."""


def _physical_term(i: int, term: dict[str, Any], T0: float, I0: float) -> dict[str, Any]:
    """A [[torque]] table in SI converted to the normalised units of :func:`torque_from_terms`."""
    kind, out = term["kind"], dict(term)
    if kind == "gravity_gradient":
        given = [k for k in ("altitude", "n") if term[k] is not None]
        if len(given) != 1:
            raise ScenarioError(
                f"torque[{i}]: give the orbit by altitude [km] or by n [rad/s], one of them"
            )
        n = orbital_rate(term["altitude"]) if given == ["altitude"] else term["n"]
        check_range(f"torque[{i}].n [rad/s]", n, low=0.0)
        out["n"] = n * T0
        del out["altitude"]
    elif kind in ("inertial_constant", "body_constant"):
        out["moment"] = np.asarray(term["moment"], dtype=float) * T0**2 / I0
    elif kind == "linear_drag":
        out["B"] = np.asarray(term["B"], dtype=float) * T0 / I0
    elif kind == "quadratic_drag":
        out["S"] = np.asarray(term["S"], dtype=float) / I0
    elif kind == "internal_dissipation":
        check_range(f"torque[{i}].tau [s]", term["tau"], low=0.0)
        out["tau"] = float(term["tau"]) / T0
    return out


def _build_physical(inputs: Inputs) -> Built[Params, State]:
    ph, ini, top = inputs["physical"], inputs["initial"], inputs[""]
    assert ph is not None and ini is not None and top is not None  # required sections
    inertia = frozen_array("physical.inertia", ph["inertia"], (3,))
    RigidBody(*inertia.tolist())
    rate = float(np.linalg.norm(ini["omega"]))
    if rate == 0.0:
        raise ScenarioError(
            "initial.omega = [0, 0, 0]: a physical scenario needs a rotating body (|ω| > 0 "
            "sets its time scale)"
        )
    T0, I0 = 1.0 / rate, float(np.max(inertia))
    torque = top["torque"]
    if not isinstance(torque, list) or not all(isinstance(t, dict) for t in torque):
        raise ScenarioError(
            f"torque = {shorten(repr(torque), 60)}: a physical scenario takes [[torque]] tables "
            f"of the kinds {', '.join(PHYSICAL_TERMS)} (a user function works in normalised "
            "units: use [parameters])"
        )
    tables = _validated_tables(inputs, torque, PHYSICAL_TERMS, "a torque of a physical scenario")
    terms = [_physical_term(i, term, T0, I0) for i, (_, term) in enumerate(tables)]
    normalised = {**ini, "omega": np.asarray(ini["omega"], dtype=float) * T0}
    p, st = _params_and_state(inertia / I0, 1.0, terms, normalised)
    return Built(p, st, Scaling(T0, I0))


SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant((_PARAMETERS, _TORQUE, _INITIAL), _build, doc="any time unit t"),
        Variant(
            (_PHYSICAL, _PHYSICAL_TORQUE, _PHYSICAL_INITIAL),
            _build_physical,
            physical=True,
            doc="SI units: t = T0 τ with T0 = 1/|ω(0)|",
        ),
    )
)


DECLARED: Declaration[Params, State] = Declaration(
    name="torqued_body",
    time=Column("t", "time t", "t"),
    methods=("full", "averaged"),
    check=_check_method,
    scenario=SCENARIO,
    orders=(1, 2),
    hybrid=True,  # across the resonances and the separatrix (tumble.models.triaxial_mean)
    check_initial=_check_initial,
    engine=True,
)
"""What a scenario of the model may ask for."""
