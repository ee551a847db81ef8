"""A moment constant in body axes, M = m: the first term of the moment (1.2) of Medvedev (1987)."""

from __future__ import annotations

from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts, sorted_vector
from tumble.kernels.terms.base import Term

LAYOUT = Layout("body_constant", (Field("moment", 3, "moment unit", "body components m"),))
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    m1, m2, m3 = vec3(prog, v + _AT.moment)
    return f * m1, f * m2, f * m3


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """⟨ℓ·m⟩ = ⟨ℓ_a⟩ m_a along L (a the encircled axis) and the power L ⟨ℓ_a⟩ m_a / I_a."""
    L, inv, first, a = ctx[0], ctx[2], ctx[6], ctx[7]
    m1, m2, m3 = vec3(p, v + _AT.moment)
    b = sorted_vector(p, m1, m2, m3)
    return 0.0, 0.0, b[a] * first, L * b[a] * first * inv[a]


@jit(INLINE)
def spinner(p: FloatArray, v: int, a: float, c: float) -> tuple[float, float]:
    """Over the spin angle only the axial component survives."""
    return 0.0, p[v + _AT.moment + 2]


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    return [f * float(c) for c in values["moment"]]


TERM = Term(
    name="body_constant",
    doc="a moment constant in body axes, M = m (Medvedev (1987), eq. (1.2))",
    layout=LAYOUT,
    reads=frozenset(),
    moment=moment,
    closed=closed,
    spinner=spinner,
    peer=peer,
)

TERMS = (TERM,)
