"""Scenario files: TOML, validated with pydantic, turned into a :class:`RunRequest`.

The keys of the normalized scenarios of each model are a contract (issues 2 and 3); a
physical-units variant replaces ``[parameters]`` by ``[physical]`` (SI) and uses seconds in
``[run]``.
"""

from __future__ import annotations

import importlib
import math
import sys
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from tumble.analysis import RunRequest
from tumble.errors import ParameterError, ScenarioError
from tumble.integrate import check_times
from tumble.models import (
    get_model,
    nonlinear_moment,
    resisting_medium,
    rotating_field,
    torqued_body,
)
from tumble.models.base import AveragingOptions
from tumble.rotations import euler313_to_matrix, matrix_to_quat

__all__ = ["Scenario", "key_units", "load_scenario", "parse_scenario", "template"]

Vector3 = Annotated[list[float], Field(min_length=3, max_length=3, description="3 numbers")]
Vector4 = Annotated[list[float], Field(min_length=4, max_length=4, description="4 numbers")]
Matrix3 = Annotated[
    list[Vector3], Field(min_length=3, max_length=3, description="3 rows of 3 numbers")
]
ANGLES = ("rho", "sigma", "psi", "theta", "phi")


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)


def _degrees_to_radians(data: Any, names: tuple[str, ...]) -> Any:
    """Accept ``<angle>_deg`` keys (degrees) for the angles in ``names``."""
    if not isinstance(data, dict):
        return data
    out = dict(data)
    for name in names:
        key = f"{name}_deg"
        if key in out:
            if name in out:
                raise ValueError(f"give either {name} or {key}, not both")
            value = out.pop(key)
            if isinstance(value, int | float) and not isinstance(value, bool):
                value = math.radians(value)
            out[name] = value
    return out


class RunSection(_Section):
    tau_end: float | None = Field(None, description="a time > 0")
    tau: list[float] | None = Field(None, description="ascending times ≥ 0")
    samples: int = Field(401, description="an integer ≥ 2")
    methods: list[Literal["full", "averaged", "closed_form"]] | None = Field(
        None, description='a non-empty list of "full", "averaged", "closed_form"'
    )
    rtol: float = Field(1e-10, description="a number in [1e-14, 1e-3]")
    atol: float = Field(1e-12, description="a number in (0, 1e-3]")
    averaging: Literal["closed_form", "numeric"] = Field(
        "closed_form", description='"closed_form" or "numeric"'
    )
    verify: bool = Field(False, description="true or false")
    integrator: Literal["auto", "numba", "scipy"] = Field(
        "auto", description='"auto", "numba" or "scipy"'
    )


class PhysicalRunSection(_Section):
    t_end_s: float | None = Field(None, description="a time > 0 [s]")
    t_s: list[float] | None = Field(None, description="ascending times ≥ 0 [s]")
    samples: int = Field(401, description="an integer ≥ 2")
    methods: list[Literal["full", "averaged", "closed_form"]] | None = Field(
        None, description='a non-empty list of "full", "averaged", "closed_form"'
    )
    rtol: float = Field(1e-10, description="a number in [1e-14, 1e-3]")
    atol: float = Field(1e-12, description="a number in (0, 1e-3]")
    averaging: Literal["closed_form", "numeric"] = Field(
        "closed_form", description='"closed_form" or "numeric"'
    )
    verify: bool = Field(False, description="true or false")
    integrator: Literal["auto", "numba", "scipy"] = Field(
        "auto", description='"auto", "numba" or "scipy"'
    )


class RMParameters(_Section):
    eps: float = Field(description="a number ≥ 0")
    kappa: float = Field(description="a number in (-1, 1]")
    a: Vector3 = Field(default_factory=lambda: [0.0, 0.0, 0.0], description="3 numbers")
    b: Matrix3 = Field(default_factory=lambda: np.zeros((3, 3)).tolist(), description="3×3")
    s: Matrix3 = Field(default_factory=lambda: np.zeros((3, 3)).tolist(), description="3×3")


class RMInitial(_Section):
    k: float = Field(1.0, description="a number > 0")
    rho: float = Field(0.0, description="an angle in [0, π] [rad]")
    sigma: float = Field(0.0, description="an angle [rad]")
    psi: float = Field(0.0, description="an angle [rad]")
    theta: float = Field(description="an angle in [0, π] [rad]")
    phi: float = Field(0.0, description="an angle [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ANGLES)


class RMPhysical(_Section):
    I1: float = Field(description="equatorial moment of inertia > 0 [kg m^2]")
    I3: float = Field(description="polar moment of inertia in (0, 2 I1] [kg m^2]")
    A: Vector3 = Field(default_factory=lambda: [0.0, 0.0, 0.0], description="3 moments [N m]")
    B: Matrix3 = Field(default_factory=lambda: np.zeros((3, 3)).tolist(), description="3×3 [N m s]")
    S: Matrix3 = Field(
        default_factory=lambda: np.zeros((3, 3)).tolist(), description="3×3 [N m s^2]"
    )
    M0: float | None = Field(None, description="a moment scale > 0 [N m]")


class RMPhysicalInitial(_Section):
    omega: Vector3 = Field(description="body angular velocity, 3 numbers [rad/s]")
    quaternion: Vector4 | None = Field(None, description="attitude quaternion [q0, q1, q2, q3]")
    rho: float | None = Field(None, description="an angle in [0, π] [rad]")
    sigma: float | None = Field(None, description="an angle [rad]")
    psi: float | None = Field(None, description="an angle [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("rho", "sigma", "psi"))


class RMScenario(_Section):
    model: Literal["resisting_medium"]
    parameters: RMParameters
    initial: RMInitial
    run: RunSection


class RMPhysicalScenario(_Section):
    model: Literal["resisting_medium"]
    physical: RMPhysical
    initial: RMPhysicalInitial
    run: PhysicalRunSection


class RFParameters(_Section):
    inertia: Vector3 = Field(description="3 principal moments > 0 obeying the triangle inequality")
    beta: float = Field(description="an angle in [0, π] [rad]")
    eps: float = Field(description="a number > 0")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("beta",))


class RFInitial(_Section):
    z: Vector3 | None = Field(None, description="body angular velocity over ω, 3 numbers")
    gamma: Matrix3 | None = Field(None, description="3 rows of the rotation Γ (v_η = Γ v_x)")
    L: float | None = Field(None, description="a number > 0")
    rho: float | None = Field(None, description="an angle in [0, π] [rad]")
    sigma: float | None = Field(None, description="an angle [rad]")
    k2: float | None = Field(None, description="a number in [0, 1]")
    regime: Literal["x3", "x1"] = Field("x3", description='"x3" or "x1"')
    u0: float = Field(0.0, description="a phase u of (3.1)")
    psi0: float = Field(0.0, description="an angle [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("rho", "sigma", "psi0"))


class RFScenario(_Section):
    model: Literal["rotating_field"]
    parameters: RFParameters
    initial: RFInitial
    run: RunSection


class RFPhysical(_Section):
    inertia: Vector3 = Field(description="3 principal moments > 0 [kg m^2]")
    k_f: float = Field(description="eddy-current factor > 0 [N m s/(A/m)^2]")
    H: float = Field(description="field strength > 0 [A/m]")
    omega: float = Field(description="field rotation rate > 0 [rad/s]")
    beta: float = Field(description="an angle in [0, π] [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("beta",))


class RFPhysicalInitial(_Section):
    Omega: Vector3 = Field(description="body angular velocity, 3 numbers [rad/s]")
    gamma: Matrix3 = Field(description="3 rows of the body → inertial rotation")


class RFPhysicalScenario(_Section):
    model: Literal["rotating_field"]
    physical: RFPhysical
    initial: RFPhysicalInitial
    run: PhysicalRunSection


@dataclass(frozen=True)
class Scenario:
    """A validated scenario: the run it asks for, and its inputs as given."""

    request: RunRequest
    inputs: dict[str, Any]
    source: str


def _path(loc: tuple[int | str, ...]) -> str:
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        # Skip pydantic's union-member tags ("float", "literal['a']", …), not keys that
        # merely begin like one ("integrator").
        elif str(part) not in ("float", "int") and not str(part).startswith(
            ("function-", "literal[", "list[")
        ):
            out += f".{part}" if out else str(part)
    return out


def _field_hint(schema: type[BaseModel], loc: tuple[int | str, ...]) -> tuple[str, list[str]]:
    """Allowed range of the field at ``loc`` and the keys allowed beside it."""
    cls: Any = schema
    hint, siblings = "", list(schema.model_fields)
    for part in loc:
        if not (isinstance(cls, type) and issubclass(cls, BaseModel)):
            break
        siblings = list(cls.model_fields)  # the keys allowed in the section ``part`` is in
        if not isinstance(part, str) or part not in cls.model_fields:
            break
        info = cls.model_fields[part]
        hint = info.description or hint
        ann = info.annotation
        cls = next(
            (
                a
                for a in getattr(ann, "__args__", ())
                if isinstance(a, type) and issubclass(a, BaseModel)
            ),
            ann,
        )
    return hint, siblings


def _one_line(exc: ValidationError, schema: type[BaseModel]) -> str:
    err = exc.errors(include_url=False)[0]
    loc = tuple(err["loc"])
    path = _path(loc) or "scenario"
    hint, siblings = _field_hint(schema, loc)
    kind = err["type"]
    if kind == "missing":
        return f"{path}: required key is missing" + (f" (expected {hint})" if hint else "")
    if kind == "extra_forbidden":
        return f"{path}: unknown key (allowed here: {', '.join(siblings)})"
    msg = str(err["msg"]).removeprefix("Value error, ")
    shown = repr(err.get("input"))
    shown = shown if len(shown) <= 60 else shown[:57] + "..."
    return f"{path} = {shown}: {msg}" + (f" (expected {hint})" if hint else "")


def _validated(schema: type[BaseModel], data: dict[str, Any]) -> Any:
    try:
        return schema.model_validate(data)
    except ValidationError as exc:
        raise ScenarioError(_one_line(exc, schema)) from None


def _times(run: Any, end_key: str, list_key: str) -> np.ndarray:
    end, listed = getattr(run, end_key), getattr(run, list_key)
    if (end is None) == (listed is None):
        raise ScenarioError(f"run: give exactly one of {end_key} (with samples) or {list_key}")
    if listed is not None:
        return check_times(listed, field=f"run.{list_key}")
    if not (math.isfinite(end) and end > 0.0):
        raise ParameterError(f"run.{end_key} = {end:g} is outside the allowed range (0, inf)")
    if run.samples < 2:
        raise ParameterError(f"run.samples = {run.samples} is outside the allowed range [2, inf)")
    return np.linspace(0.0, end, run.samples)


def _tolerances(run: Any) -> tuple[float, float]:
    if not 1e-14 <= run.rtol <= 1e-3:
        raise ParameterError(f"run.rtol = {run.rtol:g} is outside the allowed range [1e-14, 1e-3]")
    if not 0.0 < run.atol <= 1e-3:
        raise ParameterError(f"run.atol = {run.atol:g} is outside the allowed range (0, 1e-3]")
    return run.rtol, run.atol


def _methods(run: Any, allowed: tuple[str, ...]) -> tuple[str, ...]:
    methods = tuple(run.methods) if run.methods is not None else allowed
    if not methods:
        raise ScenarioError(
            "run.methods: give at least one method (allowed: " + ", ".join(allowed) + ")"
        )
    if len(set(methods)) != len(methods):
        raise ScenarioError(f"run.methods = {list(methods)}: each method at most once")
    for m in methods:
        if m not in allowed:
            raise ScenarioError(
                f"run.methods: {m!r} is not a method of this model (allowed: "
                + ", ".join(allowed)
                + ")"
            )
    return methods


def _resisting_medium(data: dict[str, Any]) -> tuple[RunRequest, dict[str, Any]]:
    model = resisting_medium.MODEL
    if "physical" in data:
        if "parameters" in data:
            raise ScenarioError(
                "give either [parameters] (normalized) or [physical] (SI), not both"
            )
        sc = _validated(RMPhysicalScenario, data)
        phys = resisting_medium.PhysicalParams(
            I1=sc.physical.I1,
            I3=sc.physical.I3,
            A=sc.physical.A,
            B=sc.physical.B,
            S=sc.physical.S,
            M0=sc.physical.M0,
        )
        ini = sc.initial
        angles_given = [n for n in ("rho", "sigma", "psi") if getattr(ini, n) is not None]
        if ini.quaternion is not None and angles_given:
            raise ScenarioError("initial: give either quaternion or rho, sigma, psi, not both")
        if ini.quaternion is None and len(angles_given) != 3:
            raise ScenarioError(
                "initial: give the attitude as quaternion or as all of rho, sigma, psi"
            )
        if ini.quaternion is not None and not np.any(ini.quaternion):
            raise ParameterError("initial.quaternion = [0, 0, 0, 0] is not a rotation")
        p, st, scaling = resisting_medium.normalize_physical(
            phys, ini.omega, attitude=ini.quaternion, rho=ini.rho, sigma=ini.sigma, psi=ini.psi
        )
        t_s = _times(sc.run, "t_end_s", "t_s")
        tau = scaling.tau_from_time(t_s)
        run = sc.run
    else:
        sc = _validated(RMScenario, data)
        par, ini = sc.parameters, sc.initial
        p = resisting_medium.Params(eps=par.eps, kappa=par.kappa, a=par.a, b=par.b, s=par.s)
        st = resisting_medium.State(
            k=ini.k, rho=ini.rho, sigma=ini.sigma, psi=ini.psi, theta=ini.theta, phi=ini.phi
        )
        tau, scaling, run = _times(sc.run, "tau_end", "tau"), None, sc.run
    rtol, atol = _tolerances(run)
    request = RunRequest(
        model,
        p,
        st,
        tau,
        _methods(run, model.methods),
        rtol,
        atol,
        scaling,
        run.verify,
        run.integrator,
        AveragingOptions(averaging=run.averaging),
    )
    return request, sc.model_dump()


def _rf_initial(p: rotating_field.Params, ini: RFInitial) -> rotating_field.State:
    elements = ("L", "rho", "sigma", "k2")
    given = [n for n in elements if getattr(ini, n) is not None]
    direct = [n for n in ("z", "gamma") if getattr(ini, n) is not None]
    if direct and given:
        raise ScenarioError(
            "initial: give either z and gamma, or the slow elements L, rho, sigma, k2 "
            f"(with regime, u0, psi0), not both (got {', '.join(direct + given)})"
        )
    if direct:
        if len(direct) != 2:
            raise ScenarioError("initial: z and gamma go together (give both)")
        return rotating_field.State(np.array(ini.z), np.array(ini.gamma))
    if len(given) != len(elements):
        missing = [n for n in elements if n not in given]
        raise ScenarioError(
            "initial: give z and gamma, or all of L, rho, sigma, k2 "
            f"(missing: {', '.join(missing)})"
        )
    L, rho, sigma, k2 = (float(getattr(ini, n)) for n in elements)  # all given (checked)
    return rotating_field.state_from_elements(
        p, L, rho, sigma, k2, ini.regime, u0=ini.u0, psi0=ini.psi0
    )


def _rotating_field(data: dict[str, Any]) -> tuple[RunRequest, dict[str, Any]]:
    model = rotating_field.MODEL
    if "physical" in data:
        if "parameters" in data:
            raise ScenarioError(
                "give either [parameters] (normalized) or [physical] (SI), not both"
            )
        sc = _validated(RFPhysicalScenario, data)
        ph = sc.physical
        phys = rotating_field.PhysicalParams(ph.inertia, ph.k_f, ph.H, ph.omega, ph.beta)
        p, st, scaling = rotating_field.normalize_physical(phys, sc.initial.Omega, sc.initial.gamma)
        tau = scaling.tau_from_time(_times(sc.run, "t_end_s", "t_s"))
    else:
        sc = _validated(RFScenario, data)
        par = sc.parameters
        p = rotating_field.Params(par.inertia, par.beta, par.eps)
        st = _rf_initial(p, sc.initial)
        tau, scaling = _times(sc.run, "tau_end", "tau"), None
    rtol, atol = _tolerances(sc.run)
    methods = _methods(sc.run, model.methods)
    averaging = AveragingOptions(averaging=sc.run.averaging)
    request = RunRequest(
        model, p, st, tau, methods, rtol, atol, scaling, sc.run.verify, sc.run.integrator, averaging
    )
    return request, sc.model_dump()


class NMParameters(_Section):
    mu: float = Field(description="C/A, a number in (0, 2]")
    a: float = Field(description="sinθ coefficient of M0/A at t = 0, a finite number [1/t^2]")
    b: float = Field(description="sin2θ coefficient of M0/A at t = 0, a finite number [1/t^2]")


class NMPressureTable(_Section):
    tau: list[float] = Field(description="ascending slow times τ = εt, from ≤ 0")
    Q: list[float] = Field(description="pressure values > 0, one per τ")


class NMPerturbation(_Section):
    eps: float = Field(description="a number in (0, 1)")
    d: float = Field(0.0, description="pitch damping, a finite number [1/t]")
    nu: float = Field(0.0, description="roll damping, a finite number [1/t]")
    pressure: Literal["constant", "exp"] | list[list[float]] | NMPressureTable = Field(
        "constant",
        description='"constant", "exp", a table [[τ, Q], ...] or {tau = [...], Q = [...]}',
    )


class NMInitial(_Section):
    theta: float = Field(description="an angle in (0, π) [rad]")
    theta_dot: float = Field(0.0, description="θ' at t = 0, a finite number [rad/t]")
    psi: float = Field(0.0, description="an angle [rad]")
    phi: float = Field(0.0, description="an angle [rad]")
    R: float = Field(0.0, description="R = Cr/A, a finite number [1/t]")
    G: float = Field(0.0, description="G = K·e_z/A, a finite number [1/t]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("theta", "psi", "phi"))


class NMRunSection(_Section):
    t_end: float | None = Field(None, description="a time > 0 [t]")
    t: list[float] | None = Field(None, description="ascending times ≥ 0 [t]")
    samples: int = Field(2001, description="an integer ≥ 2")
    methods: list[Literal["full", "averaged", "closed_form"]] | None = Field(
        None, description='a non-empty list of "full", "closed_form", "averaged"'
    )
    averaged_init: Literal["exact", "corrected"] = Field(
        "exact", description='"exact" or "corrected"'
    )
    averaged_form: Literal["energy", "theta_max", "theta_min"] = Field(
        "energy", description='"energy", "theta_max" or "theta_min"'
    )
    averaging: Literal["closed_form", "numeric"] = Field(
        "closed_form", description='"closed_form" or "numeric"'
    )
    rtol: float = Field(1e-10, description="a number in [1e-14, 1e-3]")
    atol: float = Field(1e-12, description="a number in (0, 1e-3]")
    verify: bool = Field(False, description="true or false")
    integrator: Literal["auto", "numba", "scipy"] = Field(
        "auto", description='"auto", "numba" or "scipy"'
    )


class NMScenario(_Section):
    model: Literal["nonlinear_moment"]
    parameters: NMParameters
    perturbation: NMPerturbation | None = None
    initial: NMInitial
    run: NMRunSection


def _pressure(value: Any) -> nonlinear_moment.Pressure:
    if isinstance(value, str):
        return nonlinear_moment.Pressure(value)  # type: ignore[arg-type]
    if isinstance(value, NMPressureTable):
        return nonlinear_moment.Pressure("table", tuple(value.tau), tuple(value.Q))
    if not all(len(row) == 2 for row in value):
        raise ScenarioError("perturbation.pressure: a table is a list of [τ, Q] pairs")
    return nonlinear_moment.Pressure(
        "table", tuple(r[0] for r in value), tuple(r[1] for r in value)
    )


def _nonlinear_moment(data: dict[str, Any]) -> tuple[RunRequest, dict[str, Any]]:
    model = nonlinear_moment.MODEL
    sc = _validated(NMScenario, data)
    par, pert, ini, run = sc.parameters, sc.perturbation, sc.initial, sc.run
    if pert is not None and not (math.isfinite(pert.eps) and 0.0 < pert.eps < 1.0):
        raise ParameterError(f"perturbation.eps = {pert.eps:g} is outside the allowed range (0, 1)")
    p = nonlinear_moment.Params(
        mu=par.mu,
        a=par.a,
        b=par.b,
        eps=pert.eps if pert else 0.0,
        d=pert.d if pert else 0.0,
        nu=pert.nu if pert else 0.0,
        pressure=_pressure(pert.pressure) if pert else nonlinear_moment.Pressure(),
    )
    averaging = AveragingOptions(
        averaging=run.averaging, coordinates=run.averaged_form, start=run.averaged_init
    )
    st = nonlinear_moment.State(
        theta=ini.theta, theta_dot=ini.theta_dot, psi=ini.psi, phi=ini.phi, R=ini.R, G=ini.G
    )
    t = _times(run, "t_end", "t")
    if p.eps * t[-1] > p.pressure.tau_max:
        raise ParameterError(
            f"perturbation.pressure table covers τ ≤ {p.pressure.tau_max:g}, but the run "
            f"reaches τ = eps·t = {p.eps * t[-1]:g}"
        )
    default = ("full", "averaged") if p.perturbed else ("full", "closed_form")
    methods = _methods(run, model.methods) if run.methods is not None else default
    for m in methods:
        model.check(p, m)  # closed_form needs ε = 0, averaged needs ε > 0
    rtol, atol = _tolerances(run)
    nonlinear_moment.orbit_of(p, st)  # no motion (e.g. a separatrix) → one line, before any run
    request = RunRequest(
        model,
        p,
        st,
        t,
        methods,
        rtol,
        atol,
        verify=run.verify,
        integrator=run.integrator,
        averaging=averaging,
    )
    return request, sc.model_dump()


class TBParameters(_Section):
    inertia: Vector3 = Field(description="3 principal moments > 0 obeying the triangle inequality")
    eps: float = Field(description="a number ≥ 0 (the factor of the torque)")


class TBGravityGradient(_Section):
    kind: Literal["gravity_gradient"]
    n: float = Field(description="orbital rate > 0 [rad/t]")
    normal: Vector3 = Field(default_factory=lambda: [0.0, 0.0, 1.0], description="orbit normal")
    u0: float = Field(0.0, description="argument of latitude at t = 0 [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("u0",))


class TBMoment(_Section):
    kind: Literal["inertial_constant", "body_constant"]
    moment: Vector3 = Field(description="3 components of the moment")


class TBLinearDrag(_Section):
    kind: Literal["linear_drag"]
    B: Matrix3 = Field(description="3×3 damping matrix, M = −B ω")


class TBQuadraticDrag(_Section):
    kind: Literal["quadratic_drag"]
    S: Matrix3 = Field(description="3×3 matrix, M = −S (ω ∘ |ω|)")


class TBUser(_Section):
    kind: Literal["user"]
    function: str = Field(description='"module:function", f(t, q, omega, params) -> body moment')
    params: dict[str, Any] = Field(default_factory=dict, description="a table for f")
    period: float | None = Field(None, description="period of f's time dependence > 0 [t]")


_TERMS: dict[str, type[_Section]] = {
    "gravity_gradient": TBGravityGradient,
    "inertial_constant": TBMoment,
    "body_constant": TBMoment,
    "linear_drag": TBLinearDrag,
    "quadratic_drag": TBQuadraticDrag,
    "user": TBUser,
}


class TBInitial(_Section):
    omega: Vector3 = Field(description="body angular velocity, 3 numbers [rad/t]")
    quaternion: Vector4 | None = Field(None, description="attitude quaternion [q0, q1, q2, q3]")
    psi: float | None = Field(None, description="3-1-3 Euler angle ψ [rad]")
    theta: float | None = Field(None, description="3-1-3 Euler angle ϑ [rad]")
    phi: float | None = Field(None, description="3-1-3 Euler angle φ [rad]")

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, data: Any) -> Any:
        return _degrees_to_radians(data, ("psi", "theta", "phi"))


class TBRunSection(_Section):
    t_end: float | None = Field(None, description="a time > 0 [t]")
    t: list[float] | None = Field(None, description="ascending times ≥ 0 [t]")
    samples: int = Field(401, description="an integer ≥ 2")
    methods: list[Literal["full", "averaged"]] | None = Field(
        None, description='a non-empty list of "full", "averaged"'
    )
    rtol: float = Field(1e-10, description="a number in [1e-14, 1e-3]")
    atol: float = Field(1e-12, description="a number in (0, 1e-3]")
    verify: bool = Field(False, description="true or false")
    integrator: Literal["auto", "numba", "scipy"] = Field(
        "auto", description='"auto", "numba" or "scipy"'
    )


class TBScenario(_Section):
    model: Literal["torqued_body"]
    parameters: TBParameters
    torque: str | list[dict[str, Any]] = Field(
        description='"module:function" or a list of [[torque]] tables with a kind'
    )
    torque_params: dict[str, Any] = Field(
        default_factory=dict, description="a table passed to the user function"
    )
    torque_period: float | None = Field(
        None, description="period of the user function's time dependence > 0 [t]"
    )
    initial: TBInitial
    run: TBRunSection


def _import_function(spec: str, base: Path, field: str) -> Any:
    """The callable named ``"module:function"``, importing from ``base`` (the scenario's
    directory) first."""
    module, sep, name = spec.partition(":")
    if not sep or not module or not name:
        raise ScenarioError(f'{field} = {spec!r}: expected "module:function"')
    sys.path.insert(0, str(base))
    try:
        mod = importlib.import_module(module)
    except Exception as exc:  # any failure of the user's module: one line, no traceback
        raise ScenarioError(
            f"{field} = {spec!r}: cannot import {module} ({type(exc).__name__}: {exc})"
        ) from None
    finally:
        sys.path.remove(str(base))
    function = getattr(mod, name, None)
    if not callable(function):
        raise ScenarioError(f"{field} = {spec!r}: {module} has no function {name}")
    return function


def _torque_terms(sc: TBScenario, base: Path) -> list[dict[str, Any]]:
    if isinstance(sc.torque, str):
        function = _import_function(sc.torque, base, "torque")
        return [
            {
                "kind": "user",
                "function": function,
                "name": sc.torque,
                "params": sc.torque_params,
                "period": sc.torque_period,
            }
        ]
    if sc.torque_params or sc.torque_period is not None:
        raise ScenarioError(
            'torque_params, torque_period: only with torque = "module:function" (in a '
            "[[torque]] table give params and period inside it)"
        )
    terms = []
    for i, raw in enumerate(sc.torque):
        kind = raw.get("kind")
        if kind not in _TERMS:
            raise ScenarioError(
                f"torque[{i}].kind = {kind!r} is not a torque (allowed: {', '.join(_TERMS)})"
            )
        schema = _TERMS[kind]
        try:
            term = schema.model_validate(raw).model_dump()
        except ValidationError as exc:
            raise ScenarioError(f"torque[{i}].{_one_line(exc, schema)}") from None
        if kind == "user":
            term["name"] = term["function"]
            term["function"] = _import_function(term["function"], base, f"torque[{i}].function")
        terms.append(term)
    return terms


def _check_user_torque(torque: Any, st: torqued_body.State) -> None:
    """Call the torque once at the initial state: a broken user function fails here, in one
    line, rather than deep inside an integration."""
    try:
        m = np.asarray(torque(0.0, st.q, st.omega), dtype=float)
    except Exception as exc:
        raise ScenarioError(
            f"torque: evaluating it at the initial state raised {type(exc).__name__}: {exc}"
        ) from None
    if m.shape != (3,) or not np.all(np.isfinite(m)):
        raise ScenarioError(
            f"torque: at the initial state it returned {m.tolist()!r} (expected 3 finite "
            "numbers, the body components of the moment)"
        )


def _torqued_body(data: dict[str, Any], base: Path) -> tuple[RunRequest, dict[str, Any]]:
    model = torqued_body.MODEL
    sc = _validated(TBScenario, data)
    par, ini, run = sc.parameters, sc.initial, sc.run
    torque, period, label = torqued_body.torque_from_terms(par.inertia, _torque_terms(sc, base))
    angles = [n for n in ("psi", "theta", "phi") if getattr(ini, n) is not None]
    if ini.quaternion is not None and angles:
        raise ScenarioError("initial: give either quaternion or psi, theta, phi, not both")
    if angles and len(angles) != 3:
        raise ScenarioError("initial: give all of psi, theta, phi (3-1-3 Euler angles)")
    if angles:
        q = matrix_to_quat(euler313_to_matrix(ini.psi, ini.theta, ini.phi))
    else:
        q = np.array(ini.quaternion if ini.quaternion is not None else [1.0, 0.0, 0.0, 0.0])
    st = torqued_body.State(np.array(ini.omega), q)
    p = torqued_body.Params(np.array(par.inertia), par.eps, torque, period, label)
    _check_user_torque(p.torque, st)
    t = _times(run, "t_end", "t")
    methods = _methods(run, model.methods)
    for m in methods:
        model.check(p, m)
    rtol, atol = _tolerances(run)
    request = RunRequest(
        model, p, st, t, methods, rtol, atol, verify=run.verify, integrator=run.integrator
    )
    return request, sc.model_dump()


_BUILDERS = {
    "resisting_medium": _resisting_medium,
    "rotating_field": _rotating_field,
    "nonlinear_moment": _nonlinear_moment,
}


def parse_scenario(data: dict[str, Any], source: str = "<scenario>") -> Scenario:
    """Validate a scenario given as a dict (as read from TOML).

    Raises
    ------
    ScenarioError, ParameterError
        With a one-line message naming the key and its allowed range.
    """
    if "model" not in data:
        raise ScenarioError(
            "model: required key is missing (allowed: "
            + ", ".join([*_BUILDERS, "torqued_body"])
            + ")"
        )
    name = data["model"]
    if not isinstance(name, str):
        raise ScenarioError(f"model = {name!r}: expected a string")
    get_model(name)  # unknown model → one line naming the allowed ones
    if name == "torqued_body":  # a user torque is imported relative to the scenario
        request, inputs = _torqued_body(data, Path(source).resolve().parent)
    else:
        request, inputs = _BUILDERS[name](data)
    return Scenario(request, inputs, source)


def _schema(data: dict[str, Any]) -> type[BaseModel] | None:
    """The pydantic schema a scenario dict is validated against (None: unknown model)."""
    physical = "physical" in data
    return {
        "resisting_medium": RMPhysicalScenario if physical else RMScenario,
        "rotating_field": RFPhysicalScenario if physical else RFScenario,
        "nonlinear_moment": NMScenario,
        "torqued_body": TBScenario,
    }.get(str(data.get("model")))


def key_units(data: dict[str, Any], path: tuple[str | int, ...]) -> str:
    """The unit of a scenario key, as its description gives it (``"rad"`` for
    ``initial.theta``); ``""`` when it states none, or ``"deg"`` for a ``*_deg`` key.

    Parameters
    ----------
    data : dict
        The scenario (its model and physical-units choice select the schema).
    path : tuple
        The key, split into table names and list indices.
    """
    names = [part for part in path if isinstance(part, str)]
    if names and names[-1].endswith("_deg"):
        return "deg"
    schema = _schema(data)
    if schema is None:
        return ""
    hint, _ = _field_hint(schema, tuple(names))
    if not hint.endswith("]") or "[" not in hint:
        return ""
    unit = hint[hint.rindex("[") + 1 : -1]
    # "[0, π]" is a range, not a unit.
    return "" if "," in unit else unit


def load_scenario(path: str | Path) -> Scenario:
    """Read and validate a TOML scenario file.

    Parameters
    ----------
    path : str or Path
        The scenario file.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot read the scenario ({exc.strerror})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML ({exc})") from None
    return parse_scenario(data, str(path))


def template(model: str) -> str:
    """A commented example scenario for ``model`` (what ``tumble init`` prints)."""
    get_model(model)
    return resources.files("tumble.io").joinpath("templates", f"{model}.toml").read_text("utf-8")
