"""A new model in one module: a symmetric top spinning in a viscous medium.

A dynamically symmetric body (equatorial moment A, axial moment C) under the isotropic drag
M = −ε b ω. Its full equations are Euler's with quaternion kinematics; the drag commutes with
the free motion, so each component of ω in body axes decays at its own rate,

    ω⊥(t) = ω⊥(0) exp(−ε b t / A),     ω3(t) = ω3(0) exp(−ε b t / C),

which is at once the averaged motion (the transverse rate's magnitude and the spin do not
depend on the precession phase) and its closed form. This file is the example of the
architecture page: the model contract filled in for a model that is not in the package, with
its scenario keys, used by a test (registration, a scenario file, full against averaged
against closed form).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from tumble._typing import FloatArray
from tumble.dynamics import rigid_body_kernel, rigid_body_rhs, rigid_body_state
from tumble.errors import check_range
from tumble.kernels import Kernel
from tumble.models.base import (
    Averaged,
    AveragedForm,
    AveragingOptions,
    ClosedForm,
    Column,
    Columns,
    Full,
    FullForm,
    Model,
    Unperturbed,
    fixed_columns,
)
from tumble.models.schema import Built, Key, ScenarioSchema, Section, Variant
from tumble.torques import LinearDrag
from tumble.unperturbed.euler_poinsot import EulerPoinsot


@dataclass(frozen=True, slots=True)
class Params:
    """Physics only: the moments of inertia, the drag coefficient and ε."""

    A: float  # equatorial moment of inertia [inertia unit]
    C: float  # axial moment of inertia [inertia unit]
    b: float  # drag coefficient [moment unit · time]
    eps: float = 0.01  # small parameter ε [1]

    def __post_init__(self) -> None:
        check_range("parameters.A", self.A, low=0.0)
        check_range("parameters.C", self.C, low=0.0, high=2.0 * self.A, high_open=False)
        check_range("parameters.b", self.b, low=0.0, low_open=False)
        check_range("parameters.eps", self.eps, low=0.0, low_open=False)

    @property
    def inertia(self) -> FloatArray:
        return np.array([self.A, self.A, self.C])


@dataclass(frozen=True, slots=True)
class State:
    """The body angular velocity [rad/time] and attitude quaternion (scalar first, body →
    inertial) at t = 0."""

    omega: tuple[float, float, float]
    q: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)


def full_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """Euler's equations with quaternions under M = −ε b ω."""
    return rigid_body_rhs(t, y, p.inertia, LinearDrag(p.eps * p.b * np.eye(3)))


def full_kernel(p: Params) -> Kernel | None:
    """The same right-hand side compiled."""
    return rigid_body_kernel(p.inertia, LinearDrag(p.eps * p.b * np.eye(3)))


def _initial_state(p: Params, st: State) -> FloatArray:
    return rigid_body_state(np.array(st.omega), np.array(st.q))


def _state_of(p: Params, y: FloatArray) -> State:
    w, q = (float(v) for v in y[:3]), (float(v) for v in y[3:])
    return State(tuple(w), tuple(q))  # type: ignore[arg-type]


def _rates(p: Params, t: FloatArray, Y: FloatArray) -> Columns:
    Y = np.atleast_2d(Y)
    return {"w_perp": np.hypot(Y[:, 0], Y[:, 1]), "w3": Y[:, 2].copy()}


def _invariants(p: Params, Y: FloatArray) -> Columns:
    """|L| and the energy: constant when ε = 0."""
    w = np.atleast_2d(Y)[:, :3]
    L = w * p.inertia
    return {"L": np.linalg.norm(L, axis=1), "T": 0.5 * np.sum(w * L, axis=1)}


def _averaged_rhs(t: float, y: FloatArray, p: Params) -> FloatArray:
    """d(ω⊥, ω3)/dt = −ε b (ω⊥/A, ω3/C)."""
    return -p.eps * p.b * np.array([y[0] / p.A, y[1] / p.C])


def _averaged_form(p: Params, st: State, options: AveragingOptions) -> AveragedForm[Params, State]:
    def initial(p: Params, st: State) -> FloatArray:
        return np.array([math.hypot(st.omega[0], st.omega[1]), st.omega[2]])

    def to_columns(p: Params, st: State, t: FloatArray, Y: FloatArray) -> Columns:
        Y = np.atleast_2d(Y)
        return {"w_perp": Y[:, 0].copy(), "w3": Y[:, 1].copy()}

    equation = "d(ω⊥, ω3)/dt = −εb(ω⊥/A, ω3/C)"
    return AveragedForm("rates", equation, ("w_perp", "w3"), _averaged_rhs, initial, to_columns)


def closed_form(p: Params, st: State, t: FloatArray) -> Columns:
    """ω⊥(0) exp(−εbt/A) and ω3(0) exp(−εbt/C)."""
    t = np.asarray(t, dtype=float)
    w_perp0 = math.hypot(st.omega[0], st.omega[1])
    return {
        "w_perp": w_perp0 * np.exp(-p.eps * p.b * t / p.A),
        "w3": st.omega[2] * np.exp(-p.eps * p.b * t / p.C),
    }


def _check(p: Params, method: str) -> None:
    """Every method applies to every valid parameter set."""


COLUMNS = fixed_columns(
    (
        Column("w_perp", "transverse rate |(ω1, ω2)|", "rad/t"),
        Column("w3", "spin ω3", "rad/t"),
    )
)

FULL: FullForm[Params, State] = FullForm(
    "quaternion", "Euler + quaternions", ("w1", "w2", "w3", "q0", "q1", "q2", "q3"), full_rhs,
    _initial_state, _rates, _state_of, full_kernel, _invariants,
)  # fmt: skip

SCENARIO: ScenarioSchema[Params, State] = ScenarioSchema(
    variants=(
        Variant(
            (
                Section(
                    "parameters",
                    (
                        Key("A", "number", "a number > 0", doc="equatorial moment of inertia"),
                        Key("C", "number", "a number in (0, 2A]", doc="axial moment of inertia"),
                        Key("b", "number", "a number ≥ 0", doc="drag coefficient"),
                        Key("eps", "number", "a number ≥ 0", default=0.01, doc="ε"),
                    ),
                ),
                Section(
                    "initial",
                    (Key("omega", "vector3", "3 numbers", "rad/t", doc="body angular velocity"),),
                ),
            ),
            lambda inputs: Built(
                Params(**inputs["parameters"]),  # type: ignore[arg-type]
                State(tuple(inputs["initial"]["omega"])),  # type: ignore[index]
            ),
        ),
    )
)

MODEL: Model[Params, State] = Model(
    name="damped_top",
    description="symmetric top under isotropic viscous drag (the architecture page's example)",
    paper=None,
    time=Column("t", "time t", "t"),
    full=Full(forms={"quaternion": FULL}, default="quaternion", columns=COLUMNS),
    check=_check,
    methods=("full", "averaged", "closed_form"),
    averaged=Averaged(form=_averaged_form, columns=COLUMNS, compare=("w_perp", "w3")),
    closed_form=ClosedForm(evaluate=closed_form, columns=COLUMNS),
    unperturbed=Unperturbed(
        "the free symmetric top",
        lambda p, st: EulerPoinsot.from_rigid_body_state(p.inertia, _initial_state(p, st)).states,
        lambda t, y, p: full_rhs(t, y, replace(p, eps=0.0)),
    ),
    scenario=SCENARIO,
)
