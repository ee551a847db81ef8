"""Output columns: the metadata every model's outputs carry (symbol, long name, unit, the
equation they come from), and the columns every model shares: its time, the attitude and
body rate of a full run, and the mean variables of an averaging of order 2."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TypeAlias

import numpy as np

from tumble._typing import FloatArray

__all__ = [
    "QUATERNION_STATE",
    "TIME_T",
    "TIME_TAU",
    "Column",
    "Columns",
    "attitude_columns",
    "attitude_values",
    "fixed_columns",
    "mean_columns",
]

Columns: TypeAlias = dict[str, FloatArray]
"""Output columns by name, each an array over the sample times."""


@dataclass(frozen=True, slots=True)
class Column:
    """Metadata of one output column; exports and axis labels read it, never retype it."""

    name: str
    long_name: str
    units: str
    equation: str = ""
    angle: bool = False  # compare modulo 2π
    unwrap: bool = False  # written as a continuous function of time (theory/resisting-medium §14)


TIME_TAU = Column("tau", "time τ", "1")
"""The time column of a model in a normalised time τ of its paper [1]."""
TIME_T = Column("t", "time t", "t")
"""The time column of a model in the time t of its coefficients [t]."""


def mean_columns(columns: Iterable[Column]) -> tuple[Column, ...]:
    """The columns ``<name>_mean`` of the mean variables of an averaging of order 2, one for
    each of ``columns``: the same unit, equation and angle flag (a mean angle is written as it
    is, not unwrapped)."""
    return tuple(
        Column(f"{c.name}_mean", f"mean {c.long_name} (averaging of order 2)", c.units,
               c.equation, angle=c.angle)
        for c in columns
    )  # fmt: skip


QUATERNION_STATE = ("w1", "w2", "w3", "q0", "q1", "q2", "q3")
"""The components of a full state of Euler's equations with quaternion kinematics: the body
angular velocity ω, then the attitude quaternion q (scalar first, body → inertial)."""


def attitude_columns(time: str) -> tuple[Column, ...]:
    """The attitude and body angular velocity every full run writes, in a model whose time
    is called ``time`` ("τ", "t").

    The attitude quaternion q = (q0, q1, q2, q3) is scalar first and maps body components to
    inertial ones, v_inertial = R(q) v_body (:mod:`tumble.rotations`), of unit norm and with
    q0 ≥ 0 (q and −q are one attitude: every form of every model writes the same one, at the
    cost of a change of sign where q0 passes 0); ω = (ω1, ω2, ω3) is the body angular velocity
    in body axes, in the model's normalised units (rad per unit of its time)."""
    parts = ("scalar part", "x component", "y component", "z component")
    return (
        *(Column(f"q{i}", f"attitude quaternion q{i}, {part} (body → inertial)", "1",
                 "dq/dt = ½ q ⊗ (0, ω)") for i, part in enumerate(parts)),
        *(Column(f"omega{i}", f"body angular velocity ω{i} about body axis x{i}", f"rad/{time}",
                 "Euler's equations") for i in (1, 2, 3)),
    )  # fmt: skip


def attitude_values(q: FloatArray, omega: FloatArray) -> Columns:
    """The columns of :func:`attitude_columns` of quaternions ``q`` (shape (n, 4), scalar first,
    body → inertial; normalised here, q0 ≥ 0) and body angular velocities ``omega`` (shape
    (n, 3))."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    q = np.where(q[:, :1] < 0.0, -q, q)
    omega = np.asarray(omega, dtype=float)
    out = {f"q{i}": q[:, i] for i in range(4)}
    out |= {f"omega{i + 1}": omega[:, i] for i in range(3)}
    return out


def fixed_columns(columns: tuple[Column, ...]) -> Callable[[object], tuple[Column, ...]]:
    """Columns that do not depend on the parameters, in the form the capabilities take."""

    def of(_p: object) -> tuple[Column, ...]:
        return columns

    return of
