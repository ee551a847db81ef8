"""Quadratic drag, M = −S (ω ∘ |ω|) component-wise: the third term of the moment (1.2) of
Medvedev (1987)."""

from __future__ import annotations

import math
from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, mat3, mat_vec
from tumble.kernels.terms.base import Term

LAYOUT = Layout(
    "quadratic_drag",
    (Field("S", 9, "moment·time²/rad²", "quadratic damping matrix, body axes, by rows"),),
)
_AT = LAYOUT.at
_CUBE_MEAN = 4.0 / (3.0 * math.pi)  # ⟨|sin φ|³⟩ over a turn


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    m1, m2, m3 = mat_vec(prog, v + _AT.S, w1 * abs(w1), w2 * abs(w2), w3 * abs(w3))
    return -(f * m1), -(f * m2), -(f * m3)


@jit(INLINE)
def spinner(p: FloatArray, v: int, a: float, c: float) -> tuple[float, float]:
    """⟨X⟩ = −a|a| ⟨|sin φ|³⟩ (S11 + S22) across the axis, −S33 c|c| along it."""
    s = mat3(p, v + _AT.S)
    return -(a * abs(a) * _CUBE_MEAN * (s[0] + s[4])), -(s[8] * c * abs(c))


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> None:
    return None  # ω|ω| is not analytic at ω = 0: no Taylor form


TERM = Term(
    name="quadratic_drag",
    doc="quadratic drag, M = −S (ω ∘ |ω|) (Medvedev (1987), eq. (1.2))",
    layout=LAYOUT,
    reads=frozenset({"rate"}),
    moment=moment,
    spinner=spinner,
    peer=peer,
)

TERMS = (TERM,)
