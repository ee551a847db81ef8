"""What the integrator calls of a right-hand side, compiled once per kind and passed to the
loop by address.

The loop (:func:`~.core.advance`), the step-size control, the interpolant and the location of
events do not depend on the right-hand side: they are compiled once, with three first-class
function arguments of fixed types,

- :data:`STEP`, ``step(rhs, p, t, h, y, K, y_new, tmp, rtol, atol, extended)``: the stages of
  a step, its new state, the derivative there and its error, or the extra stages of its
  interpolant (:func:`~.steps.step_stages`),
- :data:`RHS`, ``rhs(t, y, p, out)``: one evaluation,
- :data:`EVENT`, ``event(t, y, p)``: the event function the run watches.

A kind whose right-hand side is short (``Kind.inlined``) compiles its own step, with the
right-hand side inlined into the unrolled stages, where the compiler keeps its parameters in
registers across them. A long one (an averaging engine, the terms along an orbit) would be
copied sixteen times into that step and optimised again at every level of the calls that
inline it, which was most of its compile time: those kinds share one step, compiled once, that
calls the right-hand side it is given, and compile only their right-hand side (a call through
a pointer costs nanoseconds against the microseconds of such an evaluation). Each event code
compiles its own function. The loop receives the addresses as plain integers
(:func:`addresses`) and turns them back into functions (:func:`function_at`); the functions
are kept for the life of the process, so that the addresses stay valid.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple, cast

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.experimental.function_type import _get_jit_address, _get_wrapper_address
from numba.extending import intrinsic

from tumble.integrate.dop853.steps import step_stages
from tumble.kernels.codes import EVENT_NONE
from tumble.kernels.jit import KERNEL, compile_lock, jit
from tumble.kernels.kinds import KINDS
from tumble.kernels.rhs import event, rhs

__all__ = [
    "EVENT",
    "RHS",
    "STEP",
    "Compiled",
    "KindFunctions",
    "addresses",
    "event_function",
    "function_at",
    "kind_functions",
]

_VEC = types.Array(types.float64, 1, "C")
_MAT = types.Array(types.float64, 2, "C")

RHS = types.FunctionType(types.void(types.float64, _VEC, _VEC, _VEC))
"""``rhs(t, y, p, out)``: dy/dt into ``out``."""

STEP = types.FunctionType(
    types.float64(
        RHS,
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
"""``step(rhs, p, t, h, y, K, y_new, tmp, rtol, atol, extended)``: :func:`~.steps.step_stages`
of a kind (which calls ``rhs``, the kind's :data:`RHS`, unless it compiles it in)."""

EVENT = types.FunctionType(types.float64(types.float64, _VEC, _VEC))
"""``event(t, y, p)``: the event function whose sign changes the run locates."""

# A function Python passes to compiled code as a pointer needs its C wrapper.
_POINTER = {**KERNEL, "no_cfunc_wrapper": False}


class Compiled(NamedTuple):
    """A function compiled for a function type, and the two addresses by which compiled code
    calls it (:func:`function_at`): its C wrapper's and its own (numba's calling convention,
    the one a call takes when it has it).

    Passing a dispatcher itself as a first-class function makes numba look both addresses up
    by name at every call from Python (0.1 ms a run, which a short averaged run feels); these
    are looked up once.
    """

    dispatcher: Any
    c_address: int
    jit_address: int

    @classmethod
    def of(cls, dispatcher: Any, ftype: Any) -> Compiled:
        """``dispatcher``, compiled for the function type ``ftype``, with its addresses."""
        return cls(
            dispatcher,
            _get_wrapper_address(dispatcher, ftype.signature),
            _get_jit_address(dispatcher, ftype.signature),
        )


@intrinsic
def _function_at(typingctx: Any, c_address: Any, jit_address: Any, ftype: Any) -> Any:
    """``function_at(c_address, jit_address, FTYPE)``: in compiled code, the first-class
    function of type ``FTYPE`` (:data:`STEP`, :data:`RHS` or :data:`EVENT`) at those addresses
    (:class:`Compiled`), called as any other; the addresses arrive as plain integers, which
    cost nothing to pass from Python."""
    fnty = ftype.instance_type

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        pointer = context.get_value_type(types.voidptr)
        made = cgutils.create_struct_proxy(fnty)(context, builder)
        made.c_addr = builder.inttoptr(args[0], pointer)
        made.jit_addr = builder.inttoptr(args[1], pointer)
        made.py_addr = ir.Constant(pointer, None)
        return made._getvalue()

    return fnty(types.intp, types.intp, ftype), codegen


function_at = cast(Callable[[int, int, Any], Any], _function_at)
"""``function_at(c_address, jit_address, FTYPE)`` from compiled code (the intrinsic above, typed
for the callers)."""


class KindFunctions(NamedTuple):
    """The compiled functions of one right-hand-side kind."""

    step: Compiled
    rhs: Compiled


_KINDS: dict[int, KindFunctions] = {}
_EVENTS: dict[int, Compiled] = {}
_CALLED: list[Compiled] = []


def called_step(rhs_fn, p, t, h, y, K, y_new, tmp, rtol, atol, extended):  # type: ignore[no-untyped-def]
    """The step of every kind whose right-hand side is not inlined: it calls ``rhs_fn``."""
    return step_stages(rhs_fn, p, t, h, y, K, y_new, tmp, rtol, atol, extended)


def _called_step() -> Compiled:
    """:func:`called_step`, compiled on first use."""
    if not _CALLED:
        with compile_lock("called-step"):
            _CALLED.append(_compiled(STEP, called_step))
    return _CALLED[0]


def _compiled(ftype: Any, func: Callable[..., Any]) -> Compiled:
    """``func`` compiled now for the function type ``ftype`` (disk-cached)."""
    dispatcher = cast(Any, jit(_POINTER)(func))
    dispatcher.compile(ftype.signature)
    return Compiled.of(dispatcher, ftype)


def kind_functions(kind: int) -> KindFunctions:
    """The step's stages and the right-hand side of ``kind`` (``KIND_*``), compiled on first
    use: the kind's own step if its right-hand side is inlined (``Kind.inlined``), else the
    shared :func:`called_step`.

    ``kind`` is a constant of the closures, which numba types as a literal: the right-hand
    side's dispatch (:func:`tumble.kernels.rhs.rhs`) folds to that kind's kernel, and numba's
    cache tells the kinds apart by the closure's values.
    """
    got = _KINDS.get(kind)
    if got is None:

        def kind_step(rhs_fn, p, t, h, y, K, y_new, tmp, rtol, atol, extended):  # type: ignore[no-untyped-def]
            return step_stages(kind, p, t, h, y, K, y_new, tmp, rtol, atol, extended)

        def kind_rhs(t, y, p, out):  # type: ignore[no-untyped-def]
            rhs(kind, t, y, p, out)

        # Another process compiling the kind: load it after. (The shared step takes its own
        # lock inside this one; nothing takes them the other way round.)
        with compile_lock(f"kind-{kind}"):
            step = _compiled(STEP, kind_step) if KINDS[kind].inlined else _called_step()
            got = KindFunctions(step, _compiled(RHS, kind_rhs))
        _KINDS[kind] = got
    return got


def event_function(code: int) -> Compiled:
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

        with compile_lock(f"event-{code}"):
            got = _compiled(EVENT, watched)
        _EVENTS[code] = got
    return got


def addresses(kind: int, event: int) -> tuple[int, int, int, int, int, int]:
    """What the loop (:func:`~.core.advance`) takes of the kind ``kind`` and the event
    ``event``: the addresses of the step, the right-hand side and the event function, each
    (C wrapper, numba's own), compiling them on first use."""
    fns, watched = kind_functions(kind), event_function(event)
    return (fns.step.c_address, fns.step.jit_address, fns.rhs.c_address,
            fns.rhs.jit_address, watched.c_address, watched.jit_address)  # fmt: skip
