"""The gravity gradient averaged over the orbit, −c ĥ × (I ĥ) in body axes with
c = 3μ/(2a³(1 − e²)^{3/2}) (⟨3μ r̂ r̂ᵀ/r³⟩ = c (1 − ĥ ĥᵀ)) and the orbit normal ĥ turned about
ξ3 by Ω̇ t (:mod:`tumble.space.moments`)."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.frames import node_turned, node_turned_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3
from tumble.kernels.lframe import Context, Parts
from tumble.kernels.terms.base import NODE_RATE, Term, principal_moments
from tumble.kernels.terms.gravity_gradient import gradient_moment, gravity_closed

LAYOUT = Layout(
    "gravity_moments",
    (
        principal_moments("kg·m²"),
        Field("c", 1, "1/time²", "3μ/(2a³(1 − e²)^{3/2})", 0.0),
        Field("normal", 3, "1", "orbit normal ĥ at t = 0, inertial axes"),
        NODE_RATE,
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    """−f c ĥ × (I ĥ) in body axes, ĥ(t) the normal at t = 0 turned about ξ3 by Ω̇ t."""
    b1, b2, b3 = node_turned_body(a, prog, v + _AT.normal, v + _AT.node_rate, t)
    return gradient_moment(-f * prog[v + _AT.c], prog, v + _AT.inertia, b1, b2, b3)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """The Euler–Poinsot average (:func:`gravity_closed`) at the normal ĥ(t)."""
    h1, h2, h3 = node_turned(p, v + _AT.normal, v + _AT.node_rate, t)
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
