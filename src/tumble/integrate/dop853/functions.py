"""What the integrator calls of a right-hand side, compiled once per kind and passed to the
loop as function pointers.

The loop (:func:`~.core.advance`), the step-size control, the interpolant and the location of
events do not depend on the right-hand side: they are compiled once, with three first-class
function arguments of fixed types,

- :data:`STEP`, ``step(p, t, h, y, K, y_new, tmp, rtol, atol, extended)``: the stages of a
  step, its new state, the derivative there and its error, or the extra stages of its
  interpolant
  (:func:`~.steps.step_stages`, with the kind's right-hand side inlined into its loops),
- :data:`RHS`, ``rhs(t, y, p, out)``: one evaluation (the start, the starting step),
- :data:`EVENT`, ``event(t, y, p)``: the event function the run watches.

Each kind compiles only these small functions, with its kind a compile-time constant, and
each event code its own: a cold start compiles the loop once and the right-hand sides a run
uses (rather than the whole integrator again for every kind). A call through a pointer costs
a few nanoseconds, one per step against the 12 evaluations it makes.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

from numba import types

from tumble.integrate.dop853.steps import step_stages
from tumble.kernels.codes import EVENT_NONE
from tumble.kernels.jit import KERNEL, jit
from tumble.kernels.rhs import event, rhs

__all__ = ["EVENT", "RHS", "STEP", "KindFunctions", "event_function", "kind_functions"]

_VEC = types.Array(types.float64, 1, "C")
_MAT = types.Array(types.float64, 2, "C")

STEP = types.FunctionType(
    types.float64(
        _VEC,
        types.float64,
        types.float64,
        _VEC,
        _MAT,
        _VEC,
        _VEC,
        types.float64,
        types.float64,
        types.boolean,
    )
)
"""``step(p, t, h, y, K, y_new, tmp, rtol, atol, extended)``: :func:`~.steps.step_stages` of
a kind."""

RHS = types.FunctionType(types.void(types.float64, _VEC, _VEC, _VEC))
"""``rhs(t, y, p, out)``: dy/dt into ``out``."""

EVENT = types.FunctionType(types.float64(types.float64, _VEC, _VEC))
"""``event(t, y, p)``: the event function whose sign changes the run locates."""

# A function Python passes to compiled code as a pointer needs its C wrapper.
_POINTER = {**KERNEL, "no_cfunc_wrapper": False}


class KindFunctions(NamedTuple):
    """The compiled functions of one right-hand-side kind."""

    step: Any
    rhs: Any


_KINDS: dict[int, KindFunctions] = {}
_EVENTS: dict[int, Any] = {}


def _compiled(signature: Any, func: Callable[..., Any]) -> Any:
    """``func`` compiled now for ``signature`` (a disk-cached, pointer-ready dispatcher)."""
    dispatcher = jit(_POINTER)(func)
    dispatcher.compile(signature.signature)
    return dispatcher


def kind_functions(kind: int) -> KindFunctions:
    """The step's stages and the right-hand side of ``kind`` (``KIND_*``), compiled on first
    use.

    ``kind`` is a constant of the closures, which numba types as a literal: the right-hand
    side's dispatch (:func:`tumble.kernels.rhs.rhs`) folds to that kind's kernel, and numba's
    cache tells the kinds apart by the closure's values.
    """
    got = _KINDS.get(kind)
    if got is None:

        def kind_step(p, t, h, y, K, y_new, tmp, rtol, atol, extended):  # type: ignore[no-untyped-def]
            return step_stages(kind, p, t, h, y, K, y_new, tmp, rtol, atol, extended)

        def kind_rhs(t, y, p, out):  # type: ignore[no-untyped-def]
            rhs(kind, t, y, p, out)

        got = KindFunctions(_compiled(STEP, kind_step), _compiled(RHS, kind_rhs))
        _KINDS[kind] = got
    return got


def event_function(code: int) -> Any:
    """The event function ``code`` (``EVENT_*``; ``EVENT_NONE``: none, a constant 1),
    compiled on first use."""
    got = _EVENTS.get(code)
    if got is None:
        if code == EVENT_NONE:

            def watched(t, y, p):  # type: ignore[no-untyped-def]
                return 1.0

        else:

            def watched(t, y, p):  # type: ignore[no-untyped-def]
                return event(code, t, y, p)

        got = _compiled(EVENT, watched)
        _EVENTS[code] = got
    return got
