"""The gravity-gradient moment along a Keplerian orbit, M = 3μ/r³ r̂ × (I r̂) in body axes at the
orbit's position at time t."""

from __future__ import annotations

import math

from tumble._typing import FloatArray
from tumble.kernels.frames import to_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Layout, Mat3, Vec3
from tumble.kernels.space import ORBIT, orbit_at
from tumble.kernels.terms.base import ORBIT_FIELD, Term, principal_moments
from tumble.kernels.terms.gravity_gradient import gradient_moment

LAYOUT = Layout(
    "orbit_gravity",
    (
        ORBIT_FIELD,
        principal_moments("kg·m²"),
    ),
)
_AT = LAYOUT.at
_MU = _AT.orbit + ORBIT.at.mu


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    r, _ = orbit_at(prog, v + _AT.orbit, t)
    size2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2]
    r1, r2, r3 = to_body(a, r[0], r[1], r[2])
    mu = prog[v + _MU]
    g = 3.0 * mu * f / (size2 * size2 * math.sqrt(size2))  # 3μ/r³ over r²
    return gradient_moment(g, prog, v + _AT.inertia, r1, r2, r3)


TERM = Term(
    name="orbit_gravity",
    doc="the gravity gradient along a Keplerian orbit, M = 3μ/r³ r̂ × (I r̂)",
    layout=LAYOUT,
    reads=frozenset({"attitude", "time", "orbit"}),
    moment=moment,
)

TERMS = (TERM,)
