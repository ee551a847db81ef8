"""Compiled right-hand sides: what the compiled integrator integrates.

A :class:`Kernel` names a right-hand side of :mod:`tumble.kernels.rhs` by its kind and packs
its parameters into one float array. The models build their kernels here
(:func:`rigid_body_kernel` for any rigid body under built-in torques); the integrator of
:mod:`tumble.integrate.dop853` runs them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.rhs import (
    EVENT_NONE,
    EVENT_THETA_DOT,
    KIND_NONLINEAR_MOMENT,
    KIND_RIGID_BODY,
    KIND_ROTATING_FIELD,
    evaluate,
)
from tumble.torques import Torque

__all__ = [
    "EVENT_NONE",
    "EVENT_THETA_DOT",
    "KIND_NONLINEAR_MOMENT",
    "KIND_RIGID_BODY",
    "KIND_ROTATING_FIELD",
    "Kernel",
    "evaluate_rhs",
    "rigid_body_kernel",
    "torque_program",
]


@dataclass(frozen=True)
class Kernel:
    """A compiled right-hand side: its kind, its parameter array and its event function.

    Attributes
    ----------
    kind : int
        One of the ``KIND_*`` constants.
    params : ndarray
        The parameters, packed as the kind reads them.
    event : int
        ``EVENT_*`` whose zeros are located during the integration (0: none).
    t_max : float
        Last time the parameters cover (e.g. a pressure table); integrating beyond it is an
        error with ``t_max_message``.
    """

    kind: int
    params: FloatArray
    event: int = EVENT_NONE
    t_max: float = math.inf
    t_max_message: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", np.ascontiguousarray(self.params, dtype=np.float64))

    def check_end(self, t_end: float) -> None:
        """ParameterError if the run needs times beyond ``t_max``."""
        if t_end > self.t_max:
            raise ParameterError(self.t_max_message or f"the run ends after t = {self.t_max:g}")


def torque_program(torque: Torque | None) -> FloatArray | None:
    """A torque as the flat program the compiled kernels evaluate, or None if one of its terms
    is a Python function.

    Layout: ``[number of terms, (code, factor, payload...)...]``, codes and payloads as in
    :mod:`tumble.torques`.
    """
    if torque is None:
        return np.zeros(1)
    terms = torque.compiled_terms()
    if terms is None:
        return None
    flat: list[float] = [float(len(terms))]
    for code, factor, payload in terms:
        flat += [float(code), float(factor), *(float(v) for v in payload)]
    return np.array(flat)


def rigid_body_kernel(inertia: ArrayLike, torque: Torque | None) -> Kernel | None:
    """The kernel of Euler's equations with quaternions (tumble.dynamics.rigid_body_rhs) for
    principal moments ``inertia`` [inertia unit] under ``torque``; None if the torque is a
    Python function."""
    program = torque_program(torque)
    if program is None:
        return None
    return Kernel(KIND_RIGID_BODY, np.concatenate([np.asarray(inertia, dtype=float), program]))


def evaluate_rhs(kernel: Kernel, t: float, y: Any) -> FloatArray:
    """dy/dt of a compiled kernel at one state (for tests against the Python forms)."""
    state = np.ascontiguousarray(y, dtype=np.float64)
    return evaluate(kernel.kind, float(t), state, kernel.params)  # type: ignore[no-any-return]
