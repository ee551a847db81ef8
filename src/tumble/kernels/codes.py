"""The integer codes compiled code dispatches on: right-hand sides, events and torque terms.

Plain constants, apart from the compiled code that reads them, so that the classes which
pack a kernel's parameters (:mod:`tumble.torques`, the models' parameters) load without
numba; the compiled modules import them from here.
"""

from __future__ import annotations

__all__ = [
    "EVENT_FIELD_SEPARATRIX",
    "EVENT_NONE",
    "EVENT_THETA_DOT",
    "KIND_FIELD_AVERAGED",
    "KIND_MEDIUM_AVERAGED",
    "KIND_NONLINEAR_MOMENT",
    "KIND_RIGID_BODY",
    "KIND_ROTATING_FIELD",
    "RATE_ONLY_TERMS",
    "TERM_BODY_CONSTANT",
    "TERM_EDDY_CURRENT",
    "TERM_GRAVITY_GRADIENT",
    "TERM_INERTIAL_CONSTANT",
    "TERM_LINEAR_DRAG",
    "TERM_PAYLOAD",
    "TERM_QUADRATIC_DRAG",
]

KIND_RIGID_BODY = 1
KIND_ROTATING_FIELD = 2
KIND_NONLINEAR_MOMENT = 3
KIND_MEDIUM_AVERAGED = 4
KIND_FIELD_AVERAGED = 5

EVENT_NONE = 0
EVENT_THETA_DOT = 1
"""Zeros of θ' of the nonlinear-moment quaternion form: the extrema of θ(t)."""
EVENT_FIELD_SEPARATRIX = 2
"""r − 1/I2 of the rotating field's averaged vector form: its separatrix."""

TERM_BODY_CONSTANT = 1  # body moment (3)
TERM_LINEAR_DRAG = 2  # B by rows (9)
TERM_QUADRATIC_DRAG = 3  # S by rows (9)
TERM_INERTIAL_CONSTANT = 4  # inertial moment (3)
TERM_GRAVITY_GRADIENT = 5  # inertia (3), n, u0, rows e1, e2, normal (9)
TERM_EDDY_CURRENT = 6  # M0, field rate ω, cone angle β

TERM_PAYLOAD: dict[int, int] = {
    TERM_BODY_CONSTANT: 3,
    TERM_LINEAR_DRAG: 9,
    TERM_QUADRATIC_DRAG: 9,
    TERM_INERTIAL_CONSTANT: 3,
    TERM_GRAVITY_GRADIENT: 14,
    TERM_EDDY_CURRENT: 3,
}
"""Length of each term code's payload (the stride of a torque program)."""

RATE_ONLY_TERMS = frozenset({TERM_BODY_CONSTANT, TERM_LINEAR_DRAG, TERM_QUADRATIC_DRAG})
"""Terms that read neither the attitude nor the time."""
