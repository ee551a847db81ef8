"""Compiled right-hand sides: what the compiled integrator integrates.

A :class:`Kernel` names a right-hand side of :mod:`tumble.kernels.rhs` by its kind and packs
its parameters into one float array, laid out as the kind declares (:mod:`tumble.kernels.kinds`,
:mod:`tumble.kernels.params`); the integrator of :mod:`tumble.integrate.dop853` runs it. The
torque terms are declared here too, one module each (:mod:`tumble.kernels.terms`): the classes
of :mod:`tumble.torques` evaluate them from Python, the right-hand sides from compiled code.
This package reads nothing of tumble but the errors, the types and one threshold of the
rotations (where 3-1-3 angles are singular), so that every other part may build on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tumble._typing import ArrayLike, FloatArray
from tumble.errors import ParameterError
from tumble.kernels.codes import (
    EVENT_EQUATOR,
    EVENT_FIELD_SEPARATRIX,
    EVENT_NONE,
    EVENT_NUTATION_SEPARATRIX,
    EVENT_THETA_DOT,
    EVENT_TRIAXIAL_SEPARATRIX,
    KIND_FIELD_AVERAGED,
    KIND_MEDIUM_AVERAGED,
    KIND_NONLINEAR_MOMENT,
    KIND_NUTATION_AVERAGED,
    KIND_NUTATION_ENGINE,
    KIND_ORBITING_BODY,
    KIND_RIGID_BODY,
    KIND_ROTATING_FIELD,
    KIND_SPINNER_AVERAGED,
    KIND_TRIAXIAL_AVERAGED,
    KIND_TRIAXIAL_CLOSED,
    KIND_TRIAXIAL_PHASE_MEANS,
)

__all__ = [
    "EVENT_EQUATOR",
    "EVENT_FIELD_SEPARATRIX",
    "EVENT_NONE",
    "EVENT_NUTATION_SEPARATRIX",
    "EVENT_THETA_DOT",
    "EVENT_TRIAXIAL_SEPARATRIX",
    "KIND_FIELD_AVERAGED",
    "KIND_MEDIUM_AVERAGED",
    "KIND_NONLINEAR_MOMENT",
    "KIND_NUTATION_AVERAGED",
    "KIND_NUTATION_ENGINE",
    "KIND_ORBITING_BODY",
    "KIND_RIGID_BODY",
    "KIND_ROTATING_FIELD",
    "KIND_SPINNER_AVERAGED",
    "KIND_TRIAXIAL_AVERAGED",
    "KIND_TRIAXIAL_CLOSED",
    "KIND_TRIAXIAL_PHASE_MEANS",
    "Kernel",
    "evaluate_rhs",
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
    terminal : bool
        Whether the run stops at the event's first zero (a breakpoint of the equations),
        rather than recording every zero.
    """

    kind: int
    params: FloatArray
    event: int = EVENT_NONE
    t_max: float = math.inf
    t_max_message: str = ""
    terminal: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "params", np.ascontiguousarray(self.params, dtype=np.float64))
        from tumble.kernels.kinds import KINDS  # the layouts' readers load numba: not at import

        declared = KINDS.get(int(self.kind))
        if declared is None:
            raise ParameterError(f"no right-hand side of kind {self.kind}")
        size, n = declared.params.size, self.params.size
        if n < size or (declared.params.tail is None and n != size):
            raise ParameterError(
                f"{declared.params.name}: {n} parameters, the layout declares {size}"
                + (" and a tail" if declared.params.tail else "")
            )
        if not declared.allows(int(self.event)):
            raise ParameterError(f"event {self.event} cannot watch {declared.name}")

    def check_end(self, t_end: float) -> None:
        """ParameterError if the run needs times beyond ``t_max``."""
        if t_end > self.t_max:
            raise ParameterError(self.t_max_message or f"the run ends after t = {self.t_max:g}")


def evaluate_rhs(kernel: Kernel, t: float, y: ArrayLike) -> FloatArray:
    """dy/dt of a compiled kernel at one state (for tests against the Python forms)."""
    from tumble.kernels.rhs import evaluate  # compiled: loaded on first use

    state = np.ascontiguousarray(y, dtype=np.float64)
    return evaluate(kernel.kind, float(t), state, kernel.params)  # type: ignore[no-any-return]
