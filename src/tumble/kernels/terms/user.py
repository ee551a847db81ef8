"""A user's torque written as a numba function, called through its C callback
(:mod:`tumble.kernels.user`): the moment ``f(t, q, omega, params)``."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.frames import matrix_quaternion
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3
from tumble.kernels.terms.base import Term
from tumble.kernels.user import call_user

LAYOUT = Layout(
    "user",
    (
        Field("address", 1, "1", "address of the compiled callback"),
        Field("record", 1, "1", "address of its fault record (tumble.kernels.user)"),
        Field("n", 1, "1", "number of parameters", 0.0),
    ),
    tail="params",  # the function's parameters (a scenario's [torque_params] values)
)
_AT = LAYOUT.at
_PARAMS = LAYOUT.size  # the parameters follow the fixed part


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """The callback's moment at the quaternion of a (its sign arbitrary); NaN after a fault of
    the user's function, which its record keeps."""
    q0, q1, q2, q3 = matrix_quaternion(a)
    address, record, n = int(prog[v + _AT.address]), int(prog[v + _AT.record]), int(prog[v + _AT.n])
    m1, m2, m3 = call_user(address, record, t, q0, q1, q2, q3, w1, w2, w3, prog, v + _PARAMS, n)
    return f * m1, f * m2, f * m3


TERM = Term(
    name="user",
    doc="a user's numba function f(t, q, omega, params)",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time"}),
    moment=moment,
    calls_out=True,
    quadrature_only=True,
)

TERMS = (TERM,)
