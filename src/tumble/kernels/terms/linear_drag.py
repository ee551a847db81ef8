"""Linear drag of a resisting medium, M = −B ω: the second term of the moment (1.2) of
Medvedev (1987)."""

from __future__ import annotations

from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, mat3, mat_vec
from tumble.kernels.lframe import Context, Parts, sorted_diagonal, weighted
from tumble.kernels.terms.base import Term

LAYOUT = Layout(
    "linear_drag", (Field("B", 9, "moment·time/rad", "damping matrix, body axes, by rows"),)
)
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    m1, m2, m3 = mat_vec(prog, v + _AT.B, w1, w2, w3)
    return -(f * m1), -(f * m2), -(f * m3)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """−⟨ℓᵀBω⟩ along L and the power −⟨ωᵀBω⟩: only B's diagonal survives."""
    L, inv, sq = ctx[0], ctx[2], ctx[3]
    d, _ = sorted_diagonal(p, p, v + _AT.B)
    inv2 = (inv[0] * inv[0], inv[1] * inv[1], inv[2] * inv[2])
    return 0.0, 0.0, -L * weighted(d, sq, inv), -L * L * weighted(d, sq, inv2)


@jit(INLINE)
def spinner(p: FloatArray, v: int, a: float, c: float) -> tuple[float, float]:
    """⟨X⟩ = −a (B11 + B22)/2 across the axis, −B33 c along it."""
    b = mat3(p, v + _AT.B)
    return -(a * 0.5 * (b[0] + b[4])), -(b[8] * c)


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    B = values["B"]
    return [-f * sum(float(B[r, k]) * w[k] for k in range(3)) for r in range(3)]


TERM = Term(
    name="linear_drag",
    doc="linear drag, M = −B ω (Medvedev (1987), eq. (1.2))",
    layout=LAYOUT,
    reads=frozenset({"rate"}),
    moment=moment,
    closed=closed,
    spinner=spinner,
    peer=peer,
)

TERMS = (TERM,)
