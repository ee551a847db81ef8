"""Internal energy dissipation as a viscous damper: M = −c (ω − (2T/|L|²) L), body axes.

The moment of a damper (a fluid ring, a flexible appendage, a Kane sphere) whose contents
turn at the body's mean rate about its angular momentum, (2T/|L|²) L, and drag the body's own
rate towards it with a coefficient c. Its part along L vanishes, L·M = 0, so |L| is kept;
its power is ω·M = −c |ω⊥|² ≤ 0, with ω⊥ the body rate across L, so the kinetic energy T
falls at fixed |L| until ω ∥ L: a rotation about a principal axis, and of those only the
axis of largest inertia is stable. A Kane damper of small inertia whose viscous time is long
against the nutation period follows this law (its sphere settles at the body's mean rate).

Near the major axis (I_max) the mean of |ω⊥|² over the Euler–Poinsot motion is
(T − |L|²/(2 I_max)) (Σ 1/Iᵢ − 3/I_max) (the small oscillation divides the energy evenly
between its two rates), so the energy above major-axis rotation decays as e^(−t/τ) with
c = 1 / (τ (Σ 1/Iᵢ − 3/I_max)): the parameter a user gives is that time constant τ
(:class:`tumble.torques.InternalDissipation`). Far from the major axis the rate is
c ⟨|ω⊥|²⟩ over the polhode (:func:`closed`).

The full equations apply M as a body moment. An internal moment leaves the inertial L
fixed; a body moment across L turns it at c|ω⊥|/|L|, which changes sign with the nutation
and so averages out: L's direction wobbles by about 1/(ν τ) of the nutation angle (ν the
nutation frequency) about a fixed mean (measured in the tests). The averaged equations
carry no such wobble.
"""

from __future__ import annotations

from typing import Any

from tumble._typing import FloatArray
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, vec3
from tumble.kernels.lframe import Context, Parts
from tumble.kernels.terms.base import Term, principal_moments

LAYOUT = Layout(
    "internal_dissipation",
    (
        principal_moments("inertia unit"),
        Field("c", 1, "moment·time/rad", "damping coefficient c", 0.0),
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    i1, i2, i3 = vec3(prog, v + _AT.inertia)
    l1, l2, l3 = i1 * w1, i2 * w2, i3 * w3
    size2 = l1 * l1 + l2 * l2 + l3 * l3
    if size2 == 0.0:
        return 0.0, 0.0, 0.0
    mean = (l1 * w1 + l2 * w2 + l3 * w3) / size2  # 2T/|L|²
    g = -f * prog[v + _AT.c]
    return g * (w1 - mean * l1), g * (w2 - mean * l2), g * (w3 - mean * l3)


@jit(INLINE)
def closed(p: FloatArray, v: int, t: float, ctx: Context) -> Parts:
    """Nothing across or along L; the power −c|L|² Σ ⟨ℓᵢ²⟩ (1/Iᵢ − 2T/|L|²)², where
    2T/|L|² = Σ ⟨ℓᵢ²⟩/Iᵢ is constant on the motion (the variance of 1/I over the weights
    ⟨ℓᵢ²⟩, written as one so that it does not cancel near a pure rotation)."""
    L, inv, sq = ctx[0], ctx[2], ctx[3]
    r = sq[0] * inv[0] + sq[1] * inv[1] + sq[2] * inv[2]
    d1, d2, d3 = inv[0] - r, inv[1] - r, inv[2] - r
    spread = sq[0] * d1 * d1 + sq[1] * d2 * d2 + sq[2] * d3 * d3
    return 0.0, 0.0, 0.0, -p[v + _AT.c] * L * L * spread


def peer(values: dict[str, Any], f: float, t: Any, w: list[Any], frame: Any, hy: Any) -> list[Any]:
    inertia = [float(x) for x in values["inertia"]]
    ell = [inertia[k] * w[k] for k in range(3)]
    mean = sum(ell[k] * w[k] for k in range(3)) / sum(ell[k] * ell[k] for k in range(3))
    g = -f * float(values["c"])
    return [g * (w[k] - mean * ell[k]) for k in range(3)]


TERM = Term(
    name="internal_dissipation",
    doc="internal energy dissipation, a viscous damper at the mean rate about L, "
    "M = −c (ω − (2T/|L|²) L)",
    layout=LAYOUT,
    reads=frozenset({"rate"}),
    moment=moment,
    closed=closed,
    peer=peer,
)

TERMS = (TERM,)
