"""The eddy-current moment on a spherical conductor in a conical rotating field,
M = −M0 [(Ω − ω_f ξ₃)]⊥ĥ in inertial axes (Martynenko (1979), eq. (1.3), with the time
derivative of the field its print drops), ĥ(t) = (sin β cos ω_f t, sin β sin ω_f t, cos β)."""

from __future__ import annotations

import math
from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.frames import to_body, to_inertial
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3
from tumble.kernels.terms.base import Term

LAYOUT = Layout(
    "eddy_current",
    (
        Field("M0", 1, "moment·time/rad", "torque factor k_f H²", 0.0),
        Field("rate", 1, "rad/time", "field rotation rate ω_f about ξ3"),
        Field("beta", 1, "rad", "angle between the field and ξ3", 0.0, math.pi),
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """f·M0 (ĥ(ĥ·x) − x) in body axes, x = A ω − ω_f ξ₃ the angular velocity relative to the
    field."""
    rate, beta = prog[v + _AT.rate], prog[v + _AT.beta]
    sb, cb = math.sin(beta), math.cos(beta)
    h1, h2, h3 = sb * math.cos(rate * t), sb * math.sin(rate * t), cb
    x1, x2, x3 = to_inertial(a, w1, w2, w3)
    x3 = x3 - rate
    hw = h1 * x1 + h2 * x2 + h3 * x3
    m1, m2, m3 = to_body(a, h1 * hw - x1, h2 * hw - x2, h3 * hw - x3)
    g = f * prog[v + _AT.M0]
    return g * m1, g * m2, g * m3


@jit(INLINE)
def phase_mean(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """Over the field's turn (a rotating field; a static one as it is): the moment at
    ⟨ĥ ĥᵀ⟩ = diag(½ sin²β, ½ sin²β, cos²β)."""
    rate = prog[v + _AT.rate]
    if rate == 0.0:
        return moment(f, prog, v, t, w1, w2, w3, a)
    s2 = math.sin(prog[v + _AT.beta]) ** 2  # 1 − ⟨ĥĥᵀ⟩ = diag(1 − ½ s², 1 − ½ s², s²)
    x1, x2, x3 = to_inertial(a, w1, w2, w3)
    x3 = x3 - rate
    g = f * prog[v + _AT.M0]
    return to_body(a, -g * (1.0 - 0.5 * s2) * x1, -g * (1.0 - 0.5 * s2) * x2, -g * s2 * x3)


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    m0, rate, beta = values["M0"], values["rate"], values["beta"]
    h = [math.sin(beta) * hy.cos(rate * t), math.sin(beta) * hy.sin(rate * t), math.cos(beta)]
    x = frame.to_inertial(w)
    x[2] = x[2] - rate
    hw = h[0] * x[0] + h[1] * x[1] + h[2] * x[2]
    return [f * m0 * c for c in frame.to_body([h[k] * hw - x[k] for k in range(3)])]


TERM = Term(
    name="eddy_current",
    doc="eddy currents in a sphere in a rotating field (Martynenko (1979), eq. (1.3))",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time"}),
    moment=moment,
    phase_mean=phase_mean,
    forcing_rate=lambda values: float(values["rate"]),
    peer=peer,
)

TERMS = (TERM,)
