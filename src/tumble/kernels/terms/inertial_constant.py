"""A moment fixed in inertial space, M_body = Aᵀ m."""

from __future__ import annotations

from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.frames import to_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts, column_dot
from tumble.kernels.terms.base import Term

LAYOUT = Layout("inertial_constant", (Field("moment", 3, "moment unit", "inertial components m"),))
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    m1, m2, m3 = vec3(prog, v + _AT.moment)
    b1, b2, b3 = to_body(a, m1, m2, m3)
    return f * b1, f * b2, f * b3


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The moment itself, in the L-frame, and the power ⟨Ω⟩·m with ⟨Ω⟩ = L r L̂."""
    L, r, F = ctx[0], ctx[1], ctx[8]
    m1, m2, m3 = vec3(p, v + _AT.moment)
    along = column_dot(F, 2, m1, m2, m3)
    return column_dot(F, 0, m1, m2, m3), column_dot(F, 1, m1, m2, m3), along, L * r * along


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    return [f * c for c in frame.to_body([float(c) for c in values["moment"]])]


TERM = Term(
    name="inertial_constant",
    doc="a moment fixed in inertial space, M = Aᵀ m",
    layout=LAYOUT,
    reads=frozenset({"attitude"}),
    moment=moment,
    closed=closed,
    peer=peer,
)

TERMS = (TERM,)
