"""A user's torque written as a numba function, called from the compiled right-hand sides.

A function ``f(t, q, omega, params) -> body moment`` compiled with ``numba.njit`` is wrapped
once per process in a C callback (:func:`compiled_user_torque`) of one fixed signature,

    void (double t, double q0, q1, q2, q3, double w1, w2, w3,
          const double *params, int64 n, double *moment),

whose address a torque program carries as a number (a user term, ``TERM_USER``: the address,
n, then the n parameters). The compiled code calls it through that address
(:func:`call_user`), so the integrators are compiled, and cached on disk, once for every user
function: only the small callback is compiled for each.

The function receives q and omega as float arrays of 4 and 3, and ``params`` as a float array
of its n parameters (a scenario's ``[torque_params]`` values, in their order); it returns the
body moment as 3 numbers. Where the compiled code knows only the attitude matrix (the general
averaging engine), q is the quaternion of that matrix, up to its sign: such a torque must not
depend on the sign, as any attitude-dependent torque must not.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, cast

import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

__all__ = ["SIGNATURE", "call_user", "compiled_user_torque", "is_numba_function"]

SIGNATURE = types.void(
    types.float64,
    *(types.float64,) * 4,
    *(types.float64,) * 3,
    types.CPointer(types.float64),
    types.int64,
    types.CPointer(types.float64),
)
"""The C signature of the callback: t, q (4), ω (3), the parameters and their number, and the
moment written to a buffer of 3."""


def is_numba_function(function: Any) -> bool:
    """Whether ``function`` is a numba-compiled function (a ``numba.njit`` dispatcher)."""
    return isinstance(function, numba.core.registry.CPUDispatcher)


@functools.cache
def compiled_user_torque(function: Any) -> Any:
    """The C callback of a numba function ``f(t, q, omega, params)`` (module notes), compiled
    once per process and kept alive here, so that its address stays valid."""

    @numba.cfunc(SIGNATURE)
    def callback(t, q0, q1, q2, q3, w1, w2, w3, params, n, out):  # type: ignore[no-untyped-def]
        moment = function(
            t, np.array([q0, q1, q2, q3]), np.array([w1, w2, w3]), numba.carray(params, n)
        )
        out[0], out[1], out[2] = moment[0], moment[1], moment[2]

    return callback


@intrinsic
def _call_user(
    typingctx: Any, address: Any, t: Any, q0: Any, q1: Any, q2: Any, q3: Any, w1: Any,
    w2: Any, w3: Any, prog: Any, start: Any, n: Any,
) -> Any:  # fmt: skip
    """``(m1, m2, m3)`` of the callback at integer ``address`` with the parameters
    ``prog[start : start + n]`` (no copy: a pointer into the program)."""
    result = types.UniTuple(types.float64, 3)
    sig = result(address, t, q0, q1, q2, q3, w1, w2, w3, prog, start, n)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        addr, tt, a0, a1, a2, a3, b1, b2, b3, program, first, count = args
        double = ir.DoubleType()
        pointer = double.as_pointer()
        int64 = ir.IntType(64)
        fnty = ir.FunctionType(ir.VoidType(), [double] * 8 + [pointer, int64, pointer])
        fn = builder.inttoptr(addr, fnty.as_pointer())
        data = context.make_array(signature.args[9])(context, builder, program).data
        params = builder.gep(data, [first])
        buffer = builder.bitcast(builder.alloca(ir.ArrayType(double, 3)), pointer)
        builder.call(fn, [tt, a0, a1, a2, a3, b1, b2, b3, params, count, buffer])
        values = [builder.load(builder.gep(buffer, [ir.Constant(int64, i)])) for i in range(3)]
        return context.make_tuple(builder, result, values)

    return sig, codegen


call_user = cast(Callable[..., tuple[float, float, float]], _call_user)
"""``call_user(address, t, q0, q1, q2, q3, w1, w2, w3, prog, start, n) -> (m1, m2, m3)`` from
compiled code (the intrinsic above, typed for the callers)."""
