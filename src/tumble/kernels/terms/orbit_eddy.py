"""The eddy-current moment of a conductor moving along an orbit through the tilted dipole field
of the Earth: the induced dipole M x of the magnetic tensor M, x = −dB/dt seen in the body =
ω × B − Aᵀ dB/dt, and the moment (M x) × B in body axes (:mod:`tumble.space.torques`)."""

from __future__ import annotations

from tumble._typing import FloatArray
from tumble.kernels.frames import scaled_cross, to_body
from tumble.kernels.jit import INLINE, jit
from tumble.kernels.layout import Field, Layout, Mat3, Vec3, mat_vec
from tumble.kernels.space import DIPOLE, field_at
from tumble.kernels.terms.base import MAGNETIC_TENSOR, ORBIT_FIELD, Term

LAYOUT = Layout(
    "orbit_eddy",
    (
        ORBIT_FIELD,
        Field("field", DIPOLE.size, doc="the tilted dipole (kernels.space.DIPOLE)"),
        MAGNETIC_TENSOR,
    ),
)
_AT = LAYOUT.at


@jit(INLINE)
def eddy_moment(
    f: float, prog: FloatArray, vm: int, bi: Vec3, ci: Vec3, w1: float, w2: float, w3: float,
    a: Mat3,
) -> Vec3:  # fmt: skip
    """f·(M x) × b for the inertial field bi and its rate ci, x = ω × b − Aᵀ ci (body axes),
    M by rows at prog[vm : vm + 9]."""
    b1, b2, b3 = to_body(a, bi[0], bi[1], bi[2])
    c1, c2, c3 = to_body(a, ci[0], ci[1], ci[2])
    x1, x2, x3 = w2 * b3 - w3 * b2 - c1, w3 * b1 - w1 * b3 - c2, w1 * b2 - w2 * b1 - c3
    return scaled_cross(f, mat_vec(prog, vm, x1, x2, x3), b1, b2, b3)


@jit(INLINE)
def moment(
    f: float, prog: FloatArray, v: int, t: float, w1: float, w2: float, w3: float, a: Mat3
) -> Vec3:
    bi, ci = field_at(prog, v + _AT.orbit, prog, v + _AT.field, t)
    return eddy_moment(f, prog, v + _AT.tensor, bi, ci, w1, w2, w3, a)


TERM = Term(
    name="orbit_eddy",
    doc="eddy currents along an orbit in the tilted dipole field, M = (M x) × B",
    layout=LAYOUT,
    reads=frozenset({"rate", "attitude", "time", "orbit", "field"}),
    moment=moment,
)

TERMS = (TERM,)
