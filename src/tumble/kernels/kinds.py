"""The right-hand-side kinds, declared: each kind's state, its parameters' layout and the event
functions that may watch it.

:class:`tumble.kernels.Kernel` checks every kernel against these declarations when it is built:
a parameter array of another length than the kind's layout (with its tail), or an event the
kind does not declare, is refused, so that no event reads a slot of another kind's layout.
"""

from __future__ import annotations

from dataclasses import dataclass

from tumble.kernels import codes
from tumble.kernels.layout import Layout
from tumble.kernels.params import (
    FIELD_AVERAGED,
    MEDIUM_AVERAGED,
    NONLINEAR_MOMENT,
    RIGID_BODY,
    ROTATING_FIELD,
    SPINNER_AVERAGED,
    TRIAXIAL_AVERAGED,
)

__all__ = ["KINDS", "Kind"]


@dataclass(frozen=True)
class Kind:
    """A right-hand side's declaration.

    Attributes
    ----------
    name : str
        What it integrates.
    state : tuple of str
        Its state variables, in order (a tuple of one entry per variable; a state of variable
        length, such as [W, V] or [k, ϑ], lists the longer).
    params : Layout
        Its parameters.
    events : frozenset of int
        The ``EVENT_*`` functions that may watch it (``codes.EVENT_NONE`` always may).
    compile_s : float
        About how long its functions take to compile from an empty cache [s] (CPU time
        measured on 2 cores; what the compile notice announces).
    inlined : bool
        Whether the integrator's step compiles the right-hand side into its stages (a short
        one, whose parameters then stay in registers across them) or calls it (a long one,
        which would otherwise be compiled into the step sixteen times).
    slow : bool
        Whether its state moves on the slow time (averaged equations, rates of order ε): the
        compiled integrator then starts it with no step shorter than the time of a 1 % change
        (:data:`tumble.integrate.dop853.core.SLOW_START`), where Hairer's estimate would start
        it at 1e-5 to 1e-4 of the step its tolerance allows.
    """

    name: str
    state: tuple[str, ...]
    params: Layout
    events: frozenset[int] = frozenset()
    compile_s: float = 2.5
    inlined: bool = True
    slow: bool = False

    def allows(self, event: int) -> bool:
        """Whether ``event`` may watch this kind."""
        return event == codes.EVENT_NONE or event in self.events


_BODY = ("w1", "w2", "w3", "q0", "q1", "q2", "q3")
_SLOW = ("L1", "L2", "L3", "r")
_ENERGY = ("H", "R", "G", "a", "b")
# Volosov's equations and the engine's nutation setting: one state, layout and event.
_NUTATION = (_ENERGY, NONLINEAR_MOMENT, frozenset({codes.EVENT_NUTATION_SEPARATRIX}))
# The triaxial engine's three ways (closed form, phase means, product rule): one state, layout
# and event.
_TRIAXIAL = (_SLOW, TRIAXIAL_AVERAGED, frozenset({codes.EVENT_TRIAXIAL_SEPARATRIX}))

KINDS: dict[int, Kind] = {
    codes.KIND_RIGID_BODY: Kind(
        "Euler's equations under a torque program", _BODY, RIGID_BODY, compile_s=5.0
    ),
    codes.KIND_ORBITING_BODY: Kind(
        "Euler's equations under every term (along an orbit, calling out)",
        _BODY,
        RIGID_BODY,
        compile_s=9.5,
        inlined=False,
    ),
    codes.KIND_ROTATING_FIELD: Kind(
        "the rotating field's form (1.5)",
        ("z1", "z2", "z3", *(f"g{r}{c}" for r in range(1, 4) for c in range(1, 4))),
        ROTATING_FIELD,
    ),
    codes.KIND_NONLINEAR_MOMENT: Kind(
        "the nonlinear moment's Euler equations (1.1)",
        _BODY,
        NONLINEAR_MOMENT,
        frozenset({codes.EVENT_THETA_DOT}),
    ),
    codes.KIND_MEDIUM_AVERAGED: Kind(
        "the averaged equations (2.2)/(2.3)", ("k", "theta", "phi"), MEDIUM_AVERAGED, slow=True
    ),
    codes.KIND_FIELD_AVERAGED: Kind(
        "the rotating field's averaged vector form",
        _SLOW,
        FIELD_AVERAGED,
        frozenset({codes.EVENT_FIELD_SEPARATRIX}),
        compile_s=3.0,
        slow=True,
    ),
    codes.KIND_NUTATION_AVERAGED: Kind(
        "Volosov's averaged equations in the energy form",
        *_NUTATION,
        compile_s=5.5,
        inlined=False,
        slow=True,
    ),
    codes.KIND_NUTATION_ENGINE: Kind(
        "the engine's nutation setting", *_NUTATION, compile_s=9.5, inlined=False, slow=True
    ),
    codes.KIND_SPINNER_AVERAGED: Kind(
        "the engine's spinner setting",
        ("k", "rho", "sigma", "theta"),
        SPINNER_AVERAGED,
        frozenset({codes.EVENT_EQUATOR}),
        inlined=False,
        slow=True,
    ),
    codes.KIND_TRIAXIAL_AVERAGED: Kind(
        "the engine's triaxial setting, the product rule",
        *_TRIAXIAL,
        compile_s=8.0,
        inlined=False,
        slow=True,
    ),
    codes.KIND_TRIAXIAL_PHASE_MEANS: Kind(
        "the engine's triaxial setting, the phases averaged exactly",
        *_TRIAXIAL,
        compile_s=8.0,
        inlined=False,
        slow=True,
    ),
    codes.KIND_TRIAXIAL_CLOSED: Kind(
        "the engine's triaxial setting in closed form",
        *_TRIAXIAL,
        compile_s=7.0,
        inlined=False,
        slow=True,
    ),
}
"""Every kind the compiled right-hand side (:func:`tumble.kernels.rhs.rhs`) knows. The compile
times are each kind's functions alone from an empty cache, CPU time on 2 cores (the averaging
engines compile their quadratures and every term's averages)."""
