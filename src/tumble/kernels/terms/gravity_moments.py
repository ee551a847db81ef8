"""The gravity gradient averaged over the orbit, −c ĥ × (I ĥ) in body axes with
c = 3μ/(2a³(1 − e²)^{3/2}) (⟨3μ r̂ r̂ᵀ/r³⟩ = c (1 − ĥ ĥᵀ)) and the orbit normal ĥ turned about
ξ3 by Ω̇ t (:mod:`tumble.space.moments`)."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.frames import to_body, turned_about_z
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts
from tumble.kernels.terms.base import Term
from tumble.kernels.terms.gravity_gradient import gravity_closed

LAYOUT = Layout(
    "gravity_moments",
    (
        Field("inertia", 3, "kg·m²", "principal moments I1, I2, I3", 0.0),
        Field("c", 1, "1/time²", "3μ/(2a³(1 − e²)^{3/2})", 0.0),
        Field("normal", 3, "1", "orbit normal ĥ at t = 0, inertial axes"),
        Field("node_rate", 1, "rad/time", "rate of the node Ω̇"),
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def _normal(prog: FloatArray, v: int, t: float) -> Vec3:
    """ĥ(t): the normal at t = 0 turned about ξ3 by Ω̇ t."""
    return turned_about_z(prog[v + _AT.node_rate] * t, vec3(prog, v + _AT.normal))


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    h1, h2, h3 = _normal(prog, v, t)
    b1, b2, b3 = to_body(a, h1, h2, h3)
    i1, i2, i3 = vec3(prog, v + _AT.inertia)
    g = -f * prog[v + _AT.c]
    return g * (i3 - i2) * b2 * b3, g * (i1 - i3) * b3 * b1, g * (i2 - i1) * b1 * b2


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    h1, h2, h3 = _normal(p, v, t)
    return gravity_closed(p, v + _AT.inertia, p[v + _AT.c], h1, h2, h3, ctx)


TERM = Term(
    name="gravity_moments",
    doc="the gravity gradient averaged over the orbit, −c ĥ × (I ĥ)",
    layout=LAYOUT,
    reads=frozenset({"attitude", "time"}),
    moment=moment,
    closed=closed,
)

TERMS = (TERM,)
