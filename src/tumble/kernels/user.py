"""A user's torque written as a numba function, called from the compiled right-hand sides, and
kept from harming the run.

A function ``f(t, q, omega, params) -> body moment`` compiled with ``numba.njit`` is compiled
again from its source with bounds checking (:func:`checked_function`) and wrapped once per
process in a C callback (:func:`compiled_user_torque`) of one fixed signature,

    void (double t, double q0, q1, q2, q3, double w1, w2, w3,
          const double *params, int64 n, double *moment, double *record),

whose address a torque program carries as a number (a user term, ``TERM_USER``: the address,
the fault record's, n, then the n parameters). The compiled code calls it through that address
(:func:`call_user`), so the integrators are compiled, and cached on disk, once for every user
function: only the small callback is compiled for each.

The function receives q and omega as float arrays of 4 and 3, and ``params`` as a float array
of its n parameters (a scenario's ``[torque_params]`` values, in their order); it returns the
body moment as 3 numbers. Where the compiled code knows only the attitude matrix (the general
averaging engine), q is the quaternion of that matrix, up to its sign: such a torque must not
depend on the sign, as any attitude-dependent torque must not.

**Faults.** An exception cannot leave a C callback: numba would print it and go on with
whatever the moment buffer held, for every call (a flood of "Exception ignored" lines and a
wrong result, or a hang). The callback therefore catches every exception of the function (a
``raise``, a division by zero, an index out of bounds: bounds are checked), and checks that the
moment is finite; on a fault it returns a NaN moment, which makes the integrator reject the
step until it stops, and writes the first fault (its kind, t, q and ω) to the torque's *fault
record*, a small array kept here (:func:`fault_record`). The integrator's driver looks at the
records after every compiled call (:func:`raise_fault`) and raises :class:`~tumble.errors.
UserCodeError` naming the function, the time, the state and, reproduced in Python, the
exception. A function that never returns is stopped from outside the compiled call, by the
heartbeat ``calls`` counts (:meth:`tumble.integrate.dop853.Integration.advance`,
:mod:`tumble.app.guard`). What cannot be checked: the bounds inside other numba functions it
calls, which keep their own options.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import Any, NamedTuple, cast

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from tumble.errors import UserCodeError, shorten, state_text

__all__ = [
    "RECORD_SIZE",
    "SIGNATURE",
    "any_armed",
    "armed_names",
    "call_user",
    "calls",
    "checked_function",
    "compiled_user_torque",
    "fault_record",
    "is_numba_function",
    "probe",
    "raise_fault",
]

SIGNATURE = types.void(
    types.float64,
    *(types.float64,) * 4,
    *(types.float64,) * 3,
    types.CPointer(types.float64),
    types.int64,
    types.CPointer(types.float64),
    types.CPointer(types.float64),
)
"""The C signature of the callback: t, q (4), ω (3), the parameters and their number, the
moment written to a buffer of 3, and the fault record."""

RECORD_SIZE = 10
"""A fault record: [fault (0: none), t, q0, q1, q2, q3, ω1, ω2, ω3, calls]; ``calls`` counts
the calls begun, the heartbeat a guard watches (:func:`calls`)."""
_RAISED = 1.0  # the function raised (any exception, an index out of bounds included)
_NOT_FINITE = 2.0  # it returned a moment that is not finite
_CALL = (
    "f(t, q, omega, params) with t a float, q and omega float arrays of 4 and 3, params a "
    "float array"
)


def is_numba_function(function: Any) -> bool:
    """Whether ``function`` is a numba-compiled function (a ``numba.njit`` dispatcher)."""
    return isinstance(function, numba.core.registry.CPUDispatcher)


@functools.cache
def checked_function(function: Any) -> Any:
    """The numba function ``function`` compiled again from its source with its own options and
    bounds checking (an index out of bounds then raises IndexError instead of reading any
    memory), not cached on disk (its source is the user's file)."""
    options = {k: v for k, v in function.targetoptions.items() if k not in ("nopython", "cache")}
    return numba.njit(**{**options, "boundscheck": True})(function.py_func)


@numba.njit(cache=False)
def _fault(
    code: float, t: float, q0: float, q1: float, q2: float, q3: float, w1: float, w2: float,
    w3: float, out: Any, record: Any,
) -> None:  # fmt: skip
    """A NaN moment, and the first fault in the record (module notes)."""
    out[0] = out[1] = out[2] = math.nan
    r = numba.carray(record, RECORD_SIZE)
    if r[0] == 0.0:
        r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8] = t, q0, q1, q2, q3, w1, w2, w3
        r[0] = code


@functools.cache
def compiled_user_torque(function: Any) -> Any:
    """The C callback of a numba function ``f(t, q, omega, params)`` (module notes), compiled
    once per process and kept alive here, so that its address stays valid.

    Raises
    ------
    UserCodeError
        The function does not compile for the call (its signature, its types).
    """
    checked = checked_function(function)

    @cast(Any, numba.cfunc)(SIGNATURE, boundscheck=True)
    def callback(t, q0, q1, q2, q3, w1, w2, w3, params, n, out, record):  # type: ignore[no-untyped-def]
        numba.carray(record, RECORD_SIZE)[9] += 1.0  # the heartbeat
        try:
            moment = checked(
                t, np.array([q0, q1, q2, q3]), np.array([w1, w2, w3]), numba.carray(params, n)
            )
            m1, m2, m3 = moment[0], moment[1], moment[2]
        except Exception:
            _fault(_RAISED, t, q0, q1, q2, q3, w1, w2, w3, out, record)
            return
        if math.isfinite(m1) and math.isfinite(m2) and math.isfinite(m3):
            out[0], out[1], out[2] = m1, m2, m3
        else:
            _fault(_NOT_FINITE, t, q0, q1, q2, q3, w1, w2, w3, out, record)

    return callback


def _failure(exc: Exception) -> str:
    """An exception as ``Type: message`` (its first line, shortened)."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {shorten(text[0] if text else '')}".rstrip(": ")


def probe(function: Any, name: str, params: Any) -> None:
    """Call the numba function ``function`` (bounds checked) at two states, as the run will:
    the rest attitude at rest, and a turned attitude turning; raise :class:`UserCodeError`
    with one line if it does not compile for the call, raises, or returns anything but 3
    finite numbers."""
    checked = checked_function(function)
    values = np.asarray(params, dtype=float)
    half = math.sqrt(0.5)
    for t, q, w in ((0.0, (1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0)),
                    (1.0, (half, 0.0, half, 0.0), (0.1, -0.2, 0.3))):  # fmt: skip
        where = state_text(t, q, w)
        try:
            value = checked(t, np.array(q), np.array(w), values)
        except (numba.core.errors.TypingError, TypeError) as exc:
            # (numba's first line says only which pass failed: its second says why)
            lines = [ln for ln in str(exc).strip().splitlines() if ln.strip()]
            why = (
                lines[1]
                if isinstance(exc, numba.core.errors.TypingError) and len(lines) > 1
                else (lines[0] if lines else "")
            )
            raise UserCodeError(
                f"{name}: cannot be called as {_CALL} ({type(exc).__name__}: {shorten(why)})"
            ) from None
        except Exception as exc:
            raise UserCodeError(f"{name} raised {_failure(exc)} at {where}") from None
        moment = np.asarray(value, dtype=float) if np.ndim(value) <= 1 else None
        if moment is None or moment.shape != (3,):
            raise UserCodeError(
                f"{name}: a torque function must return the 3 body components of the moment, "
                f"got shape {np.shape(value)} at {where}"
            )
        if not np.all(np.isfinite(moment)):
            raise UserCodeError(f"{name} returned {moment.tolist()} (not finite) at {where}")
    try:
        compiled_user_torque(function)
    except numba.core.errors.NumbaError as exc:
        raise UserCodeError(f"{name}: cannot be called as {_CALL} ({_failure(exc)})") from None


class _Armed(NamedTuple):
    """A fault record and what a message about it needs."""

    record: np.ndarray
    function: Any
    name: str
    params: np.ndarray


_ARMED: dict[tuple[Any, str, tuple[float, ...]], _Armed] = {}


def fault_record(function: Any, name: str, params: Any) -> int:
    """The address of the fault record of the numba function ``function`` named ``name`` with
    the parameters ``params`` (one record for each, kept for the life of the process)."""
    values = tuple(float(v) for v in np.asarray(params, dtype=float).ravel())
    key = (function, name, values)
    armed = _ARMED.get(key)
    if armed is None:
        armed = _Armed(np.zeros(RECORD_SIZE), function, name, np.array(values))
        _ARMED[key] = armed
    return int(armed.record.ctypes.data)


def raise_fault() -> None:
    """Raise :class:`UserCodeError` for the first fault a compiled user torque recorded since
    the last call (and clear it): the function's name, what it did, the time and the state;
    for an exception, the exception itself, reproduced by calling the function's Python source
    at that state."""
    for armed in list(_ARMED.values()):  # (another thread may arm one meanwhile)
        record = armed.record
        if record[0] == 0.0:
            continue
        code, t = record[0], float(record[1])
        q, w = record[2:6].copy(), record[6:9].copy()
        record[:9] = 0.0
        where = state_text(t, q, w)
        if code == _NOT_FINITE:
            value = checked_function(armed.function)(t, q, w, armed.params)
            raise UserCodeError(
                f"{armed.name} returned {np.asarray(value, dtype=float).tolist()} (not finite) "
                f"at {where}"
            )
        try:
            armed.function.py_func(t, q, w, armed.params)
        except Exception as exc:
            raise UserCodeError(f"{armed.name} raised {_failure(exc)} at {where}") from None
        raise UserCodeError(f"{armed.name} raised an exception in compiled code at {where}")


def calls() -> float:
    """How many calls of the compiled user torques have begun, all together (a heartbeat)."""
    return float(sum(armed.record[9] for armed in list(_ARMED.values())))


def armed_names() -> list[str]:
    """The names of the compiled user torques of this process."""
    return sorted({armed.name for armed in list(_ARMED.values())})


def any_armed() -> bool:
    """Whether any compiled user torque has a fault record (a cheap test for the driver)."""
    return bool(_ARMED)


@intrinsic
def _call_user(
    typingctx: Any, address: Any, record: Any, t: Any, q0: Any, q1: Any, q2: Any, q3: Any,
    w1: Any, w2: Any, w3: Any, prog: Any, start: Any, n: Any,
) -> Any:  # fmt: skip
    """``(m1, m2, m3)`` of the callback at integer ``address`` with the parameters
    ``prog[start : start + n]`` (no copy: a pointer into the program) and the fault record at
    integer ``record``."""
    result = types.UniTuple(types.float64, 3)
    sig = result(address, record, t, q0, q1, q2, q3, w1, w2, w3, prog, start, n)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        addr, rec, tt, a0, a1, a2, a3, b1, b2, b3, program, first, count = args
        double = ir.DoubleType()
        pointer = double.as_pointer()
        int64 = ir.IntType(64)
        fnty = ir.FunctionType(ir.VoidType(), [double] * 8 + [pointer, int64, pointer, pointer])
        fn = builder.inttoptr(addr, fnty.as_pointer())
        data = context.make_array(signature.args[10])(context, builder, program).data
        params = builder.gep(data, [first])
        buffer = builder.bitcast(builder.alloca(ir.ArrayType(double, 3)), pointer)
        faults = builder.inttoptr(rec, pointer)
        builder.call(fn, [tt, a0, a1, a2, a3, b1, b2, b3, params, count, buffer, faults])
        values = [builder.load(builder.gep(buffer, [ir.Constant(int64, i)])) for i in range(3)]
        return context.make_tuple(builder, result, values)

    return sig, codegen


call_user = cast(Callable[..., tuple[float, float, float]], _call_user)
"""``call_user(address, record, t, q0, q1, q2, q3, w1, w2, w3, prog, start, n) -> (m1, m2, m3)``
from compiled code (the intrinsic above, typed for the callers)."""
